"""Bend: wrap a flat piece around an axis with `tailor.bend` (operator with a redo panel),
interactively in the viewport (axis placed, angle dragged with a live preview: `gizmo.py`), and
with the bend gizmo (a `GizmoGroup`: `gizmo_group.py`, its drags `gizmo_drag.py`)."""

from . import gizmo, gizmo_drag, gizmo_group, operators, tools_ui, ui

classes = (operators.classes + gizmo.classes + gizmo_drag.classes + gizmo_group.classes + ui.classes
           + tools_ui.classes)


TOOLS_MENU = [("tailor.bend_interactive", "Bend in Viewport")]


def register() -> None:
    import bpy

    from .. import menu

    menu.EXTRA.extend(e for e in TOOLS_MENU if e not in menu.EXTRA)
    bpy.types.WindowManager.tailor_bend_gizmo = bpy.props.BoolProperty(
        name="Bend Gizmo",
        description="Show the bend gizmo on the active piece: drag its axis (red), angle dial (yellow) "
        "and radius arrow (cyan)",
        default=False,
    )


def unregister() -> None:
    import bpy

    from .. import menu

    menu.EXTRA[:] = [e for e in menu.EXTRA if e not in TOOLS_MENU]
    del bpy.types.WindowManager.tailor_bend_gizmo
