"""Between the .blend and the module: read pieces and seams out of a scene, write meshes in.

`build_garment(scene)` is the entry point the other parts of the add-on use (Simulate,
export): it returns a `core.SceneGarment` whose `build_simulation()` gives a
`tailor.Simulation` of the pieces as they stand in the scene. Meshes are copied once each
way with `foreach_get`/`foreach_set` into float32/int32 numpy arrays.
"""

from __future__ import annotations

import math

import bpy
import numpy as np
from mathutils import Vector

import tailor

from . import core
from .core.garment import PieceData, SeamData, SeamSide
from .core.mesh_arrays import CONTOUR_ATTR, CORNER_ATTR, REST_ATTR, REST_UV, MeshArrays

DIRECTIONS = {"CCW": "ccw", "CW": "cw"}
MODES = {"EQUAL": "equal", "UNEQUAL": "unequal"}
MODE_ENUM = {v: k for k, v in MODES.items()}


def is_piece(obj) -> bool:
    return obj is not None and obj.type == "MESH" and obj.tailor_piece.is_piece


def piece_objects(scene, garment: str | None = None) -> list:
    """The scene's piece objects, by name (the garment's piece order), optionally one garment's."""
    objs = [o for o in scene.objects if is_piece(o) and (garment is None or o.tailor_piece.garment == garment)]
    return sorted(objs, key=lambda o: o.name)


# ---- meshes -------------------------------------------------------------------------------


def vertex_positions(obj, world: bool = True) -> np.ndarray:
    """(n, 3) float32 positions of the object's own (unevaluated) mesh, world or local."""
    me = obj.data
    co = np.empty(len(me.vertices) * 3, np.float32)
    me.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    if world:
        m = np.array(obj.matrix_world, np.float32)
        co = co @ m[:3, :3].T + m[:3, 3]
    return co


def point_attribute(me, name: str, dtype, width: int = 1) -> np.ndarray | None:
    attr = me.attributes.get(name)
    if attr is None or attr.domain != "POINT":
        return None
    out = np.empty(len(me.vertices) * width, dtype)
    key = "vector" if attr.data_type == "FLOAT2" else "value"
    attr.data.foreach_get(key, out)
    return out.reshape(-1, width) if width > 1 else out


def rest_of(obj) -> np.ndarray | None:
    return point_attribute(obj.data, REST_ATTR, np.float32, 2)


def rest_point(obj, world_point) -> tuple[float, float] | None:
    """The rest-frame (2D, metres) point of piece `obj` under a world-space point (the surface
    point nearest it, through Blender's own BVH and barycentric transform), or None when the
    mesh has no faces. Picking tools turn a ray-cast hit into the input of
    `tailor.nearest_contour_position` and friends with it; it follows bends and transforms."""
    from mathutils.geometry import barycentric_transform

    inv = obj.matrix_world.inverted()
    local = inv @ Vector(world_point)
    hit, loc, _normal, face = obj.closest_point_on_mesh(local)
    if not hit or face < 0:
        return None
    rest = rest_of(obj)
    if rest is None:
        return None
    me = obj.data
    verts = me.polygons[face].vertices
    a, b, c = (me.vertices[i].co for i in verts[:3])
    ra, rb, rc = (Vector((rest[i][0], rest[i][1], 0.0)) for i in verts[:3])
    p = barycentric_transform(loc, a, b, c, ra, rb, rc)
    return float(p.x), float(p.y)


def write_mesh(me, arrays: MeshArrays) -> None:
    """Replaces `me`'s geometry with a piece mesh and its Tailor attributes, in place (the
    object, its name, transform, modifiers and materials stay)."""
    me.clear_geometry()
    n, m = len(arrays.co), len(arrays.triangles)
    me.vertices.add(n)
    me.vertices.foreach_set("co", arrays.co.reshape(-1))
    me.loops.add(3 * m)
    me.loops.foreach_set("vertex_index", arrays.triangles.reshape(-1))
    me.polygons.add(m)
    me.polygons.foreach_set("loop_start", np.arange(0, 3 * m, 3, dtype=np.int32))
    if bpy.app.version < (4, 0, 0):
        me.polygons.foreach_set("loop_total", np.full(m, 3, np.int32))
    me.update(calc_edges=True)
    for name, dtype in ((REST_ATTR, "FLOAT2"), (CONTOUR_ATTR, "INT"), (CORNER_ATTR, "BOOLEAN")):
        old = me.attributes.get(name)
        if old is not None:
            me.attributes.remove(old)
        me.attributes.new(name, dtype, "POINT")
    me.attributes[REST_ATTR].data.foreach_set("vector", arrays.rest.reshape(-1))
    me.attributes[CONTOUR_ATTR].data.foreach_set("value", arrays.contour)
    me.attributes[CORNER_ATTR].data.foreach_set("value", arrays.corner)
    uv = me.uv_layers.get(REST_UV) or me.uv_layers.new(name=REST_UV)
    uv.data.foreach_set("uv", arrays.uv.reshape(-1))
    me.update()


def new_piece_object(coll, name: str, arrays: MeshArrays, *, piece_json: str, source_path: str, source_index: int,
                     edge_length: float, mesher: int, contour_length: float):
    """A new piece object in collection `coll`, as every importer makes one: named after the
    piece, its mesh written from `arrays`, its `tailor_piece` settings saying where it came
    from and how it is meshed (so Set Resolution and the seams find it), the garment being
    the collection's name."""
    me = bpy.data.meshes.new(name)
    write_mesh(me, arrays)
    obj = bpy.data.objects.new(name, me)
    coll.objects.link(obj)
    p = obj.tailor_piece
    p.is_piece = True
    p.piece_name = name
    p.garment = coll.name
    p.source_path = source_path
    p.source_index = source_index
    p.piece_json = piece_json
    p.edge_length = edge_length
    p.mesher = mesher
    p.contour_length = contour_length
    return obj


# ---- pieces and seams ---------------------------------------------------------------------


def read_piece(obj) -> PieceData:
    p = obj.tailor_piece
    return PieceData(
        name=p.piece_name or obj.name,
        piece_json=p.piece_json,
        edge_length=p.edge_length,
        mesher=p.mesher,
        positions=vertex_positions(obj),
        rest=rest_of(obj),
    )


def side_data(obj, start, end, direction: str, index: dict) -> SeamSide:
    return SeamSide(index[obj.name], tuple(start), tuple(end), DIRECTIONS[direction])


def read_seam(item, index: dict) -> SeamData | None:
    """A stored seam as `SeamData` over the pieces in `index` (object name -> piece index),
    or None if one of its pieces is not among them."""
    if not (is_piece(item.piece_a) and is_piece(item.piece_b)):
        return None
    if item.piece_a.name not in index or item.piece_b.name not in index:
        return None
    return SeamData(
        name=item.name,
        a=side_data(item.piece_a, item.a_start, item.a_end, item.a_direction, index),
        b=side_data(item.piece_b, item.b_start, item.b_end, item.b_direction, index),
        mode=MODES[item.mode],
        stiffness=item.stiffness,
        bend_stiffness=item.bend_stiffness,
    )


def write_seam(item, seam: SeamData, objects: list) -> None:
    """Stores `seam` (sides indexing `objects`) in a scene seam item."""
    inv_dir = {v: k for k, v in DIRECTIONS.items()}
    item.name = seam.name
    item.piece_a = objects[seam.a.piece]
    item.a_start, item.a_end, item.a_direction = seam.a.start, seam.a.end, inv_dir[seam.a.direction]
    item.piece_b = objects[seam.b.piece]
    item.b_start, item.b_end, item.b_direction = seam.b.start, seam.b.end, inv_dir[seam.b.direction]
    item.mode = MODE_ENUM[seam.mode]
    item.stiffness = seam.stiffness
    item.bend_stiffness = seam.bend_stiffness


def broken_seams(scene) -> list[str]:
    """Names of stored seams whose piece objects were deleted or are no longer pieces."""
    return [s.name for s in scene.tailor.seams if not (is_piece(s.piece_a) and is_piece(s.piece_b))]


def build_garment(scene, garment: str | None = None) -> core.SceneGarment:
    """The scene's garment (all pieces, or those of `garment`) and the seams between them,
    resolved on the current meshes. Raises `AddonError`/`tailor.TailorError` (report them
    with `reporting.report`)."""
    objects = piece_objects(scene, garment)
    index = {o.name: i for i, o in enumerate(objects)}
    seams = [s for s in (read_seam(item, index) for item in scene.tailor.seams) if s is not None]
    g = core.garment_from_scene([read_piece(o) for o in objects], seams)
    g.warnings.extend(f"seam '{n}' lost a piece and is ignored" for n in broken_seams(scene))
    return g


def placement_of(obj) -> dict:
    """The object's transform as the module's placement (intrinsic XYZ degrees = Blender's
    'ZYX' Euler). Raises for a scaled object: a placement is rigid."""
    loc, rot, scale = obj.matrix_world.decompose()
    if any(abs(c - 1.0) > 1e-4 for c in scale):
        raise core.AddonError(
            f"piece '{obj.name}' is scaled ({tuple(round(c, 4) for c in scale)}); a garment piece keeps its "
            "pattern's size",
            "Apply or clear its scale (Ctrl+A > Scale resets the rest shape: prefer Alt+S)",
        )
    euler = rot.to_matrix().to_euler("ZYX")
    flipped = False
    own = tailor.Piece.from_json(obj.tailor_piece.piece_json).placement
    if own is not None:
        flipped = bool(own["flipped"])
    return {
        "translation": list(loc),
        "rotation_deg": [math.degrees(a) for a in euler],
        "flipped": flipped,
    }


def bend_of(obj) -> dict | None:
    """The piece's stored bend with its axis in world space (the module bends after placing)."""
    p = obj.tailor_piece
    if p.bend_angle == 0.0:
        return None
    m = obj.matrix_world
    return {
        "axis_point": list(m @ Vector(p.bend_axis_point)),
        "axis_direction": list(m.to_3x3() @ Vector(p.bend_axis_direction)),
        "angle_deg": math.degrees(p.bend_angle),
        "symmetry": (tuple(p.bend_symmetry_point), tuple(p.bend_symmetry_direction)) if p.bend_symmetry else None,
        "threshold": p.bend_threshold,
        "mode": bend_mode(p),
        "radius": p.bend_radius if p.bend_radius > 0.0 else None,
        "taper_deg": math.degrees(p.bend_taper),
    }


def stored_bend_kwargs(p) -> dict:
    """`tailor.bend`'s keyword arguments for a piece's stored bend (after its positional ones)."""
    return {
        "symmetry": (tuple(p.bend_symmetry_point), tuple(p.bend_symmetry_direction)) if p.bend_symmetry else None,
        "threshold": p.bend_threshold,
        "radius": p.bend_radius if p.bend_radius > 0.0 else None,
        "taper_deg": math.degrees(p.bend_taper),
        "mode": bend_mode(p),
    }


def bend_mode(p) -> str:
    """`tailor.bend`'s `mode` of a piece's stored bend (`TailorPieceSettings.bend_rolled`)."""
    return "roll" if p.bend_rolled else "rotate"


def garment_file(scene, garment: str | None = None):
    """The scene's garment as a `tailor.Garment` (pieces, resolutions, placements from the
    objects' transforms, bends, seams, and the pieces as they stand, hand edits included), to
    `save()` as a garment file that the module alone simulates as the add-on does (`python -m
    tailor simulate`): the same garment `build_garment(...).tailor_garment()` gives, plus the
    placements and bends."""
    objects = piece_objects(scene, garment)
    if not objects:
        raise core.AddonError("the scene has no garment pieces", "Import a pattern first")
    return build_garment(scene, garment).tailor_garment(
        placements=[placement_of(o) for o in objects], bends=[bend_of(o) for o in objects])
