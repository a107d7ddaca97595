"""The collision-level overlay: every vertex of a mesh with levels drawn as a dot coloured by
its level (weight maps need none: Blender's weight paint shows them).

`level_points(obj)` is testable headless; the draw handler is not installed in background mode.
"""

from __future__ import annotations

import bpy
import numpy as np

from ..view_draw import ViewDrawHandler

from .. import scene_data
from . import maps

LEVEL_COLOURS = np.array(
    [
        (0.60, 0.60, 0.60, 1.0),
        (0.95, 0.35, 0.10, 1.0),
        (0.15, 0.60, 0.95, 1.0),
        (0.30, 0.80, 0.25, 1.0),
        (0.90, 0.20, 0.60, 1.0),
        (0.95, 0.80, 0.10, 1.0),
    ],
    np.float32,
)



def level_points(obj) -> tuple[np.ndarray, np.ndarray] | None:
    """(world positions (n, 3), RGBA colours (n, 4)) of `obj`'s vertices by collision level."""
    levels = maps.collision_levels(obj)
    if levels is None:
        return None
    colours = LEVEL_COLOURS[np.mod(levels, len(LEVEL_COLOURS))]
    return scene_data.vertex_positions(obj), colours


def _draw() -> None:
    import gpu
    from gpu_extras.batch import batch_for_shader

    from ..compat import point_shader

    context = bpy.context
    if not context.scene.tailor.show_collision_levels:
        return
    shader = None
    for obj in context.visible_objects:
        if obj.type != "MESH" or obj.mode == "EDIT":
            continue
        got = level_points(obj)
        if got is None:
            continue
        shader = shader or point_shader()
        gpu.state.point_size_set(6.0)
        gpu.state.depth_test_set("LESS_EQUAL")
        batch = batch_for_shader(shader, "POINTS", {"pos": got[0], "color": got[1]})
        shader.bind()
        batch.draw(shader)
    if shader is not None:
        gpu.state.depth_test_set("NONE")
        gpu.state.point_size_set(1.0)


_HANDLER = ViewDrawHandler(_draw)


def register() -> None:
    _HANDLER.register()


def unregister() -> None:
    _HANDLER.unregister()
