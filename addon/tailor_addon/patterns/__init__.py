"""Patterns: import DXF, SVG and GarmentCode JSON as piece objects; change a piece's resolution;
export the garment as a Tailor garment file and import one back."""

from . import import_garment, operators, properties, ui

classes = properties.classes + operators.classes + import_garment.classes + ui.classes


def register() -> None:
    properties.register()
    ui.register()


def unregister() -> None:
    ui.unregister()
    properties.unregister()
