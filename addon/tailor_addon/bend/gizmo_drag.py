"""The bend gizmo's drag: one operator that each of the gizmo's parts (`gizmo_group.py`) starts
on a click, with the Bend operator's properties and exec path (`BendProperties`).

It starts from the piece's stored bend (or the Bend operator's defaults for a flat piece),
changes one value while the mouse moves (the axis point, the angle or the radius: its `handle`)
with a live preview computed by `bend_positions` (`tailor.bend`), and on release puts the mesh
back and runs `BendProperties.execute`: one undo step per drag, whose redo panel is the Bend
operator's and gives the same mesh. Esc or right click puts the piece back as it was. The maths
of each drag is `core.bend_gizmo`'s; this file turns mouse positions into its inputs.
"""

import bpy
import numpy as np
from bpy.props import EnumProperty
from bpy_extras import view3d_utils
from mathutils import Vector

from .. import scene_data
from ..core import bend_gizmo
from ..core.errors import is_reportable
from ..reporting import report
from .operators import BendProperties, bend_positions, write_positions

HANDLES = [
    ("AXIS", "Axis", "Move the axis (and the symmetry line) in the piece's plane"),
    ("ANGLE", "Angle", "Turn the angle round the axis"),
    ("RADIUS", "Radius", "Set the radius the piece rolls onto"),
]

#: The piece's stored bend values a drag previews (put back on cancel).
STORED = ("bend_angle", "bend_axis_point", "bend_axis_direction", "bend_symmetry", "bend_symmetry_point",
          "bend_symmetry_direction", "bend_threshold", "bend_rolled", "bend_radius", "bend_taper")


class TAILOR_OT_bend_gizmo(BendProperties, bpy.types.Operator):
    bl_idname = "tailor.bend_gizmo"
    bl_label = "Bend Piece (Gizmo)"
    bl_description = "Drag the bend gizmo's axis, angle dial or radius arrow; the same bend as Bend Piece"
    bl_options = {"REGISTER", "UNDO", "BLOCKING", "INTERNAL"}  # started by the gizmo, not from a menu

    handle: EnumProperty(items=HANDLES, name="Handle", options={"HIDDEN", "SKIP_SAVE"})

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return scene_data.is_piece(obj) and obj.mode == "OBJECT"

    # ---- screen <-> piece frame -------------------------------------------------------------

    def _to_px(self, context, local) -> np.ndarray | None:
        world = self.matrix @ Vector(tuple(float(c) for c in local))
        p = view3d_utils.location_3d_to_region_2d(context.region, context.region_data, world)
        return None if p is None else np.array(p, np.float64)

    def _plane_hit(self, context, mouse):
        region, rv3d = context.region, context.region_data
        origin = view3d_utils.region_2d_to_origin_3d(region, rv3d, mouse)
        vector = view3d_utils.region_2d_to_vector_3d(region, rv3d, mouse)
        inv = self.matrix.inverted()
        o = np.array(inv @ origin, np.float64)
        v = np.array(inv.to_3x3() @ vector, np.float64)
        return bend_gizmo.ray_plane_z(o, v, 0.0)

    # ---- the drag ------------------------------------------------------------------------------

    def invoke(self, context, event):
        obj = context.active_object
        if context.region is None or context.region_data is None:
            return self.execute(context)
        self.fill_defaults(obj)
        if obj.tailor_piece.bend_angle == 0.0 and self.handle != "RADIUS":
            self.angle = 0.0  # a flat piece: the dial starts from flat, the axis moves without bending it
        self.obj_name = obj.name
        self.matrix = obj.matrix_world.copy()
        self.original = scene_data.vertex_positions(obj, world=False)
        self.stored = {k: tuple(v) if hasattr(v, "__len__") else v
                       for k, v in ((k, getattr(obj.tailor_piece, k)) for k in STORED)}
        self.mouse0 = np.array((event.mouse_region_x, event.mouse_region_y), np.float64)
        rest = scene_data.rest_of(obj)
        symmetry = (tuple(self.symmetry_point), tuple(self.symmetry_direction)) if self.use_symmetry else None
        reach = bend_gizmo.reach(rest, self.axis_direction, symmetry, self.threshold)
        self.start_radius = bend_gizmo.shown_radius(self.angle, self.radius if self.use_radius else None, reach)
        h = bend_gizmo.handles(self.axis_point, self.axis_direction, rest.min(axis=0), rest.max(axis=0),
                               self.start_radius)
        if self.handle == "ANGLE":
            centre = self._to_px(context, h.centre)
            view = np.array(context.region_data.view_rotation @ Vector((0.0, 0.0, 1.0)))
            world_dir = np.array(self.matrix.to_3x3() @ Vector(tuple(h.direction)))
            self.dial = bend_gizmo.DialDrag(self.angle, centre if centre is not None else self.mouse0, self.mouse0,
                                            facing=float(np.sign(world_dir @ view) or 1.0))
        elif self.handle == "RADIUS":
            if self.start_radius <= 0.0:
                self.start_radius = self.radius
            self.base_px = self._to_px(context, h.centre)
            self.tip_px = self._to_px(context, h.centre + self.start_radius * h.out)
        else:
            self.hit0 = self._plane_hit(context, self.mouse0)
            self.axis0, self.sym0 = tuple(self.axis_point), tuple(self.symmetry_point)
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def _update(self, context, event) -> None:
        mouse = np.array((event.mouse_region_x, event.mouse_region_y), np.float64)
        if self.handle == "ANGLE":
            self.angle = self.dial.update(mouse)
        elif self.handle == "RADIUS":
            if self.base_px is not None and self.tip_px is not None:
                self.radius = bend_gizmo.arrow_radius(self.start_radius, self.base_px, self.tip_px, self.mouse0, mouse)
                self.use_radius = True
                if self.angle == 0.0:
                    self.angle = 1.0  # a radius rolls the piece; only the angle's sign counts then
        else:
            hit = self._plane_hit(context, mouse)
            if self.hit0 is not None and hit is not None:
                self.axis_point, self.symmetry_point = bend_gizmo.moved_axis(self.axis0, self.sym0, self.hit0, hit)
        obj = bpy.data.objects[self.obj_name]
        write_positions(obj, bend_positions(obj, **self.bend_kwargs()))
        self._store(obj)
        context.area.tag_redraw()

    def _store(self, obj) -> None:
        """The values on the piece as the drag stands, so the gizmo follows it."""
        p = obj.tailor_piece
        p.bend_angle, p.bend_axis_point, p.bend_axis_direction = self.angle, self.axis_point, self.axis_direction
        p.bend_symmetry, p.bend_threshold = self.use_symmetry, self.threshold
        p.bend_symmetry_point, p.bend_symmetry_direction = self.symmetry_point, self.symmetry_direction
        p.bend_radius, p.bend_taper = (self.radius if self.use_radius else 0.0), self.taper
        p.bend_rolled = True

    def _restore(self, context) -> None:
        obj = bpy.data.objects.get(self.obj_name)
        if obj is not None:
            write_positions(obj, self.original)
            for k, v in self.stored.items():
                setattr(obj.tailor_piece, k, v)
        context.area.tag_redraw()

    def modal(self, context, event):
        try:
            if event.type in {"ESC", "RIGHTMOUSE"} and event.value == "PRESS":
                self._restore(context)
                return {"CANCELLED"}
            if event.type == "LEFTMOUSE" and event.value == "RELEASE":
                self._restore(context)
                return self.execute(context)
            if event.type in {"MOUSEMOVE", "INBETWEEN_MOUSEMOVE"}:
                self._update(context, event)
            return {"RUNNING_MODAL"}
        except Exception as exc:
            self._restore(context)
            if not is_reportable(exc):
                raise
            report(self, exc, "Bending the piece")
            return {"CANCELLED"}


classes = (TAILOR_OT_bend_gizmo,)
