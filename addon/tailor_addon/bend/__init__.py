"""Bend: wrap a flat piece around an axis with `tailor.bend` (operator with a redo panel)."""

from . import operators, ui

classes = operators.classes + ui.classes


def register() -> None:
    pass


def unregister() -> None:
    pass
