"""Paint: friction, mass scale and pin weight as vertex groups, collision levels as an integer
attribute (on pieces and colliders), a colour overlay for the levels, and a panel listing what
is painted."""

from . import draw, maps, operators, transfer, ui  # noqa: F401

classes = operators.classes + ui.classes


def register() -> None:
    draw.register()


def unregister() -> None:
    draw.unregister()
