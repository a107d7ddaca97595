"""The manual seam tool (paper Sec. 4): pick a1, an on piece A's contour, then b1 and bn on
piece B's, with the shortest path and the nearer n-vertex path shown while hovering. The logic
is `core.seam_tools.ManualSeamTool`; the loop, drawing and commit are `modal_base`."""

from __future__ import annotations

import bpy

from ..core.seam_tools import ManualSeamTool
from . import viewport
from .modal_base import ContourToolModal
from .operators import SeamAddProperties


class TAILOR_OT_seam_pick(ContourToolModal, SeamAddProperties, bpy.types.Operator):
    bl_idname = "tailor.seam_pick"
    bl_label = "Manual Seam"
    bl_description = (
        "Sew by picking in the viewport: click a1 and an on one piece's contour, then b1 and bn on "
        "another's (the path towards the cursor is shown); Backspace undoes a pick, Esc cancels"
    )
    what = "Picking the seam"

    def make_tool(self, context):
        return ManualSeamTool(viewport.mesh_for)


classes = (TAILOR_OT_seam_pick,)
