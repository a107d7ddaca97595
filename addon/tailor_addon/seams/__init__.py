"""Seams: the scene-level seam list, its operators (create from picked contour positions,
rename, flip, delete, check), the interactive tools (manual picking, automatic suggestion)
and the viewport drawing of seams."""

from . import draw, modal_pick, modal_suggest, operators, properties, tools_ui, ui

classes = properties.classes + operators.classes + modal_pick.classes + modal_suggest.classes + ui.classes
classes += tools_ui.classes


TOOLS_MENU = [("tailor.seam_pick", "Manual Seam (Viewport)"), ("tailor.seam_suggest", "Suggest Seam (Viewport)")]


def register() -> None:
    from .. import menu

    properties.register()
    draw.register()
    menu.EXTRA.extend(e for e in TOOLS_MENU if e not in menu.EXTRA)


def unregister() -> None:
    from .. import menu

    menu.EXTRA[:] = [e for e in menu.EXTRA if e not in TOOLS_MENU]
    draw.unregister()
    properties.unregister()
