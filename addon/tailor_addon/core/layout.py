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
