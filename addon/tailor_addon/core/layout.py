"""Where imported pieces go: a GarmentCode placement as an object transform, or side by side.

The module's own placement (`tailor_core::placement`) maps a rest point (x, y) to
`R · (x, y, 0) + t` with `R = Rx · Ry · Rz` (intrinsic XYZ Euler angles, degrees). Blender's
Euler order 'ZYX' composes the same matrix, so a piece object keeps its flat rest shape as mesh
coordinates and carries the placement as its transform; moving the object moves the piece.

GarmentCode files (and their body meshes) are Y-up; Blender is Z-up. Blender's OBJ importer
turns a Y-up file's (x, y, z) into (x, -z, y), a +90° rotation about X (`Y_UP_TO_Z_UP`); placed
pieces get the same turn by default, so they sit on a body imported that way.
"""

from __future__ import annotations

import math

import numpy as np

# Blender rotation mode whose matrix is Rx·Ry·Rz (the module's intrinsic XYZ convention).
PLACEMENT_ROTATION_MODE = "ZYX"


def placement_rotation(placement: dict) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """(location, euler radians in PLACEMENT_ROTATION_MODE) of a `Piece.placement` dict."""
    t = tuple(float(c) for c in placement["translation"])
    r = tuple(math.radians(float(c)) for c in placement["rotation_deg"])
    return t, r  # type: ignore[return-value]


# (x, y, z) of a Y-up file -> (x, -z, y) in Blender, as Blender's OBJ importer does.
Y_UP_TO_Z_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


def side_by_side(rests: list[np.ndarray], gap: float = 0.05, start_x: float = 0.0) -> list[tuple[float, float, float]]:
    """Object locations laying flat pieces left to right `gap` metres apart in the XY plane
    (as `Garment.build_simulation` lays out pieces without a placement)."""
    out = []
    cursor = start_x
    for rest in rests:
        lo = rest.min(axis=0) if len(rest) else np.zeros(2)
        hi = rest.max(axis=0) if len(rest) else np.zeros(2)
        out.append((float(cursor - lo[0]), float(-lo[1]), 0.0))
        cursor += float(hi[0] - lo[0]) + gap
    return out


def rotation_matrix(euler: tuple[float, float, float]) -> np.ndarray:
    """The 3x3 rotation of Euler angles (radians) in PLACEMENT_ROTATION_MODE: Rx·Ry·Rz."""
    a, b, c = (float(x) for x in euler)
    rx = np.array([[1.0, 0.0, 0.0], [0.0, math.cos(a), -math.sin(a)], [0.0, math.sin(a), math.cos(a)]])
    ry = np.array([[math.cos(b), 0.0, math.sin(b)], [0.0, 1.0, 0.0], [-math.sin(b), 0.0, math.cos(b)]])
    rz = np.array([[math.cos(c), -math.sin(c), 0.0], [math.sin(c), math.cos(c), 0.0], [0.0, 0.0, 1.0]])
    return rx @ ry @ rz


def euler_of(r: np.ndarray) -> tuple[float, float, float]:
    """Euler angles (radians, PLACEMENT_ROTATION_MODE) of a rotation matrix: the inverse of
    `rotation_matrix` (at gimbal lock, where only a + c counts, c = 0)."""
    r = np.asarray(r, np.float64)
    b = math.asin(max(-1.0, min(1.0, r[0, 2])))
    if abs(r[0, 2]) < 1.0 - 1e-9:
        return math.atan2(-r[1, 2], r[2, 2]), b, math.atan2(-r[0, 1], r[0, 0])
    return math.atan2(r[2, 1], r[1, 1]), b, 0.0
