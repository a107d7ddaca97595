"""Arrangement round the body for a whole garment (issue 25), headless.

``arrange_garment`` puts every piece of a garment on a place of the body (``tailor.body_places``):
which place by the piece's name and shape (``tailor.suggest_place``) unless ``assign`` says, each
facing the body ``clearance`` metres off it and rolled round the place's axis
(``tailor.place_on_body``). The pieces round one axis (a bodice's front and back halves, a
sleeve's front and back) are placed twice: the second time on the largest of their radii, so
that they lie on one cylinder and the seams between them start level. The result is a
new garment whose pieces carry these positions (and no pattern placement), ready to simulate.

    import tailor
    from tailor.arrange import arrange_garment

    body_v, body_t = tailor.read_mesh("body.obj")
    garment = tailor.Garment.from_pattern("shirt.json", edge=0.02)
    arranged, plan = arrange_garment(garment, body_v, body_t, up="y")
    arranged.save("shirt_arranged.json")
"""

from __future__ import annotations

import json
from typing import Any, Mapping, Sequence

import tailor


def plan_arrangement(
    garment: tailor.Garment, assign: Mapping[str, Mapping[str, Any]] | None = None
) -> list[dict[str, Any]]:
    """Per piece, where it goes: ``tailor.suggest_places`` of the pieces' names and rest shapes
    and its grain line's direction (``grain``, when it has one), with ``assign[name]`` (any of
    "place", "side", "around_deg", "along", "offset", "grain") laid over it."""
    plan = []
    meshes = garment.meshes()
    suggested = tailor.suggest_places([p.name for p in garment.pieces], [m.rest for m in meshes])
    for piece, suggestion in zip(garment.pieces, suggested):
        entry = dict(suggestion)
        direction = grain_direction(piece)
        if direction is not None:
            entry["grain"] = direction
        entry.update((assign or {}).get(piece.name, {}))
        entry["name"] = piece.name
        plan.append(entry)
    return plan


def grain_direction(piece: tailor.Piece) -> tuple[float, float] | None:
    """The direction of ``piece``'s grain line (end minus start, pattern frame), None without
    one: ``place_on_body``'s ``grain``, which turns a piece a marker laid on its side."""
    if piece.grain is None:
        return None
    (x0, y0), (x1, y1) = piece.grain
    return (x1 - x0, y1 - y0) if (x1 - x0, y1 - y0) != (0.0, 0.0) else None


def _axis_of(place: str) -> str:
    return "torso" if place in ("torso_front", "torso_back") else place


def _options(entry: Mapping[str, Any]) -> dict[str, Any]:
    keys = ("side", "around_deg", "along", "offset", "grain")
    return {k: entry[k] for k in keys if k in entry}


def place_pieces(
    rests: Sequence[Any],
    plan: Sequence[dict[str, Any]],
    places: Sequence[dict[str, Any]],
    clearance: float = 0.03,
) -> list[dict[str, Any]]:
    """Each piece (rest shape ``rests[i]``) put on its place ``plan[i]["place"]`` of ``places``
    (``tailor.place_on_body`` with the entry's side, turn, direction and offset): the pieces
    round one axis (the torso's front and back, an arm's halves) are placed again on the largest
    of their radii, so that they lie on one cylinder and the seams between them start level.
    Sets each entry's ``radius``; returns ``place_on_body``'s results. The one rule of
    ``arrange_garment`` and the add-on's Arrange on Body."""
    by_name = {p["name"]: p for p in places}
    for entry in plan:
        if entry["place"] not in by_name:
            raise tailor.InvalidParameterError(
                f"piece {entry['name']!r}: no place {entry['place']!r} (places: {sorted(by_name)})"
            )
    placed = [
        tailor.place_on_body(r, by_name[e["place"]], clearance=clearance, **_options(e)) for r, e in zip(rests, plan)
    ]
    groups: dict[str, float] = {}
    for e, p in zip(plan, placed):
        groups[_axis_of(e["place"])] = max(groups.get(_axis_of(e["place"]), 0.0), p["radius"])
    for i, (r, e) in enumerate(zip(rests, plan)):
        big = groups[_axis_of(e["place"])]
        if big > placed[i]["radius"]:
            placed[i] = tailor.place_on_body(r, by_name[e["place"]], clearance=clearance, min_radius=big, **_options(e))
        e["radius"] = placed[i]["radius"]
    return placed


def arrange_garment(
    garment: tailor.Garment,
    body_vertices: Any,
    body_triangles: Any,
    up: str | Sequence[float] = "y",
    front: str | Sequence[float] | None = None,
    clearance: float = 0.03,
    assign: Mapping[str, Mapping[str, Any]] | None = None,
    places: Sequence[dict[str, Any]] | None = None,
) -> tuple[tailor.Garment, list[dict[str, Any]]]:
    """``garment`` with every piece arranged round the body; returns it and the plan (per
    piece its place, side, turn round the axis and the radius it was rolled to). ``places``:
    the body's places when already found (``tailor.body_places``)."""
    if places is None:
        places = tailor.body_places(body_vertices, body_triangles, up=up, front=front)
    plan = plan_arrangement(garment, assign)
    placed = place_pieces([m.rest for m in garment.meshes()], plan, places, clearance)
    # The pattern's own placements are dropped: the positions are the arrangement.
    pieces = []
    for piece in garment.pieces:
        data = json.loads(piece.to_json())
        data["placement"] = None
        pieces.append(tailor.Piece.from_json(json.dumps(data)))
    arranged = tailor.Garment.from_parts(
        pieces,
        garment.edge_lengths,
        garment.seams,
        meshers=garment.meshers,
        positions=[p["positions"] for p in placed],
    )
    arranged.setup = garment.setup
    return arranged, plan
