"""Seams: the scene-level seam list, its operators (create from picked contour positions,
rename, flip, delete, check) and the viewport drawing of seams."""

from . import draw, operators, properties, ui

classes = properties.classes + operators.classes + ui.classes


def register() -> None:
    properties.register()
    draw.register()


def unregister() -> None:
    draw.unregister()
    properties.unregister()
