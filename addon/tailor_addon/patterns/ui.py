"""The Patterns panel and the File > Import and File > Export entries."""

import bpy

from .. import scene_data
from ..compat import export_menu, import_menu
from ..ui_common import TailorPanel


class TAILOR_PT_patterns(TailorPanel, bpy.types.Panel):
    bl_idname = "TAILOR_PT_patterns"
    bl_label = "Patterns"
    bl_order = 0

    def draw(self, context):
        layout = self.layout
        row = layout.row(align=True)
        row.operator("tailor.import_pattern", text="Import Pattern…", icon="IMPORT")
        row.operator("tailor.export_garment", text="Export…", icon="EXPORT")
        obj = context.active_object
        if not scene_data.is_piece(obj):
            layout.label(text="Select a garment piece", icon="INFO")
            return
        p = obj.tailor_piece
        box = layout.box()
        box.label(text=p.piece_name or obj.name, icon="MESH_DATA")
        col = box.column(align=True)
        col.label(text=f"Garment: {p.garment}")
        col.label(text=f"{len(obj.data.vertices)} vertices, {len(obj.data.polygons)} triangles")
        row = box.row(align=True)
        row.label(text=f"Resolution: {p.edge_length * 100:.3g} cm")
        row.operator("tailor.set_resolution", text="Set…", icon="MOD_TRIANGULATE")
        pieces = scene_data.piece_objects(context.scene, p.garment)
        if len(pieces) > 1:
            col = box.column(align=True)
            col.label(text=f"{len(pieces)} pieces in {p.garment}:")
            for o in pieces:
                r = col.row()
                r.label(text=o.name, icon="RADIOBUT_ON" if o == obj else "RADIOBUT_OFF")
                r.label(text=f"{len(o.data.vertices)} v, {o.tailor_piece.edge_length * 100:.3g} cm")
        col = box.column(align=True)
        col.label(text="Fabric")
        col.prop(p, "fabric", text="")
        col.prop(p, "density")
        col.prop(p, "stretch")
        col.prop(p, "shear")
        col.prop(p, "bend")
        col.prop(p, "anisotropic")
        if p.anisotropic:
            for name in ("stretch_v", "bend_bias", "bend_v"):
                col.prop(p, name)


def menu_import(self, context):
    self.layout.operator("tailor.import_pattern", text="Sewing Pattern (.dxf, .svg, .json)")
    self.layout.operator("tailor.import_garment", text="Tailor Garment (.json)")


def menu_export(self, context):
    self.layout.operator("tailor.export_garment", text="Tailor Garment (.json)")
    self.layout.operator("tailor.export_welded", text="Tailor Welded Garment (.obj)").export_format = "OBJ"
    self.layout.operator("tailor.export_welded", text="Tailor Welded Garment (.glb)").export_format = "GLB"


classes = (TAILOR_PT_patterns,)


def register() -> None:
    import_menu().append(menu_import)
    export_menu().append(menu_export)


def unregister() -> None:
    export_menu().remove(menu_export)
    import_menu().remove(menu_import)
