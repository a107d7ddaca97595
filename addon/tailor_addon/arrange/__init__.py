"""Arrange on Body (issue 25): the garment's pieces put round the collider body.

- `operators.py`: Arrange on Body (`tailor.arrange_on_body`), the places found on the collider
  (`tailor.body_places`) and each piece put on its own (`core/arrange.py`);
- `ui.py`: the Arrange panel (the active piece's place, the operator, Show Places);
- `draw.py`: the body's places drawn in the viewport (each axis a line) while Show Places is on.

Each piece's chosen place is `Object.tailor_piece.place` (patterns/properties.py).
"""

from . import draw, operators, ui

classes = operators.classes + ui.classes

#: Object > Tailor menu entries (menu.EXTRA).
MENU = (("tailor.arrange_on_body", "Arrange on Body"),)


def register() -> None:
    import bpy

    from .. import menu

    menu.EXTRA.extend(e for e in MENU if e not in menu.EXTRA)
    bpy.types.WindowManager.tailor_show_places = bpy.props.BoolProperty(
        name="Show Places",
        description="Draw the collider body's places (where Arrange on Body puts pieces) in the viewport",
        default=False,
        update=draw.on_toggle,
    )
    draw.register()


def unregister() -> None:
    import bpy

    from .. import menu

    draw.unregister()
    menu.EXTRA[:] = [e for e in menu.EXTRA if e not in MENU]
    del bpy.types.WindowManager.tailor_show_places
