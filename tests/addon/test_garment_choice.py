"""The Simulate panel's garment is chosen from the scene's garments (a drop-down), stored as the
name it always was."""

from __future__ import annotations

import bpy

from conftest import DATA, import_pattern

SKIRT_SVG = DATA / "svg/skirt_two_panels.svg"


class RecordingLayout:
    """Stands in for `UILayout` in a panel's `draw`: records the properties drawn."""

    def __init__(self, drawn):
        self.drawn = drawn

    def prop(self, data, name, **_kw):
        self.drawn.append(name)

    def row(self, **_kw):
        return self

    def operator(self, *_a, **_kw):
        return None

    def label(self, **_kw):
        return None


def test_the_garment_is_chosen_from_the_scenes_garments(scene, addon):
    pieces = import_pattern(SKIRT_SVG, edge_length=0.08)
    first, second = pieces[0], pieces[1]
    first.tailor_piece.garment, second.tailor_piece.garment = "skirt", "top"
    s = scene.tailor_simulate
    choices = [ident for ident, *_ in addon.simulate.garment_choice.items_for(scene, s.garment)]
    assert choices == ["*", "skirt", "top"]
    assert s.garment == "" and s.garment_choice == "*"
    s.garment_choice = "top"
    assert s.garment == "top"
    assert [o.name for o in addon.scene_data.piece_objects(scene, s.garment)] == [second.name]
    s.garment_choice = "*"
    assert s.garment == ""
    # A stored name no piece carries is listed as such, not silently taken for every piece.
    s.garment = "dress"
    assert s.garment_choice == "dress"
    labels = {ident: label for ident, label, *_ in addon.simulate.garment_choice.items_for(scene, s.garment)}
    assert labels["dress"] == "dress (no pieces)"
    # The panel offers the drop-down, not a text field.
    drawn = []

    class Panel:
        layout = RecordingLayout(drawn)

    addon.simulate.ui.TAILOR_PT_simulate.draw(Panel(), bpy.context)
    assert "garment_choice" in drawn and "garment" not in drawn
