"""The Bend operator: wrap a flat piece around an axis (paper Fig. 4) with `tailor.bend`.

The bend is always applied to the piece's flat rest shape in its own (object) frame and stored
on the piece (`Object.tailor_piece.bend_*`), so changing any value in the redo panel recomputes
it from flat, angle 0 makes the piece flat again, and a change of resolution re-applies it.
The exec path takes the axis in the piece's local frame; the interactive gizmo converts the
axis it places in the viewport and calls it (or `bend_positions` for its live preview).
"""

import math

import bpy
import numpy as np
from bpy.props import BoolProperty, FloatProperty, FloatVectorProperty

import tailor

from .. import scene_data
from ..core import AddonError
from ..reporting import reports_errors


def flat_positions(obj) -> np.ndarray:
    rest = scene_data.rest_of(obj)
    if rest is None or len(rest) != len(obj.data.vertices):
        raise AddonError(
            f"piece '{obj.name}' has no rest shape matching its mesh",
            "Set its resolution again (Patterns panel) to rebuild it",
        )
    co = np.zeros((len(rest), 3), np.float32)
    co[:, :2] = rest
    return co


def bend_positions(
    obj, axis_point, axis_direction, angle: float, symmetry=None, threshold: float = 0.0,
    radius: float | None = None, taper: float = 0.0,
):
    """New local vertex positions of piece `obj` bent from flat (angle and taper in radians;
    `radius` None: from the angle)."""
    co = flat_positions(obj)
    if angle == 0.0:
        return co
    return tailor.bend(
        co,
        co[:, :2],
        tuple(axis_point),
        tuple(axis_direction),
        math.degrees(angle),
        symmetry=symmetry,
        threshold=threshold,
        radius=radius,
        taper_deg=math.degrees(taper),
    )


def write_positions(obj, co: np.ndarray) -> None:
    obj.data.vertices.foreach_set("co", np.ascontiguousarray(co, np.float32).reshape(-1))
    obj.data.update()


def stored_values(obj) -> dict:
    """The Bend operator's properties for piece `obj`: its stored bend, or for a flat piece the
    axis along its vertical centre line 10 cm behind it and the symmetry line on it, 90 degrees."""
    p = obj.tailor_piece
    rest = scene_data.rest_of(obj)
    c = (rest.min(axis=0) + rest.max(axis=0)) / 2 if rest is not None and len(rest) else np.zeros(2)
    bent = p.bend_angle != 0.0
    return {
        "axis_point": tuple(p.bend_axis_point) if bent else (float(c[0]), float(c[1]), -0.1),
        "axis_direction": tuple(p.bend_axis_direction) if bent else (0.0, 1.0, 0.0),
        "angle": p.bend_angle if bent else math.radians(90.0),
        "use_symmetry": p.bend_symmetry if bent else True,
        "symmetry_point": tuple(p.bend_symmetry_point) if bent else (float(c[0]), float(c[1])),
        "symmetry_direction": tuple(p.bend_symmetry_direction) if bent else (0.0, 1.0),
        "threshold": p.bend_threshold if bent else 0.0,
        "use_radius": bent and p.bend_radius > 0.0,
        "radius": p.bend_radius if bent and p.bend_radius > 0.0 else 0.05,
        "taper": p.bend_taper if bent else 0.0,
    }


class BendProperties:
    """The Bend operator's properties and exec path; the interactive tool (`gizmo.py`) shares
    them, so its redo panel is this one and its commit is this `execute`."""

    axis_point: FloatVectorProperty(
        name="Axis Point",
        description="A point of the rotation axis (piece frame)",
        size=3,
        subtype="TRANSLATION",
        unit="LENGTH",
    )
    axis_direction: FloatVectorProperty(
        name="Axis Direction",
        description="Direction of the rotation axis (piece frame)",
        size=3,
        default=(0.0, 1.0, 0.0),
        subtype="DIRECTION",
    )
    angle: FloatProperty(
        name="Angle",
        description="Turn of the point farthest from where the piece starts to roll (the symmetry "
        "line, or the edge nearest the axis): the piece rolls onto a cylinder, every length kept",
        subtype="ANGLE",
        default=math.radians(90.0),
        soft_min=-2 * math.pi,
        soft_max=2 * math.pi,
    )
    use_symmetry: BoolProperty(
        name="Symmetric",
        description="Roll the two sides of the symmetry line in opposite senses (a sleeve)",
        default=True,
    )
    symmetry_point: FloatVectorProperty(
        name="Symmetry Point",
        description="A point of the symmetry line (rest frame)",
        size=2,
        unit="LENGTH",
    )
    symmetry_direction: FloatVectorProperty(
        name="Symmetry Direction",
        description="Direction of the symmetry line (rest frame)",
        size=2,
        default=(0.0, 1.0),
    )
    threshold: FloatProperty(
        name="Distance Threshold",
        description="Points within this distance (along the piece) of where it starts to roll do not move",
        subtype="DISTANCE",
        unit="LENGTH",
        default=0.0,
        min=0.0,
    )
    use_radius: BoolProperty(
        name="Use Radius",
        description="Roll onto a cylinder (or cone) of the given radius; the angle's sign then only says "
        "which way. Off: the radius follows from the angle",
        default=False,
    )
    radius: FloatProperty(
        name="Radius",
        description="Radius of the cylinder the piece rolls onto (of the cone level with the axis point)",
        subtype="DISTANCE",
        unit="LENGTH",
        default=0.05,
        min=0.001,
        soft_max=1.0,
    )
    taper: FloatProperty(
        name="Taper",
        description="Half-angle of the cone the piece rolls onto, for a tapered limb: the radius grows along "
        "the axis direction (shrinks if negative); 0: a cylinder",
        subtype="ANGLE",
        default=0.0,
        soft_min=math.radians(-30.0),
        soft_max=math.radians(30.0),
    )

    def bend_kwargs(self) -> dict:
        """`bend_positions`' arguments from these properties."""
        return {
            "axis_point": tuple(self.axis_point),
            "axis_direction": tuple(self.axis_direction),
            "angle": self.angle,
            "symmetry": (tuple(self.symmetry_point), tuple(self.symmetry_direction)) if self.use_symmetry else None,
            "threshold": self.threshold,
            "radius": self.radius if self.use_radius else None,
            "taper": self.taper,
        }

    def fill_defaults(self, obj) -> None:
        """Set every property the caller did not to `stored_values(obj)`."""
        for name, value in stored_values(obj).items():
            if not self.properties.is_property_set(name):
                setattr(self, name, value)

    @reports_errors("Bending the piece")
    def execute(self, context):
        obj = context.active_object
        if not scene_data.is_piece(obj):
            raise AddonError("the active object is not a garment piece", "Select an imported piece")
        if obj.mode != "OBJECT":
            raise AddonError("the piece is in edit mode", "Switch to Object Mode to bend it")
        co = bend_positions(obj, **self.bend_kwargs())
        write_positions(obj, co)
        p = obj.tailor_piece
        p.bend_angle = self.angle
        p.bend_axis_point, p.bend_axis_direction = self.axis_point, self.axis_direction
        p.bend_symmetry, p.bend_threshold = self.use_symmetry, self.threshold
        p.bend_symmetry_point, p.bend_symmetry_direction = self.symmetry_point, self.symmetry_direction
        p.bend_rolled = True
        p.bend_radius = self.radius if self.use_radius else 0.0
        p.bend_taper = self.taper
        return {"FINISHED"}


class TAILOR_OT_bend(BendProperties, bpy.types.Operator):
    bl_idname = "tailor.bend"
    bl_label = "Bend Piece"
    bl_description = (
        "Bend the active flat piece around an axis (in the piece's own frame) so it wraps around a limb; "
        "angle 0 flattens it"
    )
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return scene_data.is_piece(context.active_object)

    def invoke(self, context, event):
        """Values not given by the caller: the piece's stored bend, or for a flat piece the
        axis along its vertical centre line 10 cm behind it and the symmetry line on it."""
        self.fill_defaults(context.active_object)
        return self.execute(context)


classes = (TAILOR_OT_bend,)
