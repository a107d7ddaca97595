"""Quality of any peer's output, measured by Tailor's own metric functions on its positions.

Every peer's final positions go through the same calls, so the figures are comparable:
``tailor.max_seam_gap`` over the sewn pairs (the scene's weighted pairs, and the vertex pairs a
peer was given when it only sews vertices), ``tailor.penetration`` into the body,
``tailor.edge_strain`` over the mesh edges against their flat rest lengths and
``tailor.count_self_intersections`` over the cloth's triangles.
"""

from __future__ import annotations

import numpy as np

import tailor


def _weighted(x: np.ndarray, verts: np.ndarray, weights: np.ndarray) -> np.ndarray:
    return x[verts[:, 0]] * weights[:, :1] + x[verts[:, 1]] * weights[:, 1:]


def seam_gap(scene: dict, x: np.ndarray) -> float:
    """Largest distance between the two points of any of the scene's sewn pairs, metres."""
    if not len(scene["seam_a_vertices"]):
        return 0.0
    a = _weighted(x, scene["seam_a_vertices"], scene["seam_a_weights"])
    b = _weighted(x, scene["seam_b_vertices"], scene["seam_b_weights"])
    k = np.arange(len(a))
    return float(tailor.max_seam_gap(np.concatenate([a, b]).astype(np.float32), np.stack([k, k + len(a)], 1)))


def quality(scene: dict, x: np.ndarray, vertex_pairs: np.ndarray | None = None) -> dict:
    """The quality metrics of positions `x` (n, 3) of `scene`; lower is better for each."""
    x = np.asarray(x, np.float32)
    if not np.isfinite(x).all():
        return dict(nan=True)
    q: dict = dict(nan=False, seam_gap_m=seam_gap(scene, x))
    if vertex_pairs is not None and len(vertex_pairs):
        q["seam_gap_vertex_pairs_m"] = float(tailor.max_seam_gap(x, vertex_pairs))
    if len(scene["body_triangles"]):
        pen = tailor.penetration(x, scene["body_vertices"], scene["body_triangles"])
        q["penetration_count"] = int(pen["count"])
        q["penetration_max_m"] = float(pen["max_depth"])
    s = tailor.edge_strain(x, scene["edges"], scene["rest_lengths"])
    q["strain_max"], q["strain_mean"] = float(s["max"]), float(s["mean"])
    q["self_intersections"] = int(tailor.count_self_intersections(x, scene["triangles"]))
    return q
