"""The Bend panel's interactive tool (a sub-panel, so the Bend panel stays as it is)."""

from __future__ import annotations

import bpy

from .. import scene_data
from ..ui_common import TailorPanel


class TAILOR_PT_bend_viewport(TailorPanel, bpy.types.Panel):
    bl_idname = "TAILOR_PT_bend_viewport"
    bl_label = "Bend in the Viewport"
    bl_parent_id = "TAILOR_PT_bend"
    bl_order = 100  # among the Bend panel's sub-panels

    @classmethod
    def poll(cls, context):
        return scene_data.is_piece(context.active_object)

    def draw(self, context):
        self.layout.operator("tailor.bend_interactive", text="Place Axis and Drag", icon="ORIENTATION_GIMBAL")


classes = (TAILOR_PT_bend_viewport,)
