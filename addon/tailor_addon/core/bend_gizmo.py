"""The bend gizmo's geometry and drags, without Blender (`bend/gizmo_group.py` draws it,
`bend/gizmo_drag.py` drags it).

Everything is in the piece's own frame, where the flat piece lies in z = 0 with its rest
coordinates as x, y (as the Bend operator's `axis_point` and `axis_direction` are given):
  - the axis line: the bend axis drawn across the piece (`Handles.axis_from` to `axis_to`,
    arrow towards `axis_direction`, which is where a taper's cone widens); dragging it moves the
    axis point in the piece's plane, and with it the symmetry line (the axis' trace on the
    piece, where a symmetric bend starts to roll);
  - the dial, round the axis point in the plane across the axis, a quarter of the piece's width
    across (a size that does not change while it turns): dragging round it turns the angle
    (`DialDrag`, any number of turns);
  - the radius arrow, from the axis point towards the piece, as long as the radius the piece
    rolls onto (given, or the one the angle gives: `reach / |angle|`); dragging along it sets
    the radius (`arrow_radius`), which turns `use_radius` on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

MIN_RADIUS = 0.001  # the Bend operator's `radius` minimum, metres
AXIS_PAD = 0.1  # the axis line reaches this share of the piece's extent beyond it each side
DIAL_SHARE = 0.25  # the dial's radius: this share of the piece's extent across the axis


def _unit(v) -> np.ndarray:
    v = np.asarray(v, np.float64)
    n = float(np.linalg.norm(v))
    return v / n if n > 1e-12 else v * 0.0


def reach(rest: np.ndarray, axis_direction, symmetry=None, threshold: float = 0.0) -> float:
    """The distance the farthest point rolls (the kernel's `max s`) for a flat piece (rest
    points `rest` in z = 0) rolled about an axis along `axis_direction`: from the symmetry line
    (point, direction) both ways, else from the edge the piece rolls up from, less `threshold`."""
    d = _unit(axis_direction)
    across = _unit((-d[1], d[0]))  # in the piece's plane, across the axis
    if not across.any():
        return 0.0
    w = np.asarray(rest, np.float64) @ across
    if symmetry is not None:
        u = np.abs(w - float(np.asarray(symmetry[0], np.float64) @ across))
    else:
        u = w - w.min()
    return max(float(u.max()) - threshold, 0.0) if len(u) else 0.0


def shown_radius(angle: float, radius: float | None, rolled: float) -> float:
    """The radius the piece rolls onto: `radius` when given, else `rolled / |angle|` (0 when
    flat)."""
    if radius is not None:
        return float(radius)
    return rolled / abs(angle) if angle != 0.0 else 0.0


@dataclass
class Handles:
    """Where the gizmo's parts are, in the piece's frame."""

    axis_from: np.ndarray
    axis_to: np.ndarray
    centre: np.ndarray  # the axis point: the dial's centre, the radius arrow's start
    direction: np.ndarray  # unit axis direction
    out: np.ndarray  # unit, across the axis towards the piece: the radius arrow's direction
    radius: float  # the radius arrow's length
    dial: float  # the dial's radius


def handles(axis_point, axis_direction, rest_min, rest_max, radius: float) -> Handles:
    """The gizmo's parts for a bend about `axis_point` along `axis_direction` of a piece whose
    rest points lie in the box `rest_min`..`rest_max`."""
    o = np.asarray(axis_point, np.float64)
    d = _unit(axis_direction)
    corners = np.array([[x, y, 0.0] for x in (rest_min[0], rest_max[0]) for y in (rest_min[1], rest_max[1])])
    along = (corners - o) @ d
    lo, hi = float(along.min()), float(along.max())
    pad = AXIS_PAD * (hi - lo)
    across = (corners - o) - np.outer((corners - o) @ d, d)
    width = float(np.ptp(across @ _unit(np.cross(d, (0.0, 0.0, 1.0))))) if abs(d[2]) < 0.999 else 0.0
    # Out towards the piece's plane z = 0: its normal with the axis component removed.
    n = np.array([0.0, 0.0, 1.0]) - d[2] * d
    out = _unit(n)
    if not out.any():
        out = _unit(np.cross(d, (1.0, 0.0, 0.0))) if abs(d[0]) < 0.9 else _unit(np.cross(d, (0.0, 1.0, 0.0)))
    if o[2] > 0.0:
        out = -out
    dial = DIAL_SHARE * (width if width > 0.0 else hi - lo)
    return Handles(o + (lo - pad) * d, o + (hi + pad) * d, o, d, out, float(radius), dial)


def axis_frame(direction, out) -> np.ndarray:
    """A 3×3 rotation whose z column is `direction` and x column `out` (the dial's and the
    axis line's orientation)."""
    z = _unit(direction)
    x = _unit(np.asarray(out, np.float64) - (np.asarray(out, np.float64) @ z) * z)
    return np.column_stack([x, np.cross(z, x), z])


def arrow_frame(out, direction) -> np.ndarray:
    """A 3×3 rotation whose z column is `out` (the radius arrow's orientation)."""
    z = _unit(out)
    x = _unit(direction)
    return np.column_stack([x, np.cross(z, x), z])


def ray_plane_z(origin, direction, z: float = 0.0):
    """Where a ray (piece frame) meets the plane `z`, or None when it runs along it."""
    o, v = np.asarray(origin, np.float64), np.asarray(direction, np.float64)
    if abs(v[2]) < 1e-9:
        return None
    t = (z - o[2]) / v[2]
    return o + t * v


def moved_axis(axis_point, symmetry_point, start_hit, hit):
    """The axis point and symmetry point moved by the drag from `start_hit` to `hit` (points
    of the piece's plane): both move by its in-plane part, the axis keeps its depth."""
    delta = np.asarray(hit, np.float64)[:2] - np.asarray(start_hit, np.float64)[:2]
    a = np.asarray(axis_point, np.float64)
    s = np.asarray(symmetry_point, np.float64)
    return (float(a[0] + delta[0]), float(a[1] + delta[1]), float(a[2])), (float(s[0] + delta[0]),
                                                                           float(s[1] + delta[1]))


def arrow_radius(start_radius: float, base_px, tip_px, start_mouse, mouse) -> float:
    """The radius after dragging the arrow from `start_mouse` to `mouse` (pixels): the arrow
    runs on screen from `base_px` (the axis point) to `tip_px` (its tip at `start_radius`), and
    the tip follows the mouse's motion along it."""
    b, t = np.asarray(base_px, np.float64), np.asarray(tip_px, np.float64)
    along = t - b
    length = float(np.linalg.norm(along))
    if length < 1e-6 or start_radius <= 0.0:
        return max(start_radius, MIN_RADIUS)
    moved = (np.asarray(mouse, np.float64) - np.asarray(start_mouse, np.float64)) @ (along / length)
    return max(start_radius * (1.0 + moved / length), MIN_RADIUS)


class DialDrag:
    """The angle while dragging round the dial's centre (pixels): the turn swept, unwrapped so
    that several turns add up, counter-clockwise on screen positive when the axis points at the
    viewer (`facing` = 1; -1 when it points away)."""

    def __init__(self, start_angle: float, centre_px, start_mouse, facing: float = 1.0):
        self.angle = float(start_angle)
        self.centre = np.asarray(centre_px, np.float64)
        self.facing = 1.0 if facing >= 0.0 else -1.0
        self._last = self._bearing(start_mouse)

    def _bearing(self, mouse) -> float | None:
        v = np.asarray(mouse, np.float64) - self.centre
        return math.atan2(v[1], v[0]) if float(np.hypot(*v)) > 2.0 else None

    def update(self, mouse) -> float:
        b = self._bearing(mouse)
        if b is not None and self._last is not None:
            step = (b - self._last + math.pi) % (2 * math.pi) - math.pi
            self.angle += self.facing * step
        if b is not None:
            self._last = b
        return self.angle
