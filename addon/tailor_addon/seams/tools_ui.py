"""The Seams panel's interactive tools: manual picking and automatic suggestion (a sub-panel,
so the seam list's panel stays as it is)."""

from __future__ import annotations

import bpy

from ..ui_common import TailorPanel


class TAILOR_PT_seam_tools(TailorPanel, bpy.types.Panel):
    bl_idname = "TAILOR_PT_seam_tools"
    bl_label = "Sew in the Viewport"
    bl_parent_id = "TAILOR_PT_seams"
    bl_order = 100  # among the Seams panel's sub-panels

    def draw(self, context):
        layout = self.layout
        row = layout.row(align=True)
        row.operator("tailor.seam_pick", text="Manual Seam", icon="CURVE_PATH")
        row.operator("tailor.seam_suggest", text="Suggest Seam", icon="SNAP_EDGE")
        layout.prop(context.scene.tailor, "corner_angle")
        layout.label(text="Unequal vertex counts are sewn in Unequal mode", icon="INFO")


classes = (TAILOR_PT_seam_tools,)
