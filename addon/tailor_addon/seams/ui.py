"""The Seams panel: the scene's seam list and the active seam's settings."""

import bpy

from ..ui_common import TailorPanel


class TAILOR_UL_seams(bpy.types.UIList):
    bl_idname = "TAILOR_UL_seams"

    def draw_item(self, context, layout, data, item, icon, active_data, active_property, index=0, flt_flag=0):
        row = layout.row(align=True)
        row.prop(item, "color", text="")
        row.prop(item, "name", text="", emboss=False)
        broken = item.piece_a is None or item.piece_b is None
        if broken:
            row.label(text="piece missing", icon="ERROR")
        else:
            mode = "=" if item.mode == "EQUAL" else "≠"
            row.label(text=f"{item.a_count} {mode} {item.b_count}")
        row.prop(item, "show", text="", icon="HIDE_OFF" if item.show else "HIDE_ON", emboss=False)


class TAILOR_PT_seams(TailorPanel, bpy.types.Panel):
    bl_idname = "TAILOR_PT_seams"
    bl_label = "Seams"
    bl_order = 1

    def draw(self, context):
        layout = self.layout
        settings = context.scene.tailor
        row = layout.row()
        row.template_list("TAILOR_UL_seams", "", settings, "seams", settings, "seam_index", rows=4)
        col = row.column(align=True)
        col.operator("tailor.seam_remove", text="", icon="REMOVE")
        col.separator()
        col.operator("tailor.seam_flip", text="", icon="ARROW_LEFTRIGHT")
        col.operator("tailor.seam_rename", text="", icon="GREASEPENCIL")
        col.separator()
        col.operator("tailor.seams_update", text="", icon="FILE_REFRESH")
        row = layout.row()
        row.prop(settings, "show_seams")
        row.prop(settings, "corner_angle")
        if not (0 <= settings.seam_index < len(settings.seams)):
            return
        seam = settings.seams[settings.seam_index]
        box = layout.box()
        box.prop(seam, "name")
        col = box.column(align=True)
        col.label(text=f"A: {seam.piece_a.name if seam.piece_a else '(missing)'} ({seam.a_count} vertices)")
        col.label(text=f"B: {seam.piece_b.name if seam.piece_b else '(missing)'} ({seam.b_count} vertices)")
        row = box.row()
        row.prop(seam, "mode", expand=True)
        if seam.mode == "EQUAL" and seam.a_count != seam.b_count:
            box.label(text="Equal mode needs sides of equal counts: use Unequal", icon="ERROR")
        box.prop(seam, "stiffness")
        box.prop(seam, "bend_stiffness")


classes = (TAILOR_UL_seams, TAILOR_PT_seams)
