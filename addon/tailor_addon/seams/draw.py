"""Seams drawn in the viewport: each side's contour run, and lines joining the paired points.

`seam_lines(scene)` computes the coloured line segments (world space) and is testable
headless; the draw handler (not installed in background mode) only uploads and draws them.
Resolving a seam costs a triangulation (memoised) and a `Seam.resolve`, so resolutions are
cached by everything they depend on; the positions are re-read every redraw (cheap
`foreach_get`), so moved or bent pieces are drawn where they are.
"""

from __future__ import annotations

import bpy
import numpy as np

from ..view_draw import ViewDrawHandler

from .. import scene_data
from ..core import mesh_of
from ..core.garment import SeamData, SeamSide, resolve

_cache: dict = {}
_CACHE_MAX = 256


def _key(item) -> tuple:
    a, b = item.piece_a, item.piece_b
    return (
        a.tailor_piece.piece_json,
        a.tailor_piece.edge_length,
        a.tailor_piece.mesher,
        b.tailor_piece.piece_json,
        b.tailor_piece.edge_length,
        b.tailor_piece.mesher,
        a == b,
        tuple(item.a_start),
        tuple(item.a_end),
        item.a_direction,
        tuple(item.b_start),
        tuple(item.b_end),
        item.b_direction,
        item.mode,
    )


def _resolved(item) -> dict | None:
    key = _key(item)
    if key in _cache:
        return _cache[key]
    same = item.piece_a == item.piece_b
    a, b = item.piece_a.tailor_piece, item.piece_b.tailor_piece
    meshes = [mesh_of(a)]
    if not same:
        meshes.append(mesh_of(b))
    seam = SeamData(
        item.name,
        SeamSide(0, tuple(item.a_start), tuple(item.a_end), scene_data.DIRECTIONS[item.a_direction]),
        SeamSide(0 if same else 1, tuple(item.b_start), tuple(item.b_end), scene_data.DIRECTIONS[item.b_direction]),
        scene_data.MODES[item.mode],
    )
    try:
        r = resolve(seam, meshes)
    except (ValueError, OSError):  # tailor.SeamError & co: a seam that does not resolve is not drawn
        r = None
    if len(_cache) >= _CACHE_MAX:
        _cache.clear()
    _cache[key] = r
    return r


def _points(pos: np.ndarray, verts, weights) -> np.ndarray:
    v, w = np.asarray(verts, np.int64), np.asarray(weights, np.float32)
    return pos[v[:, 0]] * w[:, :1] + pos[v[:, 1]] * w[:, 1:2]


def seam_lines(scene) -> list[tuple[tuple[float, float, float, float], np.ndarray, bool]]:
    """(RGBA, (2k, 3) float32 segment endpoints, is the active seam) per visible seam: its two
    sides as polylines and a line between every sewn pair."""
    if not scene.tailor.show_seams:
        return []
    out = []
    positions: dict = {}
    for k, item in enumerate(scene.tailor.seams):
        if not item.show or not (scene_data.is_piece(item.piece_a) and scene_data.is_piece(item.piece_b)):
            continue
        r = _resolved(item)
        if r is None:
            continue
        for obj in (item.piece_a, item.piece_b):
            if obj.name not in positions:
                positions[obj.name] = scene_data.vertex_positions(obj)
        pa, pb = positions[item.piece_a.name], positions[item.piece_b.name]
        if r["a_vertices"] and max(r["a_vertices"]) >= len(pa) or r["b_vertices"] and max(r["b_vertices"]) >= len(pb):
            continue  # the mesh changed under the seam (being edited): nothing sensible to draw
        a = _points(pa, r["pair_a_vertices"], r["pair_a_weights"])
        b = _points(pb, r["pair_b_vertices"], r["pair_b_weights"])
        pairs = np.stack([a, b], axis=1).reshape(-1, 3)
        sides = []
        for p, verts in ((pa, r["a_vertices"]), (pb, r["b_vertices"])):
            run = p[np.asarray(verts, np.int64)]
            if len(run) > 1:
                sides.append(np.stack([run[:-1], run[1:]], axis=1).reshape(-1, 3))
        segs = np.concatenate([pairs] + sides).astype(np.float32)
        out.append(((*item.color, 1.0), segs, k == scene.tailor.seam_index))
    return out


def _draw() -> None:
    import gpu
    from gpu_extras.batch import batch_for_shader

    from ..compat import polyline_shader

    context = bpy.context
    lines = seam_lines(context.scene)
    if not lines or context.region is None:
        return
    shader = polyline_shader()
    gpu.state.depth_test_set("LESS_EQUAL")
    gpu.state.blend_set("ALPHA")
    shader.bind()
    shader.uniform_float("viewportSize", (context.region.width, context.region.height))
    for colour, segs, active in lines:
        batch = batch_for_shader(shader, "LINES", {"pos": segs})
        shader.uniform_float("lineWidth", 4.0 if active else 2.0)
        shader.uniform_float("color", colour)
        batch.draw(shader)
    gpu.state.depth_test_set("NONE")
    gpu.state.blend_set("NONE")


_HANDLER = ViewDrawHandler(_draw)


def register() -> None:
    _HANDLER.register()


def unregister() -> None:
    _HANDLER.unregister()
    _cache.clear()
