"""The Bend panel."""

import math

import bpy

from .. import scene_data
from ..ui_common import TailorPanel


class TAILOR_PT_bend(TailorPanel, bpy.types.Panel):
    bl_idname = "TAILOR_PT_bend"
    bl_label = "Bend"
    bl_order = 3

    def draw(self, context):
        layout = self.layout
        obj = context.active_object
        if not scene_data.is_piece(obj):
            layout.label(text="Select a garment piece", icon="INFO")
            return
        p = obj.tailor_piece
        if p.bend_angle:
            how = f"radius {p.bend_radius * 100:.1f} cm" if p.bend_radius > 0.0 else f"{math.degrees(p.bend_angle):.0f}°"
            cone = f", taper {math.degrees(p.bend_taper):.1f}°" if p.bend_taper else ""
            layout.label(text=f"Bent by {how}{cone}" + (" (symmetric)" if p.bend_symmetry else ""))
        else:
            layout.label(text="Flat")
        row = layout.row(align=True)
        row.operator("tailor.bend", text="Bend…", icon="MOD_SIMPLEDEFORM")
        flat = row.operator("tailor.bend", text="Flatten", icon="MESH_PLANE")
        flat.angle = 0.0
        layout.prop(context.window_manager, "tailor_bend_gizmo", text="Gizmo", icon="GIZMO")


classes = (TAILOR_PT_bend,)
