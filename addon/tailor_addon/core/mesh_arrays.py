"""A `tailor.PieceMesh` as the flat float32/int32 arrays a Blender mesh is written from.

A piece object's mesh stores (see docs/addon.md):
  * vertex coordinates: the rest shape (x, y, 0) until the piece is bent;
  * `tailor_rest` (point, FLOAT2) and the UV map `TailorRest` (per corner): the rest shape in
    metres, the solver's 2D reference, kept when the 3D shape changes;
  * `tailor_contour` (point, INT): the vertex's position on the outer contour, -1 inside;
  * `tailor_corner` (point, BOOLEAN): contour corners (pins and sharp turns).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import tailor

REST_ATTR = "tailor_rest"
CONTOUR_ATTR = "tailor_contour"
CORNER_ATTR = "tailor_corner"
REST_UV = "TailorRest"


@dataclass
class MeshArrays:
    co: np.ndarray  # (n, 3) float32 local coordinates
    triangles: np.ndarray  # (m, 3) int32
    rest: np.ndarray  # (n, 2) float32
    contour: np.ndarray  # (n,) int32 contour position or -1
    corner: np.ndarray  # (n,) bool
    uv: np.ndarray  # (3m, 2) float32, per face corner

    @property
    def num_vertices(self) -> int:
        return len(self.co)


def mesh_arrays(mesh: tailor.PieceMesh, positions: np.ndarray | None = None) -> MeshArrays:
    """The arrays of `mesh`; vertex coordinates are `positions` (n, 3) or the flat rest shape."""
    rest = np.ascontiguousarray(mesh.rest, dtype=np.float32)
    n = len(rest)
    if positions is None:
        co = np.zeros((n, 3), np.float32)
        co[:, :2] = rest
    else:
        co = np.ascontiguousarray(positions, dtype=np.float32).reshape(n, 3)
    tris = np.ascontiguousarray(mesh.triangles, dtype=np.int32)
    contour_idx = np.asarray(mesh.contour, dtype=np.int64)
    contour = np.full(n, -1, np.int32)
    contour[contour_idx] = np.arange(len(contour_idx), dtype=np.int32)
    corner = np.zeros(n, bool)
    if mesh.corners:
        corner[contour_idx[np.asarray(mesh.corners, dtype=np.int64)]] = True
    uv = rest[tris.reshape(-1)]
    return MeshArrays(co=co, triangles=tris, rest=rest, contour=contour, corner=corner, uv=uv)
