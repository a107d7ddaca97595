"""The Fit Map overlay (issue 28): each piece's fit-map colours (the colour attribute
`tailor_fit_map` that Live and a bake's playback write, `fit_map_attrs.py`) drawn over it in
the 3D view, in any shading mode, so the map shows without switching the viewport to Attribute
shading. Drawn from the evaluated mesh (a baked piece plays through its Mesh Cache modifier),
offset a fraction of a millimetre to each side along the vertex normals so that neither the
solid shading nor the other side of the cloth hides it.

`fit_map_triangles(obj, depsgraph)` is testable headless; the draw handler is not installed in
background mode.
"""

from __future__ import annotations

import bpy
import numpy as np

from .. import scene_data
from ..core import fit_maps
from ..view_draw import ViewDrawHandler

#: Metres the overlay sits off the surface, on each side.
OFFSET = 4e-4

#: What the last redraw drew (read by the real-window test).
LAST = {"objects": 0, "triangles": 0}


def fit_map_triangles(obj, depsgraph=None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
    """(world positions (n, 3), unit world vertex normals (n, 3), RGBA colours (n, 4), triangles
    (m, 3)) of `obj`'s evaluated mesh (its own mesh without `depsgraph`) coloured by its fit-map
    colour attribute; None where it has none (a mesh that no fit map was written onto)."""
    if obj.type != "MESH":
        return None
    src = obj.evaluated_get(depsgraph) if depsgraph is not None else obj
    me = src.to_mesh()
    try:
        col = me.color_attributes.get(fit_maps.COLOUR_ATTRIBUTE)
        n = len(me.vertices)
        if col is None or col.domain != "POINT" or n == 0:
            return None
        rgba = np.empty(n * 4, np.float32)
        col.data.foreach_get("color", rgba)
        co = np.empty(n * 3, np.float32)
        me.vertices.foreach_get("co", co)
        normals = np.empty(n * 3, np.float32)
        if hasattr(me, "vertex_normals"):  # 3.5+
            me.vertex_normals.foreach_get("vector", normals)
        else:
            me.vertices.foreach_get("normal", normals)
        me.calc_loop_triangles()
        tris = np.empty(len(me.loop_triangles) * 3, np.int32)
        me.loop_triangles.foreach_get("vertices", tris)
    finally:
        src.to_mesh_clear()
    m = np.array(obj.matrix_world, np.float32)
    pos = co.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]
    nrm = normals.reshape(-1, 3) @ np.linalg.inv(m[:3, :3])  # normals transform by the inverse transpose
    length = np.linalg.norm(nrm, axis=1, keepdims=True)
    nrm = np.divide(nrm, length, out=np.zeros_like(nrm), where=length > 0)
    return pos, nrm, rgba.reshape(-1, 4), tris.reshape(-1, 3)


def _draw() -> None:
    import gpu
    from gpu_extras.batch import batch_for_shader

    from ..compat import smooth_colour_shader

    context = bpy.context
    s = context.scene.tailor_simulate
    LAST.update(objects=0, triangles=0)
    if s.fit_map == "NONE" or not s.show_fit_map_overlay:
        return
    depsgraph = context.evaluated_depsgraph_get()
    shader = None
    for obj in context.visible_objects:
        if obj.type != "MESH" or obj.mode == "EDIT" or not scene_data.is_piece(obj):
            continue
        got = fit_map_triangles(obj, depsgraph)
        if got is None:
            continue
        pos, nrm, rgba, tris = got
        shader = shader or smooth_colour_shader()
        gpu.state.depth_test_set("LESS_EQUAL")
        for side in (1.0, -1.0):
            batch = batch_for_shader(shader, "TRIS", {"pos": pos + side * OFFSET * nrm, "color": rgba}, indices=tris)
            shader.bind()
            batch.draw(shader)
        LAST["objects"] += 1
        LAST["triangles"] += len(tris)
    if shader is not None:
        gpu.state.depth_test_set("NONE")


_HANDLER = ViewDrawHandler(_draw)


def register() -> None:
    _HANDLER.register()


def unregister() -> None:
    _HANDLER.unregister()
