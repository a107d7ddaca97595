"""The modal loop shared by the interactive seam tools (manual picking, suggestion).

A tool (`core.seam_tools.ManualSeamTool` or `SuggestSeamTool`) holds the picks and says what a
hover shows and what a click does; this loop feeds it the piece and rest point under the mouse
(`viewport.pick`), draws its highlight, shows its prompt in the 3D view's header and the status
bar, and when a click completes a seam sews it through Add Seam's exec path: the tools share
`tailor.seam_add`'s properties and `execute` (`SeamAddProperties`), set those properties to the
picked contour positions and run that `execute` (the same checks and errors). The finished tool
is one undo step whose redo panel is Add Seam's; a nested `bpy.ops.tailor.seam_add` call would
not do, as Blender neither registers nor pushes an operator called inside an undoable modal one.

Keys: left click picks, Backspace undoes the last pick, Esc or right click cancels (nothing is
changed); navigation (middle mouse, wheel, numpad, trackpad) passes through to the view.
"""

from __future__ import annotations

import bpy

from .. import scene_data
from ..core.errors import is_reportable
from ..reporting import report
from . import viewport

NAVIGATION = {
    "MIDDLEMOUSE",
    "WHEELUPMOUSE",
    "WHEELDOWNMOUSE",
    "TRACKPADPAN",
    "TRACKPADZOOM",
    "MOUSEROTATE",
    "NDOF_MOTION",
    *(f"NUMPAD_{k}" for k in ("0", "1", "2", "3", "4", "5", "6", "7", "8", "9", "PERIOD", "PLUS", "MINUS")),
}

# A quick second click arrives as DOUBLE_CLICK instead of PRESS; it is a pick all the same.
CLICK = {"PRESS", "DOUBLE_CLICK"}


class ContourToolModal:
    """Mixin (before `SeamAddProperties`) for a modal seam tool; subclasses define
    `make_tool(context)` and `what`."""

    bl_options = {"REGISTER", "UNDO", "BLOCKING"}
    what = "Picking the seam"

    @classmethod
    def poll(cls, context):
        return viewport.window_region(context) is not None and any(
            scene_data.is_piece(o) for o in context.scene.objects
        )

    def make_tool(self, context):
        raise NotImplementedError

    def invoke(self, context, event):
        view = viewport.window_region(context)
        if view is None:
            self.report({"ERROR"}, f"{self.bl_label} works in a 3D View: start it from the Tailor sidebar there")
            return {"CANCELLED"}
        self.view = view
        self.tool = self.make_tool(context)
        self.hovered = (None, None)
        self.message = ""
        self.batches = []
        self._handle = bpy.types.SpaceView3D.draw_handler_add(self._draw, (), "WINDOW", "POST_VIEW")
        context.window_manager.modal_handler_add(self)
        self._hover(context, event)
        return {"RUNNING_MODAL"}

    def _draw(self) -> None:
        viewport.draw_batches(self.batches)

    def _refresh(self, context) -> None:
        piece, point = self.hovered
        self.batches = viewport.highlight_batches(self.tool.highlight(piece, point))
        text = self.prompt_text()
        viewport.set_header(context, self.view, f"{text} · {self.message}" if self.message else text)
        self.view[0].tag_redraw()

    def prompt_text(self) -> str:
        return self.tool.prompt()

    def _hover(self, context, event) -> None:
        self.hovered = viewport.pick(context, self.view, viewport.region_mouse(self.view, event))
        self._refresh(context)

    def _finish(self, context, result: set) -> set:
        if self._handle is not None:
            bpy.types.SpaceView3D.draw_handler_remove(self._handle, "WINDOW")
            self._handle = None
        viewport.set_header(context, self.view, None)
        self.view[0].tag_redraw()
        return result

    def cancel(self, context):
        """Blender ends the modal (file load, window closed): remove the handler."""
        self._finish(context, {"CANCELLED"})

    def modal(self, context, event):
        try:
            return self._modal(context, event)
        except Exception as exc:
            if not is_reportable(exc):
                self._finish(context, {"CANCELLED"})
                raise
            report(self, exc, self.what)
            return self._finish(context, {"CANCELLED"})

    def _modal(self, context, event):
        if event.type in NAVIGATION:
            return {"PASS_THROUGH"}
        if event.type in {"ESC", "RIGHTMOUSE"} and event.value == "PRESS":
            return self._finish(context, {"CANCELLED"})
        if event.type == "MOUSEMOVE":
            self._hover(context, event)
        elif event.type == "BACK_SPACE" and event.value == "PRESS":
            self.message = "" if self.tool.undo() else "nothing to undo"
            self._hover(context, event)
        elif event.type == "LEFTMOUSE" and event.value in CLICK:
            self._hover(context, event)
            piece, point = self.hovered
            result = self.tool.click(piece, point)
            self.message = result.message
            if result.request is not None:
                return self._commit(context, result.request)
            self._refresh(context)
        return {"RUNNING_MODAL"}

    def _commit(self, context, request) -> set:
        """Sews the picked sides through Add Seam's exec path; on an error (reported by it)
        the last pick is undone so the artist can pick it again."""
        for name, value in request.operator_kwargs().items():
            setattr(self, name, value)
        done = self.execute(context)
        if "FINISHED" in done:
            return self._finish(context, {"FINISHED"})
        self.tool.undo()
        self.message = "the seam was refused (see the status bar): pick again"
        self._refresh(context)
        return {"RUNNING_MODAL"}
