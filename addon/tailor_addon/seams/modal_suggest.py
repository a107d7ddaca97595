"""The automatic seam suggestion (paper Sec. 4, Fig. 3): hovering a piece lights up the
corner-delimited contour run nearest the cursor (corners under the Seams panel's corner angle);
click it, then its partner, and the seam is sewn equal or unequal as the vertex counts say.
The logic is `core.seam_tools.SuggestSeamTool`; the loop, drawing and commit are `modal_base`."""

from __future__ import annotations

import math

import bpy

from ..core.seam_tools import SuggestSeamTool
from . import viewport
from .modal_base import ContourToolModal
from .operators import SeamAddProperties


class TAILOR_OT_seam_suggest(ContourToolModal, SeamAddProperties, bpy.types.Operator):
    bl_idname = "tailor.seam_suggest"
    bl_label = "Suggest Seam"
    bl_description = (
        "Sew corner-to-corner contour segments: hover a piece to see the segment nearest the cursor, click "
        "it, then click its partner (corners: the Seams panel's corner angle); Esc cancels"
    )
    what = "Suggesting the seam"

    def make_tool(self, context):
        return SuggestSeamTool(viewport.mesh_for, viewport.locate, math.degrees(context.scene.tailor.corner_angle))

    def prompt_text(self) -> str:
        piece, point = self.hovered
        hovered = None
        if piece is not None:
            segment = self.tool.segment(piece, point)
            hovered = (piece, segment) if segment is not None else None
        return self.tool.prompt(hovered)


classes = (TAILOR_OT_seam_suggest,)
