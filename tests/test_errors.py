"""Every kind of bad input raises a typed exception naming the offending element; nothing
panics across into Python."""

import numpy as np
import pytest

import tailor


def test_hierarchy():
    for cls, builtin in [
        (tailor.InvalidMeshError, ValueError),
        (tailor.InvalidParameterError, ValueError),
        (tailor.SeamError, ValueError),
        (tailor.PatternError, ValueError),
        (tailor.TailorIOError, OSError),
        (tailor.SimulationError, RuntimeError),
    ]:
        assert issubclass(cls, tailor.TailorError) and issubclass(cls, builtin)
    assert issubclass(tailor.CancelledError, tailor.TailorError)


def test_empty_mesh():
    with pytest.raises(tailor.InvalidMeshError, match="no vertices"):
        tailor.Simulation(np.zeros((0, 3)), np.zeros((0, 3), int), np.zeros((0, 2)))
    with pytest.raises(tailor.InvalidMeshError, match="no triangles"):
        tailor.Simulation(np.zeros((3, 3)), np.zeros((0, 3), int), np.zeros((3, 2)))


def test_index_out_of_range(square):
    pos, tris, rest = square
    bad = tris.copy()
    bad[7, 1] = 999
    with pytest.raises(tailor.InvalidMeshError, match=r"triangle 7: index 999"):
        tailor.Simulation(pos, bad, rest)
    bad[7, 1] = -1
    with pytest.raises(tailor.InvalidMeshError, match="-1"):
        tailor.Simulation(pos, bad, rest)


def test_nan_and_inf_positions(square):
    pos, tris, rest = square
    p = pos.copy()
    p[5, 0] = np.nan
    with pytest.raises(tailor.InvalidMeshError, match="vertex 5"):
        tailor.Simulation(p, tris, rest)
    sim = tailor.Simulation(pos, tris, rest)
    p[5, 0] = np.inf
    with pytest.raises(tailor.InvalidMeshError, match="vertex 5"):
        sim.positions = p


def test_zero_area_triangle(square):
    pos, tris, rest = square
    r = rest.copy()
    r[tris[3]] = r[tris[3][0]]  # collapse triangle 3 (and its neighbours) to a point
    with pytest.raises(tailor.InvalidMeshError, match=r"triangle \d+ is degenerate"):
        tailor.Simulation(pos, tris, r)


def test_seam_pairing_different_counts(square):
    pos, tris, rest = square
    sim = tailor.Simulation(pos, tris, rest)
    with pytest.raises(tailor.SeamError, match="side A has 3 vertices and side B 2"):
        sim.add_seam([0, 1, 2], [20, 21], name="side")


def test_zero_and_negative_mass(square):
    pos, tris, rest = square
    sim = tailor.Simulation(pos, tris, rest)
    s = np.ones(len(pos), np.float32)
    s[11] = 0.0
    with pytest.raises(tailor.InvalidParameterError, match="particle 11"):
        sim.set_mass_scale(s)
    s[11] = -1.0
    with pytest.raises(tailor.InvalidParameterError, match="particle 11"):
        sim.set_mass_scale(s)
    with pytest.raises(tailor.InvalidParameterError, match="fabric.density"):
        tailor.Simulation(pos, tris, rest, tailor.Fabric(density=0.0))


def test_bad_triangle_bending(square):
    pos, tris, rest = square
    sim = tailor.Simulation(pos, tris, rest)
    with pytest.raises(tailor.InvalidParameterError, match=f"3 values for {len(tris)} triangles"):
        sim.set_triangle_bending([1e-5] * 3)
    bend = np.full(len(tris), 1e-5, np.float32)
    bend[7] = -1.0
    with pytest.raises(tailor.InvalidParameterError, match="triangle 7: bend -1"):
        sim.set_triangle_bending(bend)
    bend[7] = np.nan
    with pytest.raises(tailor.InvalidParameterError, match="triangle 7"):
        sim.set_triangle_bending(bend)


def test_bad_shapes_and_settings(square):
    pos, tris, rest = square
    with pytest.raises(tailor.InvalidParameterError, match=r"\(n, 3\)"):
        tailor.Simulation(pos[:, :2], tris, rest)
    with pytest.raises(tailor.InvalidParameterError, match="substeps"):
        tailor.Simulation(pos, tris, rest, settings=tailor.Settings(substeps=0))
    with pytest.raises(tailor.InvalidParameterError, match="method"):
        tailor.Simulation(pos, tris, rest, settings=tailor.Settings(method="newton"))
    with pytest.raises(TypeError):
        tailor.Settings(no_such_field=1)
    sim = tailor.Simulation(pos, tris, rest)
    with pytest.raises(tailor.InvalidParameterError, match="dt"):
        sim.step(float("nan"))
    with pytest.raises(tailor.InvalidMeshError, match="999"):
        sim.pin([999])


def test_divergence_is_reported_and_rolled_back(square):
    pos, tris, rest = square
    sim = tailor.Simulation(pos, tris, rest)
    before = sim.positions
    sim.velocities = np.full((len(pos), 3), 3e38, np.float32)
    with pytest.raises(tailor.SimulationError, match="rolled back"):
        sim.step(1.0)
    np.testing.assert_array_equal(sim.positions, before)
