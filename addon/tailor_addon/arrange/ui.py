"""The Arrange panel: the active piece's place, Arrange on Body, Show Places."""

import bpy

from .. import scene_data
from ..ui_common import TailorPanel


class TAILOR_PT_arrange(TailorPanel, bpy.types.Panel):
    bl_idname = "TAILOR_PT_arrange"
    bl_label = "Arrange"
    bl_order = 2

    def draw(self, context):
        layout = self.layout
        obj = context.active_object
        if scene_data.is_piece(obj):
            p = obj.tailor_piece
            layout.prop(p, "place")
            if p.arranged_place:
                layout.label(text=f"Arranged on: {p.arranged_place.replace('_', ' ')}")
        else:
            layout.label(text="Select a piece to choose its place", icon="INFO")
        layout.operator("tailor.arrange_on_body", icon="ARMATURE_DATA")
        layout.prop(context.window_manager, "tailor_show_places", text="Show Places", icon="EMPTY_SINGLE_ARROW")


classes = (TAILOR_PT_arrange,)
