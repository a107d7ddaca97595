"""From a point under the mouse to a place on a piece: the bpy-free half of viewport picking.

The interactive tools ray-cast the mouse into the scene (Blender's `Scene.ray_cast`, in
`seams/viewport.py`) and get a hit point and a triangle of a piece object. The piece's rest
shape is what the module's contour functions take, so the hit is carried over to the rest
frame with its barycentric coordinates in the hit triangle: this works on a bent piece as well
as on a flat one, because vertex `i` of the Blender mesh is vertex `i` of the piece mesh.

A click just outside a piece (the contour is its border, so artists click on or near it) hits
nothing; the fallback is the contour vertex nearest the mouse on screen within a few pixels,
for which the vertices are projected with the view's perspective matrix (`project_points`).
"""

from __future__ import annotations

import numpy as np


def barycentric(p, a, b, c) -> np.ndarray:
    """Barycentric coordinates (3,) of `p` with respect to triangle `abc` (3D or 2D), of the
    point's projection onto the triangle's plane; a degenerate triangle gives its first vertex."""
    p, a, b, c = (np.asarray(x, np.float64) for x in (p, a, b, c))
    v0, v1, v2 = b - a, c - a, p - a
    d00, d01, d11 = v0 @ v0, v0 @ v1, v1 @ v1
    d20, d21 = v2 @ v0, v2 @ v1
    den = d00 * d11 - d01 * d01
    if abs(den) <= 1e-30:
        return np.array([1.0, 0.0, 0.0])
    v = (d11 * d20 - d01 * d21) / den
    w = (d00 * d21 - d01 * d20) / den
    return np.array([1.0 - v - w, v, w])


def hit_to_rest(local_point, co: np.ndarray, triangles: np.ndarray, rest: np.ndarray, face: int) -> np.ndarray:
    """The rest-frame (2D, metres) point of a hit at `local_point` (object frame) on triangle
    `face`, whose vertices are `co[triangles[face]]` now and `rest[triangles[face]]` at rest.
    Barycentrics are clamped into the triangle so a hit on its border stays on it."""
    if not 0 <= face < len(triangles):
        raise IndexError(f"triangle {face} of a mesh with {len(triangles)} triangles")
    t = np.asarray(triangles[face], np.int64)
    w = np.clip(barycentric(local_point, *np.asarray(co, np.float64)[t]), 0.0, None)
    w /= w.sum()
    return (w[:, None] * np.asarray(rest, np.float64)[t]).sum(axis=0)


def project_points(points, perspective, width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
    """Region pixel coordinates (n, 2) of world points (n, 3) under a view's 4x4 perspective
    matrix (`RegionView3D.perspective_matrix`), and a mask of the points in front of the
    view (the same maths as `view3d_utils.location_3d_to_region_2d`)."""
    pts = np.asarray(points, np.float64).reshape(-1, 3)
    h = np.c_[pts, np.ones(len(pts))] @ np.asarray(perspective, np.float64).T
    w = h[:, 3]
    front = w > 1e-9
    safe = np.where(front, w, 1.0)
    xy = np.c_[(width / 2.0) * (1.0 + h[:, 0] / safe), (height / 2.0) * (1.0 + h[:, 1] / safe)]
    return xy, front


def nearest_on_screen(xy: np.ndarray, visible: np.ndarray, mouse, radius: float) -> int | None:
    """Index of the visible point of `xy` nearest `mouse` (pixels) if within `radius`, else None."""
    if len(xy) == 0:
        return None
    d = np.hypot(xy[:, 0] - mouse[0], xy[:, 1] - mouse[1])
    d[~np.asarray(visible, bool)] = np.inf
    i = int(np.argmin(d))
    return i if d[i] <= radius else None
