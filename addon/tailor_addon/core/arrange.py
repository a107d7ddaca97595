"""Arrange on Body (issue 25), bpy-free: each piece put on a place of the collider body.

The add-on's counterpart of `tailor.arrange.arrange_garment` for pieces read out of a scene:
the body's places (`tailor.body_places`), a plan (per piece `tailor.suggest_place` of its name
and rest shape, or the place the artist chose, `AUTO` meaning the suggestion), and the pieces
put on their places by the module's own rule (`tailor.arrange.place_pieces`: the pieces round
one axis rolled to the largest of their radii), as its `arrange_garment` does. The positions come back in the body's frame
(world space in the add-on); the Blender layer writes them into the piece meshes.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

import tailor
from tailor.arrange import grain_direction, place_pieces

from .errors import AddonError

#: The piece setting's value for "the place `tailor.suggest_place` gives".
AUTO = "AUTO"
#: The module's default clearance (`tailor.place_on_body`, `arrange_garment`), metres.
CLEARANCE = 0.03

_LABELS = {
    "torso_front": ("Torso Front", "The front of the torso, from the neck down"),
    "torso_back": ("Torso Back", "The back of the torso, from the neck down"),
    "waist": ("Waist", "Round the waist, from the waist down (skirts, waistbands)"),
    "neck": ("Neck", "Round the neck, from its base up (collars)"),
    "head": ("Head", "Over the head, from the neck's base up (hoods)"),
    "left_arm": ("Left Arm", "Along the body's left arm, from the shoulder"),
    "right_arm": ("Right Arm", "Along the body's right arm, from the shoulder"),
    "left_leg": ("Left Leg", "Along the body's left leg, from the waist"),
    "right_leg": ("Right Leg", "Along the body's right leg, from the waist"),
}


def place_items() -> list[tuple[str, str, str]]:
    """EnumProperty items: AUTO, then every `tailor.PLACE_NAMES` entry (its identifier is the
    module's name)."""
    items = [(AUTO, "Auto", "The place the piece's name and shape suggest (tailor.suggest_places)")]
    for name in tailor.PLACE_NAMES:
        label, desc = _LABELS.get(name, (name.replace("_", " ").title(), f"The body's place '{name}'"))
        items.append((name, label, desc))
    return items


@dataclass
class ArrangedPiece:
    """Where one piece went: its plan entry (place, side, around_deg, along, radius) and its
    positions ((n, 3), the body's frame)."""

    name: str
    entry: dict[str, Any]
    positions: np.ndarray


def plan_entry(
    name: str, rest: np.ndarray, choice: str = AUTO, suggested: dict[str, Any] | None = None
) -> dict[str, Any]:
    """Where piece `name` with rest shape `rest` goes: `suggested` (what `tailor.suggest_places`
    said of it among the pattern's pieces; else `tailor.suggest_place` of it alone), or with
    `choice` (a place name) that place, as `tailor.suggest_place(..., place=choice)` puts it (the
    suggestion's turn kept, a limb's longest direction and no half side, a band's shortest)."""
    entry = dict(suggested if suggested is not None else tailor.suggest_place(name, np.asarray(rest, np.float32)))
    if choice and choice != AUTO and choice != entry["place"]:
        if choice not in tailor.PLACE_NAMES:
            raise AddonError(f"piece '{name}': no place '{choice}'", f"Pick one of {', '.join(tailor.PLACE_NAMES)}")
        entry = dict(tailor.suggest_place(name, np.asarray(rest, np.float32), place=choice))
    entry["name"] = name
    return entry


def find_places(vertices, triangles, body: str = "the collider", up: str = "z") -> list[dict[str, Any]]:
    """`tailor.body_places` of a body mesh (world space, Z up in Blender), its failure (not a
    standing humanoid) an `AddonError` naming `body` and saying what to do."""
    v = np.ascontiguousarray(vertices, np.float32).reshape(-1, 3)
    t = np.ascontiguousarray(triangles, np.int32).reshape(-1, 3)
    if len(v) == 0 or len(t) == 0:
        raise AddonError(f"the collider '{body}' has no faces", "Mark a body mesh as the collider")
    try:
        return tailor.body_places(v, t, up=up)
    except tailor.InvalidMeshError as exc:
        raise AddonError(
            f"the collider '{body}' is {str(exc).strip().rstrip('.')}",
            "Mark a standing humanoid body (Z up, feet on the ground) as the collider",
        ) from exc


def grain_of(piece_json: str) -> tuple[float, float] | None:
    """The grain line's direction of a piece stored as JSON (`tailor_piece.piece_json`), None
    when it has none or nothing is stored."""
    if not piece_json:
        return None
    return grain_direction(tailor.Piece.from_json(piece_json))


def arrange(
    names: Sequence[str],
    rests: Sequence[np.ndarray],
    places: Sequence[dict[str, Any]],
    choices: Sequence[str] | None = None,
    clearance: float = CLEARANCE,
    grains: Sequence[tuple[float, float] | None] | None = None,
) -> list[ArrangedPiece]:
    """Every piece (`names[i]`, rest shape `rests[i]`, (n, 2) metres, the place `choices[i]` or
    AUTO, its grain line's direction `grains[i]` or None) put on its place of `places`
    (`find_places`), `clearance` metres off the body."""
    names_of = {p["name"] for p in places}
    choices = list(choices) if choices is not None else [AUTO] * len(names)
    suggested = tailor.suggest_places(list(names), [np.asarray(r, np.float32) for r in rests])
    plan = [plan_entry(n, r, c, s) for n, r, c, s in zip(names, rests, choices, suggested)]
    for e, g in zip(plan, grains or [None] * len(plan)):
        if g is not None:
            e["grain"] = g
    for e in plan:
        if e["place"] not in names_of:
            raise AddonError(f"piece '{e['name']}': the body has no place '{e['place']}'", "Choose another place")
    # The module's rule (the same-axis pieces on one radius), as `arrange_garment` applies it.
    placed = place_pieces([np.asarray(r, np.float32) for r in rests], plan, places, clearance)
    return [ArrangedPiece(e["name"], e, np.asarray(p["positions"], np.float32)) for e, p in zip(plan, placed)]


def to_local(world: np.ndarray, matrix_world) -> np.ndarray:
    """(n, 3) world points into an object's local frame (`matrix_world`: 4x4, any invertible)."""
    m = np.linalg.inv(np.asarray(matrix_world, np.float64))
    w = np.asarray(world, np.float64)
    return (w @ m[:3, :3].T + m[:3, 3]).astype(np.float32)


def axis_lines(places: Sequence[dict[str, Any]], length_scale: float = 1.0) -> dict[str, np.ndarray]:
    """Per place, a segment along its axis ((2, 3): origin, origin + axis * length) for drawing."""
    out = {}
    for p in places:
        o, a = np.asarray(p["origin"], np.float64), np.asarray(p["axis"], np.float64)
        out[p["name"]] = np.array([o, o + a * float(p["length"]) * length_scale], np.float32)
    return out
