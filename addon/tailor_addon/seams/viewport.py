"""Viewport side of the interactive tools: the piece and rest point under the mouse, contour
positions in world space, and drawing highlights with the `gpu` module.

`pick(context, mouse)` ray-casts from the mouse (`view3d_utils.region_2d_to_origin_3d` /
`region_2d_to_vector_3d`, `Scene.ray_cast`) onto piece objects and carries the hit to the
piece's rest frame (`core.picking.hit_to_rest`); a miss falls back to the contour vertex
nearest the mouse on screen within `PICK_RADIUS` pixels, since artists click on the border.
The maths is in `core.picking` (bpy-free, tested without Blender).
"""

from __future__ import annotations

import bpy
import numpy as np

from .. import scene_data
from ..core import mesh_of
from ..core.picking import hit_to_rest, nearest_on_screen, project_points

PICK_RADIUS = 24.0  # pixels
COLOURS = {"picked": (1.0, 0.55, 0.0, 1.0), "preview": (0.2, 0.9, 1.0, 1.0), "axis": (1.0, 0.2, 0.3, 1.0)}


def mesh_for(name: str):
    """The `tailor.PieceMesh` of piece object `name` (memoised triangulation)."""
    p = bpy.data.objects[name].tailor_piece
    return mesh_of(p)


def locate(name: str, position: int) -> np.ndarray:
    """World position of contour position `position` of piece `name`."""
    obj = bpy.data.objects[name]
    v = int(mesh_for(name).contour[position])
    return np.asarray(obj.matrix_world @ obj.data.vertices[v].co, np.float64)


def contour_world(name: str, positions) -> np.ndarray:
    obj = bpy.data.objects[name]
    verts = np.asarray(mesh_for(name).contour, np.int64)[np.asarray(positions, np.int64)]
    return scene_data.vertex_positions(obj)[verts]


def window_region(context):
    """(area, WINDOW region, RegionView3D) of the 3D view the tool was started in (from the
    sidebar, `context.region` is the sidebar's region), or None outside a 3D view."""
    area = context.area
    if area is None or area.type != "VIEW_3D":
        return None
    region = next((r for r in area.regions if r.type == "WINDOW"), None)
    rv3d = area.spaces.active.region_3d
    return None if region is None or rv3d is None else (area, region, rv3d)


def region_mouse(view, event) -> tuple[float, float]:
    """The event's mouse position in the view's WINDOW region (pixels)."""
    region = view[1]
    return (event.mouse_x - region.x, event.mouse_y - region.y)


def _ray(view, mouse):
    from bpy_extras import view3d_utils

    _area, region, rv3d = view
    origin = view3d_utils.region_2d_to_origin_3d(region, rv3d, mouse)
    direction = view3d_utils.region_2d_to_vector_3d(region, rv3d, mouse)
    return origin, direction


def _pieces(context, only=None) -> list:
    objs = [o for o in context.visible_objects if scene_data.is_piece(o)]
    return [o for o in objs if only is None or o.name in only]


def pick(context, view, mouse, only=None) -> tuple[str | None, np.ndarray | None]:
    """(piece object name, rest-frame point) under pixel `mouse` of `view` (`window_region`),
    or (None, None). `only`: names of the pieces that may be picked (the bend tool's piece)."""
    origin, direction = _ray(view, mouse)
    piece, point = pick_ray(context, origin, direction, only)
    if piece is not None:
        return piece, point
    return _nearest_contour_vertex(context, view, mouse, only)


def pick_ray(context, origin, direction, only=None) -> tuple[str | None, np.ndarray | None]:
    """(piece object name, rest-frame point) of the first piece a world-space ray hits, or
    (None, None); the region-free half of `pick`."""
    from mathutils import Vector

    depsgraph = context.evaluated_depsgraph_get()
    hit, location, _normal, face, obj, _matrix = context.scene.ray_cast(depsgraph, Vector(origin), Vector(direction))
    if not (hit and scene_data.is_piece(obj) and (only is None or obj.name in only)):
        return None, None
    obj = bpy.data.objects[obj.name]  # the original, not the evaluated copy
    mesh = mesh_for(obj.name)
    if len(obj.data.vertices) != len(mesh.rest) or face >= len(mesh.triangles):
        return None, None  # a modifier or a hand edit changed the faces: no barycentric mapping
    local = np.asarray(obj.matrix_world.inverted() @ location, np.float64)
    co = scene_data.vertex_positions(obj, world=False)
    return obj.name, hit_to_rest(local, co, mesh.triangles, mesh.rest, face)


def _nearest_contour_vertex(context, view, mouse, only) -> tuple[str | None, np.ndarray | None]:
    _area, region, rv3d = view
    persp = np.array(rv3d.perspective_matrix, np.float64)
    best = (None, None, np.inf)
    for obj in _pieces(context, only):
        mesh = mesh_for(obj.name)
        if len(obj.data.vertices) != len(mesh.rest):
            continue
        contour = np.asarray(mesh.contour, np.int64)
        xy, front = project_points(scene_data.vertex_positions(obj)[contour], persp, region.width, region.height)
        i = nearest_on_screen(xy, front, mouse, PICK_RADIUS)
        if i is not None:
            d = float(np.hypot(*(xy[i] - np.asarray(mouse, np.float64))))
            if d < best[2]:
                best = (obj.name, np.asarray(mesh.rest[contour[i]], np.float64), d)
    return best[0], best[1]


def highlight_batches(highlight) -> list[tuple[str, str, np.ndarray]]:
    """(kind 'LINES'/'POINTS', role, world float32 coordinates) for a `core.seam_tools.Highlight`."""
    out = []
    for piece, positions, role in highlight.paths:
        if piece not in bpy.data.objects or len(positions) < 2:
            continue
        run = contour_world(piece, positions)
        out.append(("LINES", role, np.stack([run[:-1], run[1:]], axis=1).reshape(-1, 3).astype(np.float32)))
    for piece, position, role in highlight.points:
        if piece in bpy.data.objects:
            out.append(("POINTS", role, contour_world(piece, [position]).astype(np.float32)))
    return out


def draw_batches(batches, line_width: float = 4.0, point_size: float = 12.0) -> None:
    """Draws `highlight_batches` output on top of the scene (POST_VIEW handler)."""
    import gpu
    from gpu_extras.batch import batch_for_shader

    from ..compat import point_shader, polyline_shader

    region = bpy.context.region
    if region is None or not batches:
        return
    gpu.state.blend_set("ALPHA")
    gpu.state.depth_test_set("NONE")
    lines = polyline_shader()
    lines.bind()
    lines.uniform_float("viewportSize", (region.width, region.height))
    lines.uniform_float("lineWidth", line_width)
    for kind, role, co in batches:
        if kind == "LINES":
            lines.uniform_float("color", COLOURS[role])
            batch_for_shader(lines, "LINES", {"pos": co}).draw(lines)
    points = point_shader()
    gpu.state.point_size_set(point_size)
    for kind, role, co in batches:
        if kind == "POINTS":
            colours = np.tile(np.asarray(COLOURS[role], np.float32), (len(co), 1))
            batch_for_shader(points, "POINTS", {"pos": co, "color": colours}).draw(points)
    gpu.state.point_size_set(1.0)
    gpu.state.blend_set("NONE")


def set_header(context, view, text: str | None) -> None:
    """Shows what the next click does in the 3D view's header and the status bar (None clears)."""
    view[0].header_text_set(text)
    if context.workspace is not None:
        context.workspace.status_text_set(text)

