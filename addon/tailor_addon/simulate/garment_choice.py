"""The Simulate panel's garment, chosen from the garments the scene holds (a drop-down, as
Blender offers existing data) rather than typed: `TailorSimulateSettings.garment_choice`, an enum
whose items are the scene's garments, stored in the `garment` string it has always been (files
keep their choice; scripts and operators still set the name).

A garment is the pieces sharing `Object.tailor_piece.garment` (the collection they were imported
into). A stored name no piece carries any more is still listed, marked, so the panel shows what
the bake would refuse rather than quietly falling back to every piece.
"""

from __future__ import annotations

from .. import scene_data

#: The item meaning every piece of the scene (stored as the empty name).
ALL = "*"

# Blender keeps only pointers to an enum's item strings: they must outlive the callback.
_ITEMS: list[tuple[str, str, str, int]] = []


def garment_names(scene) -> list[str]:
    """The garments of the scene's pieces, sorted."""
    return sorted({o.tailor_piece.garment for o in scene_data.piece_objects(scene)} - {""})


def items_for(scene, stored: str) -> list[tuple[str, str, str, int]]:
    """(identifier, label, description, number) of every choice: all pieces, then each garment,
    then the stored name if no piece carries it."""
    names = garment_names(scene)
    out = [(ALL, "All Pieces", "Every garment piece of the scene", 0)]
    out += [(n, n, f"The pieces of garment '{n}'", i + 1) for i, n in enumerate(names)]
    if stored and stored not in names:
        out.append((stored, f"{stored} (no pieces)", f"No piece belongs to '{stored}' any more", len(out)))
    return out


def items(self, _context):
    _ITEMS[:] = items_for(self.id_data, self.garment)
    return _ITEMS


def get_number(self) -> int:
    stored = self.garment or ALL
    for ident, _, _, number in items_for(self.id_data, self.garment):
        if ident == stored:
            return number
    return 0


def set_number(self, number: int) -> None:
    for ident, _, _, n in items_for(self.id_data, self.garment):
        if n == number:
            self.garment = "" if ident == ALL else ident
            return

