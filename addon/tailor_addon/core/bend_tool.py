"""The interactive bend's logic, without Blender: where the axis goes and what a drag means.

The viewport tool (`bend/gizmo.py`) works in two stages on the active piece:
  1. place the axis: the bend axis runs through the rest point under the cursor, along the
     piece's rest y (a vertical axis, the default: sleeves and skirts are cut upright) or rest x
     (key X/Y switches), `depth` behind the piece (the limb's radius; mouse wheel changes it);
     with symmetry on, the symmetry line is the axis' trace on the piece;
  2. drag the angle: horizontal mouse motion sets the angle (`degrees_per_pixel`), the piece is
     bent live (`tailor.bend` through the Bend operator's `bend_positions`); a click commits
     through the exec-path operator `tailor.bend` (redo panel), Esc/right-click restores it.
`BendParams.operator_kwargs()` are exactly that operator's properties.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

AXES = {"Y": (0.0, 1.0), "X": (1.0, 0.0)}
DEFAULT_DEPTH = 0.1
MIN_DEPTH = 0.005
DEPTH_STEP = 1.25  # factor per wheel step


@dataclass
class BendParams:
    """The Bend operator's properties: axis in the piece frame, symmetry line in the rest frame."""

    axis_point: tuple[float, float, float]
    axis_direction: tuple[float, float, float]
    angle: float  # radians
    use_symmetry: bool
    symmetry_point: tuple[float, float]
    symmetry_direction: tuple[float, float]
    threshold: float = 0.0

    def operator_kwargs(self) -> dict:
        return {
            "axis_point": self.axis_point,
            "axis_direction": self.axis_direction,
            "angle": self.angle,
            "use_symmetry": self.use_symmetry,
            "symmetry_point": self.symmetry_point,
            "symmetry_direction": self.symmetry_direction,
            "threshold": self.threshold,
        }

    def symmetry(self):
        """The `symmetry` argument of `tailor.bend`."""
        return (self.symmetry_point, self.symmetry_direction) if self.use_symmetry else None


class BendTool:
    """Stage 'axis' then 'angle'; `params()` is what the preview and the commit use."""

    def __init__(self, rest_centre, degrees_per_pixel: float = 0.5, use_symmetry: bool = True):
        self.axis = "Y"
        self.depth = DEFAULT_DEPTH
        self.use_symmetry = use_symmetry
        self.through = (float(rest_centre[0]), float(rest_centre[1]))  # rest point the axis passes over
        self.degrees_per_pixel = float(degrees_per_pixel)
        self.stage = "axis"
        self.anchor_x: float | None = None  # mouse x where the angle drag started
        self.angle = 0.0  # radians

    def prompt(self) -> str:
        sym = "on" if self.use_symmetry else "off"
        if self.stage == "axis":
            return (
                f"Bend 1/2: move to place the axis (along rest {self.axis.lower()}, {self.depth * 100:.1f} cm behind), "
                f"click to fix it · X/Y: axis direction · wheel: depth · S: symmetry ({sym}) · Esc: cancel"
            )
        return (
            f"Bend 2/2: drag sideways to set the angle ({math.degrees(self.angle):.0f}°), click to apply · "
            "Backspace: move the axis again · Esc/right-click: cancel"
        )

    def hover(self, rest_point) -> None:
        """Stage 'axis': the axis follows the cursor's rest point."""
        if self.stage == "axis" and rest_point is not None:
            self.through = (float(rest_point[0]), float(rest_point[1]))

    def set_axis(self, key: str) -> None:
        if key in AXES:
            self.axis = key

    def wheel(self, steps: int) -> None:
        self.depth = max(MIN_DEPTH, self.depth * DEPTH_STEP**steps)

    def toggle_symmetry(self) -> None:
        self.use_symmetry = not self.use_symmetry

    def fix_axis(self, mouse_x: float) -> None:
        self.stage, self.anchor_x, self.angle = "angle", float(mouse_x), 0.0

    def drag(self, mouse_x: float) -> None:
        if self.stage == "angle":
            self.angle = math.radians((float(mouse_x) - self.anchor_x) * self.degrees_per_pixel)

    def back(self) -> bool:
        """Backspace: from the angle back to placing the axis; False if already there."""
        if self.stage != "angle":
            return False
        self.stage, self.anchor_x, self.angle = "axis", None, 0.0
        return True

    def params(self) -> BendParams:
        d = AXES[self.axis]
        return BendParams(
            axis_point=(self.through[0], self.through[1], -self.depth),
            axis_direction=(d[0], d[1], 0.0),
            angle=self.angle,
            use_symmetry=self.use_symmetry,
            symmetry_point=self.through,
            symmetry_direction=d,
        )

    def axis_segment(self, rest_min, rest_max) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """The axis drawn across the piece's rest bounding box (piece frame), for the viewport."""
        p = self.params()
        k = 1 if self.axis == "Y" else 0
        lo, hi = float(rest_min[k]), float(rest_max[k])
        pad = 0.1 * (hi - lo)
        if self.axis == "Y":
            return (p.axis_point[0], lo - pad, p.axis_point[2]), (p.axis_point[0], hi + pad, p.axis_point[2])
        return (lo - pad, p.axis_point[1], p.axis_point[2]), (hi + pad, p.axis_point[1], p.axis_point[2])
