"""The bend gizmo: a `GizmoGroup` in the 3D viewport on the active piece, shown while the
Bend panel's *Gizmo* toggle (`WindowManager.tailor_bend_gizmo`) is on.

Three parts, placed from the piece's stored bend (`Object.tailor_piece.bend_*`, or the Bend
operator's defaults for a flat piece) by `core.bend_gizmo.handles`:
  - the axis (red arrow along it, pointing where a taper's cone widens): drag to move it;
  - the angle dial (yellow ring round the axis point): drag round it to turn the angle;
  - the radius arrow (cyan, from the axis towards the piece, as long as the radius it rolls
    onto): drag its tip to set the radius.
Each part starts `tailor.bend_gizmo` (`gizmo_drag.py`) with its `handle`: a live preview while
dragging, then the Bend operator's exec path on release (one undo step, Bend's redo panel).
"""

from __future__ import annotations

import bpy
from mathutils import Matrix, Vector

from .. import scene_data
from ..core import bend_gizmo
from .operators import stored_values

COLOURS = {"AXIS": (0.9, 0.15, 0.15), "ANGLE": (0.95, 0.8, 0.1), "RADIUS": (0.1, 0.8, 0.95)}
DEFAULT_RADIUS = 0.05  # the radius arrow's length on a flat piece, metres
ARROW_UNIT = 0.2  # metres per unit of the arrows' own size (their heads, about 2 cm across)


def _matrix(rotation, translation, scale: float) -> Matrix:
    """Rotation, then a uniform `scale`, at `translation`: the gizmo's units in the piece's frame
    (its `use_draw_scale` is off, so the basis is all the scale it gets: sizes in metres)."""
    m = (Matrix([list(map(float, row)) for row in rotation]) * float(scale)).to_4x4()
    m.translation = Vector(tuple(float(c) for c in translation))
    return m


def placement(obj) -> tuple[bend_gizmo.Handles, float]:
    """The gizmo's parts for piece `obj` (its frame) and the angle they show."""
    v = stored_values(obj)
    rest = scene_data.rest_of(obj)
    angle = obj.tailor_piece.bend_angle
    symmetry = (v["symmetry_point"], v["symmetry_direction"]) if v["use_symmetry"] else None
    r = bend_gizmo.shown_radius(angle, v["radius"] if v["use_radius"] else None,
                                bend_gizmo.reach(rest, v["axis_direction"], symmetry, v["threshold"]))
    h = bend_gizmo.handles(v["axis_point"], v["axis_direction"], rest.min(axis=0), rest.max(axis=0),
                           r if r > 0.0 else DEFAULT_RADIUS)
    return h, angle


class TAILOR_GGT_bend(bpy.types.GizmoGroup):
    bl_idname = "TAILOR_GGT_bend"
    bl_label = "Tailor Bend"
    bl_space_type = "VIEW_3D"
    bl_region_type = "WINDOW"
    bl_options = {"3D", "PERSISTENT"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        wm = context.window_manager
        if not (getattr(wm, "tailor_bend_gizmo", False) and scene_data.is_piece(obj) and obj.mode == "OBJECT"):
            return False
        rest = scene_data.rest_of(obj)
        return rest is not None and len(rest) == len(obj.data.vertices) and len(rest) > 0

    def setup(self, context):
        self.parts = {}
        for handle, kind in (("AXIS", "GIZMO_GT_arrow_3d"), ("ANGLE", "GIZMO_GT_dial_3d"),
                             ("RADIUS", "GIZMO_GT_arrow_3d")):
            gz = self.gizmos.new(kind)
            props = gz.target_set_operator("tailor.bend_gizmo")
            props.handle = handle
            gz.color = COLOURS[handle]
            gz.alpha = 0.8
            gz.color_highlight = (1.0, 1.0, 1.0)
            gz.alpha_highlight = 1.0
            gz.line_width = 3.0
            self.parts[handle] = gz
        for gz in self.parts.values():
            gz.use_draw_scale = False
        self._place(context)

    def refresh(self, context):
        self._place(context)

    def draw_prepare(self, context):
        self._place(context)

    def _place(self, context) -> None:
        obj = context.active_object
        if not scene_data.is_piece(obj):
            return
        h, _ = placement(obj)
        m = obj.matrix_world
        frame = bend_gizmo.axis_frame(h.direction, h.out)
        # Arrows in units of ARROW_UNIT metres (their heads are sized in those units); the dial's
        # ring has radius 1 in its own units.
        axis = self.parts["AXIS"]
        axis.matrix_basis = m @ _matrix(frame, h.axis_from, ARROW_UNIT)
        axis.length = float(((h.axis_to - h.axis_from) ** 2).sum() ** 0.5) / ARROW_UNIT
        self.parts["ANGLE"].matrix_basis = m @ _matrix(frame, h.centre, h.dial)
        radius = self.parts["RADIUS"]
        radius.matrix_basis = m @ _matrix(bend_gizmo.arrow_frame(h.out, h.direction), h.centre, ARROW_UNIT)
        radius.length = h.radius / ARROW_UNIT


classes = (TAILOR_GGT_bend,)
