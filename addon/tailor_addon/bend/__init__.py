"""Bend: wrap a flat piece around an axis with `tailor.bend` (operator with a redo panel),
and interactively in the viewport (axis placed, angle dragged with a live preview)."""

from . import gizmo, operators, tools_ui, ui

classes = operators.classes + gizmo.classes + ui.classes + tools_ui.classes


TOOLS_MENU = [("tailor.bend_interactive", "Bend in Viewport")]


def register() -> None:
    from .. import menu

    menu.EXTRA.extend(e for e in TOOLS_MENU if e not in menu.EXTRA)


def unregister() -> None:
    from .. import menu

    menu.EXTRA[:] = [e for e in menu.EXTRA if e not in TOOLS_MENU]
