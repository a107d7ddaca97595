"""The add-on's bpy-free simulation builder and Live worker (`core/simulate.py`,
`core/simulate_live.py`), against the module, without Blender."""

import re
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import tailor
from tailor import bake

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "addon"))
from tailor_addon.core import garment_from_scene, piece_mesh  # noqa: E402
from tailor_addon.core import simulate as core_sim  # noqa: E402
from tailor_addon.core.garment import PieceData  # noqa: E402
from tailor_addon.core.simulate_live import LiveSolver  # noqa: E402

def two_pieces():
    pattern = tailor.read_pattern(str(ROOT / "native/tailor-core/tests/data/garmentcode/shirt_mean_specification.json"))
    pieces = []
    for k, p in enumerate(pattern.pieces[:2]):
        js = p.to_json()
        m = piece_mesh(js, 0.05, tailor.MESHER_VERSION)
        pos = np.concatenate([m.rest, np.full((len(m.rest), 1), 0.3 * k, np.float32)], axis=1)
        pieces.append(PieceData(p.name, js, 0.05, pos.astype(np.float32), None))
    return garment_from_scene(pieces, [])


def box():
    v = np.array([[x, y, z] for z in (-1.0, -0.5) for y in (-1.0, 1.0) for x in (-1.0, 1.0)], np.float32)
    t = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                  [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]], np.int64)
    return v, t


def test_presets_settings_and_backend_passthrough():
    """The panel's presets are the module's (one source), its defaults open in Final, and the
    Backend menu reaches the solver: a build with Backend = CPU runs its step on the CPU."""
    assert core_sim.PRESETS == ("PREVIEW", "FINAL")
    for name in core_sim.PRESETS:
        m = tailor.Settings.preset(name.lower())
        assert core_sim.preset_values(name) == {"substeps": m.substeps, "iterations": m.iterations,
                                                "tolerance": pytest.approx(m.tolerance)}
    final, opened = tailor.Settings.preset("final"), core_sim.SimSettings()
    assert (opened.substeps, opened.iterations, opened.tolerance) == (final.substeps, final.iterations,
                                                                      pytest.approx(final.tolerance))
    with pytest.raises(Exception, match="FAST"):
        core_sim.preset_values("FAST")
    s = core_sim.SimSettings(substeps=3, iterations=7, gravity=(0, 0, -1), air_damping=0.5).to_tailor()
    assert (s.substeps, s.iterations, s.air_damping) == (3, 7, 0.5) and tuple(s.gravity) == (0, 0, -1)
    assert not s.two_level and core_sim.SimSettings(two_level=True).to_tailor().two_level  # off unless asked
    with pytest.raises(tailor.InvalidParameterError, match="substeps is 0"):
        core_sim.SimSettings(substeps=0).to_tailor()
    v, t = box()
    fabrics = [core_sim.PieceFabric(0.15, 600.0, 60.0, 2e-5)] * 2
    built = core_sim.build(two_pieces(), core_sim.SimSettings(backend="cpu"), fabrics, [{}, {}],
                           [core_sim.ColliderData("box", v, t)])
    assert built.sim.backend == "cpu" and built.adapter.startswith("CPU")
    assert built.sim.step(1 / 30)["backend"] == "cpu"
    with pytest.raises(tailor.InvalidParameterError, match="backend"):
        core_sim.build(two_pieces(), core_sim.SimSettings(backend="tpu"), fabrics, [{}, {}], [])


def test_painted_bend_scale_multiplies_each_triangles_bending():
    """Bend Scale painted at weight 1 (factor 100) all over piece 0 gives the trajectory of piece 0
    made of a fabric 100x stiffer in bending; painted on some vertices only, each triangle takes
    the mean of its vertices' factors, so the result lies between the two."""
    from tailor_addon.core import paint

    g = two_pieces()
    n0 = int(g.offsets[1])
    assert paint.values("bend_scale", np.array([0.0, 0.5, 1.0])) == pytest.approx([0.01, 1.0, 100.0])
    # The stiff fabric's bending is the painted product as the solver gets it (float32).
    soft = core_sim.PieceFabric(0.2, 600.0, 60.0, 2e-5)
    stiff = core_sim.PieceFabric(0.2, 600.0, 60.0, float(np.float32(2e-5) * np.float32(100.0)))
    settings = core_sim.SimSettings(pin_mode="FIXED", gravity=(0.0, 0.0, -9.81))
    pin = np.zeros(n0, np.float32)
    pin[:2] = 1.0  # piece 0 held at two corners, so it folds under its weight

    def run(fabrics, scale=None):
        maps = [{"pin": (pin, pin > 0)}, {}]
        if scale is not None:
            maps[0]["bend_scale"] = (scale, np.ones(n0, bool))
        sim = core_sim.build(g, settings, fabrics, maps, []).sim
        sim.step(1 / 30, frames=10)
        return sim.positions

    painted = run([soft, soft], np.full(n0, 100.0, np.float32))
    np.testing.assert_allclose(painted, run([stiff, soft]), atol=1e-6)
    plain = run([soft, soft])
    assert np.abs(painted - plain).max() > 1e-3
    half = np.where(np.arange(n0) % 2 == 0, 100.0, 1.0).astype(np.float32)
    mixed = run([soft, soft], half)
    assert 0 < np.abs(mixed - plain).max() and 0 < np.abs(mixed - painted).max()


def test_build_per_piece_fabric_pins_friction_levels_and_colliders():
    g = two_pieces()
    n0 = int(g.offsets[1])
    fabrics = [core_sim.PieceFabric(0.2, 600.0, 60.0, 2e-5), core_sim.PieceFabric(0.4, 1200.0, 60.0, 4e-5)]
    pin = np.zeros(n0, np.float32)
    pin[:3] = 1.0
    pin[3:5] = 0.5
    maps = [{"pin": (pin, pin > 0), "collision_level": (np.full(n0, 2, np.int32), np.ones(n0, bool))}, {}]
    v, t = box()
    fixed = core_sim.SimSettings(pin_mode="FIXED")
    built = core_sim.build(g, fixed, fabrics, maps, [core_sim.ColliderData("box", v, t)])
    sim = built.sim
    assert built.pins is None
    assert not built.warnings  # each piece's bending is its own (set per triangle)
    # The second piece's density is twice the first's: its particles weigh twice as much as with
    # one fabric for both.
    same = core_sim.build(g, fixed, [fabrics[0]] * 2, maps, [core_sim.ColliderData("box", v, t)])
    np.testing.assert_allclose(sim.masses[n0:], 2 * same.sim.masses[n0:], rtol=1e-6)
    np.testing.assert_allclose(sim.masses[:n0], same.sim.masses[:n0], rtol=1e-6)
    assert (sim.particle_levels[:n0] == 2).all() and (sim.particle_levels[n0:] == 0).all()
    assert [(w, p.tolist()) for w, p in built.garment.pin_weights()] == [(1.0, [0, 1, 2]), (0.5, [3, 4])]
    before = sim.positions[:3].copy()
    sim.step(1 / 30)
    np.testing.assert_array_equal(sim.positions[:3], before)  # hard pins stay
    # Pin mode ATTACH (the default): nothing is pinned in place; the painted pins wait in
    # `Built.pins` for `Bake` to attach them to the collider, weight 1 at the pin stiffness,
    # lower weights in proportion.
    riding = core_sim.build(g, core_sim.SimSettings(pin_stiffness=80.0), fabrics, maps,
                            [core_sim.ColliderData("box", v, t)])
    assert riding.pins is not None and riding.pins.collider == riding.colliders[0].id and not riding.pins.attached
    assert [(p.tolist(), k) for p, k in riding.pins.groups] == [([0, 1, 2], 80.0), ([3, 4], 40.0)]
    first = riding.sim.positions[:3].copy()
    riding.sim.step(1 / 30)
    assert len(riding.sim.collider_attached) == 0 and np.abs(riding.sim.positions[:3] - first).max() > 0
    # They wait while the seams close and are attached after the first frame that is not.
    assert not riding.pins.after_frame(riding.sim, "closing") and len(riding.sim.collider_attached) == 0
    assert riding.pins.after_frame(riding.sim, "releasing") and len(riding.sim.collider_attached) == 5
    assert riding.pins.after_frame(riding.sim, "done") and len(riding.sim.collider_attached) == 5  # once
    # Without a collider there is nothing to ride on: held in place, with a warning.
    alone = core_sim.build(g, core_sim.SimSettings(), fabrics, maps, [])
    assert alone.pins is None and any("no collider" in w for w in alone.warnings)
    with pytest.raises(tailor.InvalidParameterError, match="pin mode"):
        core_sim.build(g, core_sim.SimSettings(pin_mode="GLUED"), fabrics, maps, [])
    assert built.colliders[0].name == "box" and sim.num_mesh_colliders == 1
    bad = v.copy()
    bad[2, 0] = np.inf
    with pytest.raises(tailor.InvalidParameterError, match="collider 'box': vertex 2 is not finite"):
        core_sim.build(g, core_sim.SimSettings(), fabrics, maps, [core_sim.ColliderData("box", bad, t)])


def test_self_collision_radius_and_cloth_friction_pass_through_or_stay_automatic():
    FABRICS = [core_sim.PieceFabric(0.2, 600.0, 60.0, 2e-5)] * 2
    g = two_pieces()
    col = [core_sim.ColliderData("box", *box())]
    auto = core_sim.build(g, core_sim.SimSettings(self_collision=True), FABRICS, [{}, {}], col)
    assert auto.sim.self_collision["enabled"] and auto.sim.self_collision["radius_setting"] is None
    assert auto.sim.self_collision["radius"] > 0.01  # half the mean edge of a 5 cm mesh
    # The panel's cloth friction (where not painted) is the cloth's friction against itself.
    assert (auto.sim.self_collision["static_friction"], auto.sim.self_collision["kinetic_friction"]) == (
        pytest.approx(0.5), pytest.approx(0.3))
    s = core_sim.SimSettings(self_collision=True, self_collision_radius=0.007, friction_static=0.6,
                             friction_kinetic=0.4)
    set_ = core_sim.build(g, s, FABRICS, [{}, {}], col)
    sc = set_.sim.self_collision
    assert sc["radius"] == pytest.approx(0.007) and (sc["static_friction"], sc["kinetic_friction"]) == (
        pytest.approx(0.6), pytest.approx(0.4))
    with pytest.raises(tailor.InvalidParameterError, match="friction.static"):
        core_sim.build(g, core_sim.SimSettings(friction_static=-0.1), FABRICS, [{}, {}], col)
    # Triangle contacts: the radius is the distance kept from a triangle, 4 mm when automatic.
    tri = core_sim.build(g, core_sim.SimSettings(self_collision=True, self_collision_contacts="TRIANGLES"), FABRICS,
                         [{}, {}], col).sim.self_collision
    assert tri["contacts"] == "triangles" and tri["radius"] == pytest.approx(tailor.DEFAULT_THICKNESS)
    assert auto.sim.self_collision["contacts"] == "spheres"
    with pytest.raises(tailor.InvalidParameterError, match="self_collision_contacts"):
        core_sim.build(g, core_sim.SimSettings(self_collision=True, self_collision_contacts="CUBES"), FABRICS,
                       [{}, {}], col)
    for bad in (float("nan"), -0.001):
        with pytest.raises(tailor.InvalidParameterError, match="self_collision_radius"):
            core_sim.build(g, core_sim.SimSettings(self_collision=True, self_collision_radius=bad), FABRICS,
                           [{}, {}], col)


def test_the_exported_setup_is_what_the_module_reads_back(tmp_path):
    """What the add-on gives a garment (`garment_of`: setup from the panel, fabric per piece,
    painted maps, the collider's levels) is saved typed in the garment file and read back as it
    was; the file's simulation is the add-on's, bit for bit."""
    fab = [core_sim.PieceFabric(0.2, 600.0, 60.0, 2e-5), core_sim.PieceFabric(0.3, 900.0, 90.0, 5e-5)]
    sg = two_pieces()
    n0, n1 = int(sg.offsets[1]), sg.num_particles - int(sg.offsets[1])
    pin = np.zeros(n0, np.float32)
    pin[[1, 2]] = [1.0, 0.5]
    maps = [{"pin": (pin, pin > 0)}, {"collision_level": (np.full(n1, 3, np.int32), np.ones(n1, bool))}]
    body = np.array([0, 0, 1, 1, 0, 2, 0, 0], np.int32)
    chosen = core_sim.SimSettings(self_collision=True, self_collision_radius=0.007, friction_static=0.6,
                                  self_collision_contacts="TRIANGLES")
    g = core_sim.garment_of(sg.tailor_garment(placements=None), "coat", chosen, fab, maps, body)
    g.save(tmp_path / "coat.json")
    back = tailor.Garment.load(tmp_path / "coat.json")
    s = back.setup
    assert s == g.setup and s["name"] == "coat" and s["fabrics"][1] == {"density": 0.3, "stretch": 900.0,
                                                                        "shear": 90.0, "bend": 5e-5}
    assert s["self_collision"] and s["self_collision_radius"] == pytest.approx(0.007)
    assert s["self_collision_contacts"] == "triangles"
    assert core_sim.setup_settings(s)["self_collision_contacts"] == "TRIANGLES"
    assert s["thickness"] == pytest.approx(tailor.DEFAULT_THICKNESS)
    assert s["friction"] == {"static": pytest.approx(0.6), "kinetic": pytest.approx(0.3)}
    levels, warnings = back.collider_levels(8)
    np.testing.assert_array_equal(levels, body) and not warnings
    assert back.collider_levels(9)[0] is None and "9" in back.collider_levels(9)[1][0]
    painted = {(n, k): v for n, k, v in back.particle_params}
    np.testing.assert_array_equal(painted[("pin", 0)], pin)
    np.testing.assert_array_equal(painted[("collision_level", 1)], np.full(n1, 3))
    np.testing.assert_array_equal(painted[("position", 0)], sg.positions[:n0])
    settings = chosen.to_tailor()
    a, _ = g.build_simulation(settings=settings)
    b, _ = back.build_simulation(settings=settings)
    for _ in range(3):
        a.step(1 / 30)
        b.step(1 / 30)
    np.testing.assert_array_equal(a.positions, b.positions)
    # Nothing painted on the collider: nothing recorded.
    assert core_sim.garment_of(sg.tailor_garment(placements=None), "coat", chosen, fab, [{}, {}],
                               np.zeros(8)).setup["collider_levels"] is None


def test_triangle_size_spread():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [10, 0, 0]], np.float32)
    even = core_sim.triangle_size_spread(v, [[0, 1, 2]])
    uneven = core_sim.triangle_size_spread(v, [[0, 1, 2], [0, 3, 2]])
    assert even["edge_cv"] < uneven["edge_cv"] and even["edge_p95_p5"] < uneven["edge_p95_p5"]


def test_live_solver_solves_on_native_threads_and_applies_edits():
    """Live's solver starts no Python thread (in Blender one races Blender's own calls into
    Python: see `core/simulate_live.py`); polling alone, never waiting, moves a frame through
    its assembly and measurement to its result while the solves run on native threads."""
    g = two_pieces()
    v, t = box()
    fabrics = [core_sim.PieceFabric(0.15, 600.0, 60.0, 2e-5)] * 2
    built = core_sim.build(g, core_sim.SimSettings(), fabrics, [{}, {}], [core_sim.ColliderData("box", v, t)])
    threads = threading.active_count()
    solver = LiveSolver(bake.Bake(built.sim, built.colliders, 30.0, 1, preroll=3))
    try:
        seen = []
        assert solver.submit(1, [v], [lambda sim: seen.append(sim.num_particles)])
        assert solver.busy and not solver.submit(1, [v])  # one frame at a time
        assert threading.active_count() == threads
        polls, r = 0, None
        deadline = time.monotonic() + 60
        while r is None and time.monotonic() < deadline:
            r, polls = solver.poll(), polls + 1
            time.sleep(0.001)
        assert r is not None and r.error is None and r.frame == 1 and seen == [g.num_particles]
        assert r.positions.shape == (g.num_particles, 3) and polls > 1 and not solver.busy
        assert solver.run.preroll_frames >= 3 and r.solve_ms == r.record["ms"] > 0.0
        assert solver.submit(2, [v])
        r = solver.wait(30)
        assert r is not None and r.error is None and r.frame == 2
        bad = v.copy()
        bad[0] = np.nan
        assert solver.submit(2, [bad])
        r = solver.wait(30)
        assert isinstance(r.error, tailor.InvalidParameterError)
    finally:
        solver.stop()
    with pytest.raises(RuntimeError, match="stopped"):
        solver.submit(3, [v])
    # The modal bake's use: every frame kept; stop lets a frame in progress finish (and drops
    # one not started yet): the frames kept are whole and in order either way.
    built = core_sim.build(g, core_sim.SimSettings(), fabrics, [{}, {}], [core_sim.ColliderData("box", v, t)])
    run = bake.Bake(built.sim, built.colliders, 30.0, 1)
    keeper = LiveSolver(run, keep_frames=True)
    for f in (1, 2, 3):
        assert keeper.submit(f, [v])
        assert keeper.wait(30).error is None
    assert keeper.submit(4, [v])
    keeper.stop(timeout=None)
    kept = len(run.records)
    assert kept in (3, 4) and len(run.frames) == kept
    assert [r["frame"] for r in run.records] == list(range(1, kept + 1))


def test_live_measures_a_few_times_a_second_and_solves_the_same_frames():
    """Live measures a frame's quality at most every `measure_every_s` seconds (the overlay's
    figures; the measurement costs about half the T-shirt's solve): the frames between have a
    record without quality fields, `measured` keeps the latest measured one, and the positions
    are bit for bit those of a run that measures every frame (as the modal bake does)."""
    g = two_pieces()
    v, t = box()
    fabrics = [core_sim.PieceFabric(0.15, 600.0, 60.0, 2e-5)] * 2
    runs = {}
    for every in (0.0, 3600.0):
        built = core_sim.build(g, core_sim.SimSettings(), fabrics, [{}, {}], [core_sim.ColliderData("box", v, t)])
        solver = LiveSolver(bake.Bake(built.sim, built.colliders, 30.0, 1), measure_every_s=every)
        try:
            results = []
            for f in range(1, 6):
                assert solver.submit(f, [v + np.float32(0.002 * f)])
                r = solver.wait(30)
                assert r is not None and r.error is None
                results.append(r)
            runs[every] = (results, solver.measured)
        finally:
            solver.stop()
    every_frame, (first, *rest) = runs[0.0][0], runs[3600.0][0]
    assert all("seam_gap_max_m" in r.record for r in every_frame) and runs[0.0][1] is every_frame[-1]
    # The first frame is measured, then none for an hour; the overlay keeps the first's figures.
    assert "seam_gap_max_m" in first.record and runs[3600.0][1] is first
    assert all(r.record["measured"] is False and "seam_gap_max_m" not in r.record and r.record["ms"] > 0
               for r in rest)
    for a, b in zip(every_frame, [first, *rest]):
        assert a.positions.tobytes() == b.positions.tobytes()
    # The modal bake measures (and keeps) every frame whatever it is asked.
    assert LiveSolver(bake.Bake(built.sim, built.colliders, 30.0, 1), keep_frames=True).measure_every_s == 0.0


def test_a_stop_with_no_time_leaves_the_frame_to_its_thread_quietly(monkeypatch):
    """Stopped with no time to finish a frame in progress (its assembly under held gravity),
    the frame is left to its native thread and its loop is closed there and then: its clean-up
    (gravity put back) meets the busy simulation, which is not reported later as an
    "Exception ignored" when the loop is collected."""
    import gc

    g = two_pieces()
    v, t = box()
    fabrics = [core_sim.PieceFabric(0.15, 600.0, 60.0, 2e-5)] * 2
    built = core_sim.build(g, core_sim.SimSettings(), fabrics, [{}, {}], [core_sim.ColliderData("box", v, t)])
    unraisable = []
    monkeypatch.setattr(sys, "unraisablehook", unraisable.append)
    solver = LiveSolver(bake.Bake(built.sim, built.colliders, 30.0, 1, preroll=200, assembly_gravity=(0.0, 0.0, 0.0)))
    assert solver.submit(1, [v]) and solver.busy
    solver.stop(timeout=0.0)
    assert not solver.busy
    gc.collect()
    assert unraisable == []
    with pytest.raises(RuntimeError, match="stopped"):
        solver.submit(2, [v])


def test_one_seam_stiffness_default_on_every_path():
    """The module's seams, the garment builder's and the add-on's settings share one default
    (a closed seam's gap is the cloth's tension over it: 1e3 N/m left mm gaps on the shirt)."""
    assert tailor.DEFAULT_SEAM_STIFFNESS == pytest.approx(1.0e4)
    assert core_sim.SimSettings().seam_stiffness == pytest.approx(tailor.DEFAULT_SEAM_STIFFNESS)
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 0.1], [1, 0, 0.1], [0, 1, 0.1]], np.float32)
    sim = tailor.Simulation(v, np.array([[0, 1, 2], [3, 4, 5]], np.uint32), v[:, :2].copy())
    sim.add_seam([0, 1], [3, 4], name="s")
    assert sim.seam_pairs()[0]["stiffness"] == pytest.approx(tailor.DEFAULT_SEAM_STIFFNESS)
    assert tailor.DEFAULT_SETUP["seam_stiffness"] == pytest.approx(tailor.DEFAULT_SEAM_STIFFNESS)
    props = (ROOT / "addon/tailor_addon/simulate/properties.py").read_text()
    assert re.search(r"seam_stiffness: FloatProperty\([^)]*default=_SETUP\[\"seam_stiffness\"\]\)", props), \
        "the add-on's property default is the module's"


def test_an_anisotropic_piece_fabric_reaches_the_setup_and_comes_back():
    """A piece's anisotropic fabric (the add-on's Anisotropic and its three directions) is the
    setup's entry with `stretch_v`, `bend_bias`, `bend_v`; an isotropic one writes the four
    values alone; both read back as they were written."""
    aniso = core_sim.PieceFabric(0.3, 400.0, 60.0, 2e-5, 2000.0, 2.5e-5, 3e-5)
    iso = core_sim.PieceFabric(0.15, 600.0, 60.0, 2e-5)
    assert iso.entry() == {"density": 0.15, "stretch": 600.0, "shear": 60.0, "bend": 2e-5}
    assert aniso.entry()["stretch_v"] == 2000.0 and aniso.entry()["bend_v"] == 3e-5
    back = core_sim.setup_fabrics({"fabrics": [aniso.entry(), iso.entry()]}, 2)
    assert back == [aniso, iso]
    g = core_sim.garment_of(two_pieces().tailor_garment(), "g", core_sim.SimSettings(), [aniso, iso], [{}, {}])
    assert g.setup["fabrics"][0]["stretch_v"] == 2000.0 and "stretch_v" not in g.setup["fabrics"][1]
    assert core_sim.setup_fabrics(g.setup, 2) == [aniso, iso]
