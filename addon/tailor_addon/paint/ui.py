"""The Paint panel: what is painted on the active mesh, with set, paint and clear buttons."""

import bpy
import numpy as np

from ..core.paint import WEIGHT_MAPS
from ..ui_common import TailorPanel
from . import maps


class TAILOR_PT_paint(TailorPanel, bpy.types.Panel):
    bl_idname = "TAILOR_PT_paint"
    bl_label = "Paint"
    bl_order = 4

    def draw(self, context):
        layout = self.layout
        obj = context.active_object
        if obj is None or obj.type != "MESH":
            layout.label(text="Select a garment piece or the character", icon="INFO")
            return
        editing = obj.mode == "EDIT"
        layout.label(text="Set on the selection (Edit Mode)" if editing else "Set on all vertices", icon="INFO")
        col = layout.column(align=True)
        for m in WEIGHT_MAPS:
            vg = obj.vertex_groups.get(m.group)
            row = col.row(align=True)
            row.label(text=m.label + (f": {_painted_count(obj, vg)} vertices" if vg else ": not painted"))
            op = row.operator("tailor.paint_set", text="", icon="CHECKMARK")
            op.map = m.key.upper()
            row.operator("tailor.paint_weights", text="", icon="BRUSH_DATA").map = m.key.upper()
            if vg:
                row.operator("tailor.paint_clear", text="", icon="X").map = m.key.upper()
        box = layout.box()
        levels = None if editing else maps.collision_levels(obj)
        row = box.row(align=True)
        if levels is None:
            row.label(text="Collision levels: " + ("(leave Edit Mode to list)" if editing else "none"))
        else:
            values, counts = np.unique(levels, return_counts=True)
            row.label(text="Collision levels: " + ", ".join(f"{v} ×{c}" for v, c in zip(values, counts)))
            row.operator("tailor.paint_clear", text="", icon="X").map = "COLLISION_LEVEL"
        row = box.row(align=True)
        row.operator("tailor.collision_level_set", icon="MOD_PHYSICS")
        row.operator("tailor.collision_level_paint", text="Paint Level", icon="BRUSH_DATA")
        for level, name in sorted(maps.level_groups(obj).items()):
            row = box.row(align=True)
            row.label(text=f"Level {level}: painted ({name})")
            row.operator("tailor.collision_level_paint", text="", icon="BRUSH_DATA").level = level
        box.prop(context.scene.tailor, "show_collision_levels")


def _painted_count(obj, vg) -> int:
    if obj.mode == "EDIT":
        return 0
    gi = vg.index
    return sum(1 for v in obj.data.vertices for g in v.groups if g.group == gi)


classes = (TAILOR_PT_paint,)
