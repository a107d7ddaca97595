"""The solver through the Python module: stepping, seams, stats, accuracy measures, the GIL."""

import threading
import time

import numpy as np
import pytest

import tailor


def make_tube_sim(tube, **settings):
    sim = tailor.Simulation(tube["positions"], tube["triangles"], tube["rest"], tailor.Fabric(), tailor.Settings(**settings))
    for name, a, b in tube["seams"]:
        assert sim.add_seam(a, b, name=name) > 0  # hinges across the sewn edges
    return sim


def test_sewn_tube_closes_and_reports_stats(tube):
    sim = make_tube_sim(tube, gravity=(0.0, 0.0, 0.0))
    assert sim.num_particles == len(tube["positions"])
    for _ in range(30):
        st = sim.step(1 / 30)
    assert st["seam_gap_max"] < 1e-3
    assert st["ramp_phase"] == "done"
    assert st["colours"] >= 4 and st["iterations"] == 4 * 20
    assert set(st["timings"]) == {"prediction", "local", "global", "damping", "total"}
    assert st["timings"]["total"] > 0
    p = sim.positions
    assert p.dtype == np.float32 and p.shape == (sim.num_particles, 3) and np.isfinite(p).all()


def test_a_simulation_runs_on_the_threads_it_is_given(tube):
    """`set_threads(n)`: steps run on n threads of the simulation's own (each step says how
    many) and reach the same state as on the process's pool; 0 or fewer is a typed error."""
    sims = [make_tube_sim(tube) for _ in range(2)]
    sims[0].set_threads(1)
    assert sims[0].threads == 1 and sims[1].threads >= 1
    for _ in range(6):
        assert sims[0].step(1 / 30)["threads"] == 1
        assert sims[1].step(1 / 30)["threads"] == sims[1].threads
    assert sims[0].state_hash() == sims[1].state_hash()
    for bad in (0, -1):
        with pytest.raises(tailor.InvalidParameterError, match="threads"):
            sims[0].set_threads(bad)
    sims[0].set_threads(None)
    assert sims[0].threads == sims[1].threads


def test_step_frames_and_settings_round_trip(square):
    pos, tris, rest = square
    sim = tailor.Simulation(pos, tris, rest)
    s = sim.settings
    s.substeps = 2
    s.method = "gauss_seidel"
    sim.settings = s
    assert sim.settings.substeps == 2 and sim.settings.method == "gauss_seidel"
    st = sim.step(1 / 60, frames=3)
    assert st["substeps"] == 2
    # Free fall under gravity (-z) for 3 frames with light air damping: about g t^2 / 2.
    drop = pos[:, 2].mean() - sim.positions[:, 2].mean()
    assert 0.8 * 0.5 * 9.81 * 0.05**2 < drop < 1.2 * 0.5 * 9.81 * 0.05**2


def test_quality_presets(tube):
    assert tailor.Settings.presets() == ["preview", "final"]
    preview, final = tailor.Settings.preset("preview"), tailor.Settings.preset("final")
    assert preview.substeps * preview.iterations < final.substeps * final.iterations
    assert preview.tolerance > final.tolerance >= 0  # Final runs every iteration (8 x 15)
    sim = make_tube_sim(tube, gravity=(0.0, 0.0, 0.0))
    sim.settings = preview
    st = sim.step(1 / 30)
    assert st["substeps"] == preview.substeps and st["iterations"] <= preview.substeps * preview.iterations
    with pytest.raises(tailor.InvalidParameterError, match="preset"):
        tailor.Settings.preset("fast")


def test_pins_attachments_and_masses(square):
    pos, tris, rest = square
    sim = tailor.Simulation(pos, tris, rest, tailor.Fabric(density=0.2))
    assert abs(sim.masses.sum() - 0.2 * 0.2 * 0.2) < 1e-6
    sim.pin([0, 4])
    sim.add_attachments([24], [[0.2, 0.2, 0.1]], weight=50.0)
    sim.step(1 / 30, frames=20)
    p = sim.positions
    np.testing.assert_allclose(p[[0, 4]], pos[[0, 4]], atol=1e-6)
    assert p[24, 2] > 0.0  # pulled up towards its attachment against gravity
    base = sim.masses
    # Vertex 3 (bottom edge) touches three 1.25e-3 m² triangles: 0.2 kg/m² x 3.75e-3 m² / 3.
    assert base[3] == pytest.approx(0.2 * 3 * 0.05**2 / 2 / 3, rel=1e-5)
    scale = np.ones(sim.num_particles, np.float32)
    scale[3] = 2.0
    sim.set_mass_scale(scale)
    np.testing.assert_allclose(sim.masses / base, scale, rtol=1e-6)


def test_triangle_bending_is_the_fabrics_bending(square):
    """Bending set per triangle gives the trajectory of a fabric with that bending (the module
    side of painted or per-piece bending; the Rust test checks it to the bit)."""
    pos, tris, rest = square
    held = np.flatnonzero(rest[:, 0] < 0.06)  # the square's two left columns, held flat

    def drop(fabric_bend, per_triangle=None):
        sim = tailor.Simulation(pos, tris, rest, tailor.Fabric(bend=fabric_bend))
        if per_triangle is not None:
            sim.set_triangle_bending(np.full(len(tris), per_triangle, np.float32))
        sim.pin(held)
        sim.step(1 / 30, frames=15)
        return sim.positions

    stiff, painted, soft = drop(1e-2), drop(1e-7, 1e-2), drop(1e-7)
    np.testing.assert_allclose(painted, stiff, atol=1e-6)
    assert np.abs(painted - soft).max() > 5e-3  # and the setting is not one the solver ignores


def test_unequal_weighted_seam_closes(square):
    pos, tris, rest = square
    # Sew the left column (5 vertices) to edge points of the right column, halfway along each
    # edge: a weighted seam, as seams of unequal counts produce.
    left = np.arange(0, 25, 5)
    right = np.arange(4, 25, 5)
    a_v = np.stack([left[:4], left[:4]], 1)
    a_w = np.tile([1.0, 0.0], (4, 1))
    b_v = np.stack([right[:4], right[1:]], 1)
    b_w = np.tile([0.5, 0.5], (4, 1))
    sim = tailor.Simulation(pos, tris, rest, settings=tailor.Settings(gravity=(0, 0, 0)))
    # The 20 cm square rolls into a tube thinner than two self-collision spheres (5 cm each).
    sim.set_self_collision(enabled=False)
    # Vertices sewn to edge midpoints half an edge away: the coarse square must shear to close.
    sim.add_weighted_seam(a_v, a_w, b_v, b_w, stiffness=2000.0, name="wrap")
    sim.step(1 / 30, frames=40)
    assert sim.seam_gaps()[0] < 1e-3


def test_gil_is_released_during_step(tube):
    sim = make_tube_sim(tube, iterations=200)
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    time.sleep(0.01)
    start = time.perf_counter()
    sim.step(1 / 30, frames=40)
    end = time.perf_counter()
    stop.set()
    t.join()
    during = [x for x in ticks if start < x < end]
    assert end - start > 0.05
    assert len(during) >= 5, "the other thread could not run while the solver worked"


def test_measure_step_chebyshev_beats_gauss_seidel():
    # A strip hung 10 % too long: a stretch-dominated step (see the Rust accuracy test).
    nx, ny, w, l = 4, 20, 0.1, 0.5
    xs, ys = np.linspace(0, w, nx + 1), np.linspace(0, l, ny + 1)
    rest = np.array([[x, y] for y in ys for x in xs], np.float32)
    tris = []
    for j in range(ny):
        for i in range(nx):
            a, b, c, d = j * (nx + 1) + i, j * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i
            tris += [[a, b, c], [a, c, d]]
    pos = np.stack([rest[:, 0], np.zeros(len(rest)), 1.1 * (rest[:, 1] - l)], 1).astype(np.float32)
    sim = tailor.Simulation(pos, tris, rest, tailor.Fabric(density=0.2, stretch=200, shear=50, bend=1e-6))
    sim.pin(np.arange(ny * (nx + 1), (ny + 1) * (nx + 1)))
    before = sim.state_hash()
    ch = sim.measure_step(1 / 30, "chebyshev", 300)
    gs = sim.measure_step(1 / 30, "gauss_seidel", 300)
    assert sim.state_hash() == before
    assert ch["reference"]["last_change"] < 1e-6
    for m in (ch, gs):
        assert len(m["iteration"]) == 300 and np.all(np.diff(m["seconds"]) >= 0)
    assert ch["distance_rel"][-1] < 1e-2 < gs["distance_rel"][-1]
    assert ch["objective_rel"][-1] < gs["objective_rel"][-1]


def test_deterministic(tube):
    hashes = set()
    for _ in range(2):
        sim = make_tube_sim(tube)
        sim.step(1 / 30, frames=5)
        hashes.add(sim.state_hash())
    assert len(hashes) == 1


def test_more_iterations_do_not_diverge():
    """Raising the iterations converges further, never away: the skirt sample assembling (no
    body, no gravity) at 240 iterations a substep. Chebyshev restarts straight into an
    extrapolation of nearly 2 after each growth of the update; at the waist, where four seams
    meet, that cycle grew a mode by 4 % an iteration until frame 23 diverged. An update that
    outgrows the substep's first sweep now ends the extrapolation for the substep
    (`stages/chebyshev.rs`)."""
    from pathlib import Path

    garment = tailor.Garment.load(str(Path(__file__).resolve().parents[1] / "sample_blends" / "skirt.json"))
    sim, _ = garment.build_simulation(settings=tailor.Settings(substeps=8, iterations=240, gravity=(0.0, 0.0, 0.0)),
                                      backend="cpu")
    for frame in range(30):
        sim.step(1 / 30)  # a diverged step raises DivergedError
    m = sim.metrics()
    assert np.isfinite(sim.positions).all()
    assert m["seam_gap"] < 1e-3 and m["strain_max"] < 0.2, m
