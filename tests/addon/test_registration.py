"""Every operator has a tooltip, a menu entry (F3 finds it) and Blender's undo/redo conventions;
panels sit in the Tailor tab."""

import bpy

from conftest import MODULE


def addon_classes(addon, base):
    import inspect
    import sys

    out = []
    for name, mod in list(sys.modules.items()):
        if name.startswith(MODULE) and mod is not None:
            out += [
                c for _, c in inspect.getmembers(mod, inspect.isclass) if issubclass(c, base) and c.__module__ == name
            ]
    return set(out)


#: Operators that run a simulation: no redo panel (Adjust Last Operation would run it again).
NO_REDO = {"tailor.bake", "tailor.live", "tailor.live_step", "tailor.live_stop"}
#: File exporters: they change no data, so they push no undo step (as Blender's exporters).
EXPORTERS = {"tailor.export_garment"}


def test_operators_have_tooltips_undo_and_a_menu_entry(addon):
    ops = addon_classes(addon, bpy.types.Operator)
    assert len(ops) >= 12
    assert NO_REDO | EXPORTERS <= {op.bl_idname for op in ops}
    in_menu = {e[0] for e in (*addon.menu.OPERATORS, *addon.menu.EXTRA) if e}
    for op in ops:
        assert op.bl_description and len(op.bl_description) > 20, op
        options = set(op.bl_options)
        if op.bl_idname in EXPORTERS:
            assert "UNDO" not in options, op.bl_idname
        elif op.bl_idname in NO_REDO:
            assert "REGISTER" not in options and "UNDO" in options, (op.bl_idname, options)
        else:
            assert {"REGISTER", "UNDO"} <= options, op.bl_idname
        # An operator only a gizmo starts (INTERNAL: not in menus or search) has no menu entry.
        assert op.bl_idname in in_menu or "INTERNAL" in options, op.bl_idname
        assert hasattr(bpy.types, op.__name__), f"{op.__name__} is not registered"
    assert addon.menu.menu_object in bpy.types.VIEW3D_MT_object._dyn_ui_initialize()


def test_panels_in_the_tailor_tab_in_workflow_order(addon):
    panels = sorted(addon_classes(addon, bpy.types.Panel), key=lambda p: p.bl_order)
    assert [p.bl_label for p in panels][:5] == ["Patterns", "Seams", "Arrange", "Bend", "Paint"]
    assert all(p.bl_category == "Tailor" and p.bl_space_type == "VIEW_3D" for p in panels)
