"""Object > Tailor: every Tailor operator in a menu, so that F3 (menu search) finds them all
without Developer Extras, and so the workflow can also be driven from the menus."""

import bpy

# (idname, label) in workflow order; tests check that every registered Tailor operator is here.
OPERATORS = (
    ("tailor.import_pattern", "Import Sewing Pattern…"),
    ("tailor.import_garment", "Import Tailor Garment…"),
    ("tailor.set_resolution", "Set Piece Resolution…"),
    ("tailor.export_garment", "Export Tailor Garment…"),
    None,
    ("tailor.seam_add", "Add Seam"),
    ("tailor.seam_add_segments", "Add Seam Between Segments"),
    ("tailor.seam_flip", "Flip Seam"),
    ("tailor.seam_rename", "Rename Seam…"),
    ("tailor.seam_remove", "Delete Seam"),
    ("tailor.seams_update", "Check Seams"),
    None,
    ("tailor.bend", "Bend Piece"),
    None,
    ("tailor.paint_set", "Set Painted Value"),
    ("tailor.paint_weights", "Weight Paint Map"),
    ("tailor.collision_level_set", "Set Collision Level"),
    ("tailor.collision_level_paint", "Paint Collision Level…"),
    ("tailor.paint_clear", "Clear Painted Map"),
)

# Operators added by other parts (Simulate, interactive tools) register here too.
EXTRA: list[tuple[str, str]] = []


class TAILOR_MT_object(bpy.types.Menu):
    bl_idname = "TAILOR_MT_object"
    bl_label = "Tailor"

    def draw(self, context):
        layout = self.layout
        for entry in (*OPERATORS, *((None,) if EXTRA else ()), *EXTRA):
            if entry is None:
                layout.separator()
            else:
                layout.operator(entry[0], text=entry[1])


def menu_object(self, context):
    self.layout.menu(TAILOR_MT_object.bl_idname)


classes = (TAILOR_MT_object,)


def register() -> None:
    bpy.types.VIEW3D_MT_object.append(menu_object)


def unregister() -> None:
    bpy.types.VIEW3D_MT_object.remove(menu_object)
