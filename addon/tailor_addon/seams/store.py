"""Small helpers that update stored seams from a resolution result (`tailor.Seam.resolve`)."""

from __future__ import annotations

PALETTE = [
    (0.95, 0.35, 0.10),
    (0.15, 0.60, 0.95),
    (0.30, 0.80, 0.25),
    (0.90, 0.20, 0.60),
    (0.95, 0.80, 0.10),
    (0.55, 0.35, 0.90),
    (0.10, 0.80, 0.75),
    (0.60, 0.60, 0.60),
]


def store_seam_counts(item, resolved: dict) -> None:
    """Vertex counts of both sides, shown in the seam list beside the mode."""
    item.a_count = len(resolved["a_vertices"])
    item.b_count = len(resolved["b_vertices"])


def colour_for(index: int) -> tuple[float, float, float]:
    return PALETTE[index % len(PALETTE)]


def add_seam_item(scene, seam, objects: list, resolved: dict):
    """Appends `seam` (a `core.SeamData` over `objects`) to the scene's seams, coloured and
    counted, and makes it the active one. Returns the new item."""
    from .. import scene_data

    seams = scene.tailor.seams
    item = seams.add()
    scene_data.write_seam(item, seam, objects)
    item.color = colour_for(len(seams) - 1)
    store_seam_counts(item, resolved)
    scene.tailor.seam_index = len(seams) - 1
    return item
