"""`tailor.weld` and `Garment.welded`: sewn pieces as one mesh for export, frames and UVs
carried over, bad input refused with a typed error that says what and where."""

from pathlib import Path

import numpy as np
import pytest

import tailor

ROOT = Path(__file__).resolve().parents[1]
SKIRT = ROOT / "sample_blends" / "skirt.json"


def edge_counts(tris):
    e = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    _, counts = np.unique(e, axis=0, return_counts=True)
    return counts


def test_a_simulated_tube_welds_closed_from_its_seam_pairs(tube):
    sim = tailor.Simulation(tube["positions"], tube["triangles"], tube["rest"])
    for name, a, b in tube["seams"]:
        sim.add_seam(a, b, name=name)
    sim.step(1.0 / 30.0, frames=3)
    w = tailor.weld(sim.positions, sim.triangles, sim.seam_pairs())
    rows = len(tube["seams"][0][1])
    assert w.stats["merged"] == 2 * rows
    assert w.num_vertices == len(sim.positions) - 2 * rows
    assert w.positions.shape == (w.num_vertices, 3) and w.triangles.shape == (len(sim.triangles), 3)
    # Closed along both seams: only the two rims stay open, nothing is non-manifold.
    counts = edge_counts(w.triangles.astype(np.int64))
    assert (counts <= 2).all()
    cols = (np.count_nonzero(counts == 1)) // 4
    assert w.stats["boundary_edges"] == 4 * cols and cols > 0
    assert w.stats["misoriented_edges"] == 0
    # A seam vertex sits at the mean of its pair; the map carries any frame over.
    a, b = tube["seams"][0][1][0], tube["seams"][0][2][0]
    np.testing.assert_allclose(w.positions[w.vertex_map[a]], (sim.positions[a] + sim.positions[b]) / 2, atol=1e-6)
    assert w.vertex_map[a] == w.vertex_map[b]
    np.testing.assert_array_equal(w.apply(sim.positions), w.positions)
    moved = sim.positions + np.float32(1.0)
    np.testing.assert_allclose(w.apply(moved), w.positions + 1.0, atol=1e-5)


def test_the_sample_skirt_welds_with_unequal_seams_split():
    garment = tailor.Garment.load(str(SKIRT))
    w = garment.welded()
    s = w.stats
    assert s["inserted_points"] > 0 and s["split_triangles"] > 0
    assert w.num_vertices == s["input_vertices"] + s["inserted_points"] + s["centroids"] - s["merged"]
    assert (s["non_manifold_edges"], s["misoriented_edges"]) == (0, 0)
    assert (edge_counts(w.triangles.astype(np.int64)) <= 2).all()
    # The same weld from the simulation's own seam pairs, and at its positions.
    sim, offsets = garment.build_simulation()
    w2 = tailor.weld(sim.positions, sim.triangles, sim.seam_pairs())
    np.testing.assert_array_equal(w2.triangles, w.triangles)
    np.testing.assert_array_equal(garment.welded(sim.positions).positions, w.positions)
    # UVs per corner: each welded corner gets the rest position of its point on its piece.
    rest = sim.rest
    uv = rest[np.asarray(sim.triangles).reshape(-1)]
    out = w.apply_corners(uv)
    assert out.shape == (3 * len(w.triangles), 2)
    src = np.asarray(sim.triangles)[w.triangle_source]  # (m, 3) source corners
    expected = np.einsum("tck,tkd->tcd", w.corner_weights, rest[src]).reshape(-1, 2)
    np.testing.assert_allclose(out, expected, atol=1e-6)
    assert w.corner_weights.shape == (len(w.triangles), 3, 3)
    np.testing.assert_allclose(w.corner_weights.sum(axis=2), 1.0, atol=1e-6)


def test_bad_input_raises_typed_errors_naming_what_and_where(square):
    pos, tris, _ = square
    seam = {"name": "hem", "a_vertices": [[0, 0]], "a_weights": [[1, 0]], "b_vertices": [[4, 4]], "b_weights": [[1, 0]]}
    tailor.weld(pos, tris, [seam])
    bad = pos.copy()
    bad[7, 1] = np.nan
    with pytest.raises(tailor.InvalidMeshError, match="vertex 7 has a non-finite"):
        tailor.weld(bad, tris, [seam])
    with pytest.raises(tailor.InvalidMeshError, match=r"seam 'hem' side B.*index 99"):
        tailor.weld(pos, tris, [dict(seam, b_vertices=[[99, 99]])])
    with pytest.raises(tailor.SeamError, match="hem: pair 0 side A: vertices 0 and 24 are not the ends"):
        tailor.weld(pos, tris, [dict(seam, a_vertices=[[0, 24]], a_weights=[[0.5, 0.5]])])
    with pytest.raises(tailor.SeamError, match="not a point of an edge"):
        tailor.weld(pos, tris, [dict(seam, a_vertices=[[0, 1]], a_weights=[[0.9, 0.9]])])
    with pytest.raises(tailor.InvalidParameterError, match="'b_weights' is missing"):
        tailor.weld(pos, tris, [{k: v for k, v in seam.items() if k != "b_weights"}])
    w = tailor.weld(pos, tris, [seam])
    with pytest.raises(tailor.InvalidParameterError, match="frame"):
        w.apply(pos[:3])
    with pytest.raises(tailor.InvalidParameterError, match="corner"):
        w.apply_corners(np.zeros((5, 2), np.float32))
    with pytest.raises(tailor.InvalidParameterError, match="particles"):
        tailor.Garment.load(str(SKIRT)).welded(np.zeros((3, 3), np.float32))
