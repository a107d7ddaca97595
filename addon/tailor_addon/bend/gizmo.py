"""Bend in the viewport: place the bend axis on the active piece, drag the angle with a live
preview, commit through the Bend operator's exec path (whose redo panel then adjusts it).

The stages and what each key does are `core.bend_tool.BendTool` (bpy-free). While the tool
runs the piece's mesh shows the preview (flat while the axis is placed, bent while dragging),
computed by the Bend operator's own `bend_positions` (`tailor.bend`); Esc or right click puts
the mesh back exactly as it was. The tool shares the Bend operator's properties and exec path
(`BendProperties`): on commit it puts the mesh back, sets those properties to the placed axis
and dragged angle and runs that `execute`, so the finished tool is one undo step whose redo
panel is Bend's (axis, angle, symmetry, threshold), recomputed from flat by the same `execute`.
"""

from __future__ import annotations

import bpy
import numpy as np

from .. import scene_data
from ..core.bend_tool import BendTool
from ..core.errors import is_reportable
from ..reporting import report
from ..seams import viewport
from ..seams.modal_base import CLICK, NAVIGATION
from .operators import BendProperties, bend_positions, flat_positions, write_positions


class TAILOR_OT_bend_interactive(BendProperties, bpy.types.Operator):
    bl_idname = "tailor.bend_interactive"
    bl_label = "Bend in Viewport"
    bl_description = (
        "Bend the active piece interactively: move to place the axis and click, drag sideways to set the "
        "angle (live preview) and click to apply; X/Y: axis direction, wheel: axis depth, S: symmetry"
    )
    bl_options = {"REGISTER", "UNDO", "BLOCKING"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return viewport.window_region(context) is not None and scene_data.is_piece(obj) and obj.mode == "OBJECT"

    def invoke(self, context, event):
        view = viewport.window_region(context)
        obj = context.active_object
        try:
            flat = flat_positions(obj)
        except Exception as exc:
            if not is_reportable(exc):
                raise
            report(self, exc, "Bending the piece")
            return {"CANCELLED"}
        self.view, self.obj_name = view, obj.name
        self.original = scene_data.vertex_positions(obj, world=False)
        self.flat = flat
        rest = flat[:, :2]
        self.rest_min, self.rest_max = rest.min(axis=0), rest.max(axis=0)
        self.tool = BendTool((self.rest_min + self.rest_max) / 2)
        write_positions(obj, flat)
        self._handle = bpy.types.SpaceView3D.draw_handler_add(self._draw, (), "WINDOW", "POST_VIEW")
        context.window_manager.modal_handler_add(self)
        self._update(context, event)
        return {"RUNNING_MODAL"}

    # ---- drawing ---------------------------------------------------------------------------

    def _lines(self) -> list:
        obj = bpy.data.objects.get(self.obj_name)
        if obj is None:
            return []
        m = np.array(obj.matrix_world, np.float64)
        a, b = self.tool.axis_segment(self.rest_min, self.rest_max)
        axis = np.array([a, b], np.float64)
        trace = axis.copy()
        trace[:, 2] = 0.0  # the axis' trace on the flat piece: the symmetry line
        out = []
        for role, seg in (("axis", axis), ("preview", trace)):
            if role == "preview" and not self.tool.use_symmetry:
                continue
            world = seg @ m[:3, :3].T + m[:3, 3]
            out.append(("LINES", role, world.astype(np.float32)))
        return out

    def _draw(self) -> None:
        viewport.draw_batches(self._lines(), line_width=3.0)

    # ---- events ----------------------------------------------------------------------------

    def _update(self, context, event) -> None:
        obj = bpy.data.objects[self.obj_name]
        mouse = viewport.region_mouse(self.view, event)
        if self.tool.stage == "axis":
            piece, point = viewport.pick(context, self.view, mouse, only={self.obj_name})
            self.tool.hover(point if piece is not None else None)
        else:
            self.tool.drag(mouse[0])
            p = self.tool.params()
            co = bend_positions(obj, p.axis_point, p.axis_direction, p.angle, p.symmetry(), p.threshold)
            write_positions(obj, co)
        viewport.set_header(context, self.view, self.tool.prompt())
        self.view[0].tag_redraw()

    def _finish(self, context, result: set, restore: bool) -> set:
        if self._handle is not None:
            bpy.types.SpaceView3D.draw_handler_remove(self._handle, "WINDOW")
            self._handle = None
        obj = bpy.data.objects.get(self.obj_name)
        if restore and obj is not None:
            write_positions(obj, self.original)
        viewport.set_header(context, self.view, None)
        self.view[0].tag_redraw()
        return result

    def cancel(self, context):
        self._finish(context, {"CANCELLED"}, restore=True)

    def modal(self, context, event):
        try:
            return self._modal(context, event)
        except Exception as exc:
            self._finish(context, {"CANCELLED"}, restore=True)
            if not is_reportable(exc):
                raise
            report(self, exc, "Bending the piece")
            return {"CANCELLED"}

    def _modal(self, context, event):
        tool = self.tool
        if event.type in {"WHEELUPMOUSE", "WHEELDOWNMOUSE"} and tool.stage == "axis":
            tool.wheel(1 if event.type == "WHEELUPMOUSE" else -1)
            self._update(context, event)
            return {"RUNNING_MODAL"}
        if event.type in NAVIGATION:
            return {"PASS_THROUGH"}
        if event.type in {"ESC", "RIGHTMOUSE"} and event.value == "PRESS":
            return self._finish(context, {"CANCELLED"}, restore=True)
        if event.value == "PRESS" and event.type in {"X", "Y"} and tool.stage == "axis":
            tool.set_axis(event.type)
        elif event.value == "PRESS" and event.type == "S":
            tool.toggle_symmetry()
        elif event.value == "PRESS" and event.type == "BACK_SPACE":
            if tool.back():
                write_positions(bpy.data.objects[self.obj_name], self.flat)
        elif event.value in CLICK and event.type in {"LEFTMOUSE", "RET", "NUMPAD_ENTER"}:
            if tool.stage == "axis":
                tool.fix_axis(viewport.region_mouse(self.view, event)[0])
            else:
                return self._commit(context)
        elif event.type != "MOUSEMOVE":
            return {"RUNNING_MODAL"}
        self._update(context, event)
        return {"RUNNING_MODAL"}

    def _commit(self, context) -> set:
        self._finish(context, {"FINISHED"}, restore=True)
        for name, value in self.tool.params().operator_kwargs().items():
            setattr(self, name, value)
        return self.execute(context)


classes = (TAILOR_OT_bend_interactive,)
