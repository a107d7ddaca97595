"""Patterns: import DXF, SVG and GarmentCode JSON as piece objects; change a piece's resolution."""

from . import operators, properties, ui

classes = properties.classes + operators.classes + ui.classes


def register() -> None:
    properties.register()
    ui.register()


def unregister() -> None:
    ui.unregister()
    properties.unregister()
