"""The scene's garment as one welded mesh, for export (bpy-free).

`tailor.weld` merges the pieces along their seams (vertex-to-vertex pairs merged, unequal
seams' edge points inserted so the seam stays watertight, pieces flipped to one winding); this
module only hands it the scene garment's arrays and carries per-corner UVs over. The Blender
side (`simulate/export_welded.py`) reads the evaluated positions and UVs and writes the object.
"""

from __future__ import annotations

import numpy as np

import tailor

from .errors import AddonError
from .garment import SceneGarment


def seam_dicts(garment: SceneGarment) -> list[dict]:
    """Every seam's sewn pairs in global indices, as `tailor.weld` (and
    `Simulation.seam_pairs()`) take them."""
    out = []
    for k, s in enumerate(garment.seams):
        av, aw, bv, bw = garment.seam_pairs(k)
        out.append({"name": s.name, "a_vertices": av, "a_weights": aw, "b_vertices": bv, "b_weights": bw})
    return out


def weld(garment: SceneGarment, positions: np.ndarray | None = None) -> tailor.WeldedMesh:
    """The garment welded at `positions` ((n, 3) world positions of every particle, e.g. the
    evaluated pieces at the current frame), or where the pieces stand."""
    pos = garment.positions if positions is None else np.asarray(positions, np.float32)
    if pos.shape != garment.positions.shape:
        raise AddonError(
            f"{len(pos)} positions for a garment of {garment.num_particles} vertices",
            "A modifier changes the pieces' vertex count: disable it (a Mesh Cache is fine)",
        )
    return tailor.weld(pos, garment.triangles, seam_dicts(garment))


def welded_corner_values(welded: tailor.WeldedMesh, values: np.ndarray) -> np.ndarray:
    """A per-corner attribute of the pieces ((3 × triangles, d): every piece's loops in garment
    order) on the welded mesh's corners ((3 × welded triangles, d))."""
    return welded.apply_corners(np.asarray(values, np.float32))


def summary(welded: tailor.WeldedMesh) -> str:
    s = welded.stats
    text = (
        f"{s['input_vertices']} vertices welded into {welded.num_vertices} ({s['merged']} merged"
        + (f", {s['inserted_points']} inserted on unequal seams" if s["inserted_points"] else "")
        + f"), {len(welded.triangles)} triangles, {s['boundary_edges']} open edges"
    )
    if s["misoriented_edges"]:
        text += f", {s['misoriented_edges']} edges whose normals flip"
    if s["non_manifold_edges"]:
        text += f", {s['non_manifold_edges']} edges shared by more than two triangles"
    return text
