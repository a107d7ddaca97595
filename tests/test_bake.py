"""tailor.bake: the frame loop shared by the CLI and the Blender add-on (no Blender here)."""

from __future__ import annotations

import numpy as np
import pytest

import tailor
from tailor import bake


def box(size: float, z: float) -> tuple[np.ndarray, np.ndarray]:
    """A closed axis-aligned box (8 vertices, 12 outward triangles) centred at (0, 0, z)."""
    h = size / 2
    v = np.array([[x, y, zz] for zz in (-h, h) for y in (-h, h) for x in (-h, h)], np.float32)
    v[:, 2] += z
    t = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                  [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]], np.int64)
    return v, t


def new_bake(square, **kw) -> bake.Bake:
    pos, tris, rest = square
    pos = pos - np.array([0.1, 0.1, -0.05], np.float32)  # centred, 5 cm above the box
    sim = tailor.Simulation(pos, tris, rest, settings=tailor.Settings(substeps=2, iterations=5))
    v, t = box(0.3, -0.15)
    cid = sim.add_mesh_collider(v, t)
    return bake.Bake(sim, [bake.Collider("box", cid, len(v))], fps=30.0, start=1, **kw)


def moving_box(frame: int) -> list[np.ndarray]:
    v, _ = box(0.3, -0.15 + 0.002 * frame)
    return [v]


def test_frames_records_and_cancel_resume_are_the_uninterrupted_run(square):
    whole = new_bake(square, preroll=3)
    assert whole.run(moving_box, 8) is True
    assert [r["frame"] for r in whole.records] == list(range(1, 9))
    assert set(bake.FIELDS) <= set(whole.records[0]) and not whole.summary()["nan"]
    parted = new_bake(square, preroll=3)
    assert parted.run(moving_box, 8, cancel=lambda: len(parted.frames) >= 3) is False
    assert parted.next_frame == 4
    assert parted.run(moving_box, 8) is True
    np.testing.assert_array_equal(parted.positions(), whole.positions())
    # A new session: the cached frames are solved again, checked, and the bake goes on.
    replayed = new_bake(square, preroll=3)
    replayed.replay(whole.positions()[:5], moving_box)
    replayed.run(moving_box, 8)
    np.testing.assert_array_equal(replayed.positions(), whole.positions())


def test_replay_refuses_a_cache_of_another_scene(square):
    other = new_bake(square, preroll=3)
    other.run(moving_box, 3)
    with pytest.raises(tailor.SimulationError, match="differs from a new solve at frame 1"):
        new_bake(square, preroll=0).replay(other.positions(), moving_box)


def test_assembly_pose_transition_and_gravity(square):
    """The preroll runs at the assembly pose under the assembly gravity, then the colliders move
    to the start frame's pose; the gravity is put back after."""
    far = [box(0.3, -5.0)[0]]  # no contact during the preroll
    b = new_bake(square, preroll=10, assembly=far, assembly_gravity=(0.0, 0.0, 0.0))
    g = tuple(b.sim.settings.gravity)
    b.step(moving_box(1))
    np.testing.assert_allclose(b.frames[0][:, 2], 0.05, atol=1e-4)  # no gravity in the preroll: it stayed
    assert tuple(b.sim.settings.gravity) == g
    b.step(moving_box(2))
    assert b.frames[1][:, 2].max() < 0.05  # gravity again
    fallen = new_bake(square, preroll=10, assembly=far)
    fallen.step(moving_box(1))
    assert fallen.frames[0][:, 2].max() < 0.0  # under gravity it fell past the (far) box's top
    moved = new_bake(square, preroll=2, assembly=far, transition=4)
    moved.step(moving_box(1))
    np.testing.assert_allclose(moved.sim.collider_positions(0), moving_box(1)[0], atol=1e-6)


def test_bad_collider_positions_name_the_collider_and_vertex(square):
    b = new_bake(square)
    v = moving_box(1)[0].copy()
    v[5, 1] = np.nan
    with pytest.raises(tailor.InvalidParameterError, match=r"collider 'box': vertex 5 is not finite"):
        b.step([v])
    with pytest.raises(tailor.InvalidParameterError, match="has 7 vertices now but 8"):
        b.step([v[:7]])
    assert not b.frames


def test_pc2_written_atomically(tmp_path, square):
    b = new_bake(square)
    b.run(moving_box, 4)
    path = tmp_path / "cache.pc2"
    bake.write_pc2_atomic(path, b.positions(), start_frame=1)
    assert [p.name for p in tmp_path.iterdir()] == ["cache.pc2"]
    np.testing.assert_array_equal(tailor.read_pc2(str(path))["frames"], b.positions())
    with pytest.raises(tailor.TailorError):
        bake.write_pc2_atomic(tmp_path / "missing" / "x.pc2", b.positions(), start_frame=1)
    assert [p.name for p in tmp_path.iterdir()] == ["cache.pc2"]


def test_collider_pins_wait_for_the_seams_then_ride_on_the_collider(tube):
    """Pins riding on a collider (`ColliderPins`) are not attached while the seams close (they
    would hold them open), are attached once every seam pair is within the ramp's gap threshold,
    and then follow the collider as it moves."""
    settings = tailor.Settings(substeps=4, iterations=10, gravity=(0.0, 0.0, 0.0))
    sim = tailor.Simulation(tube["positions"], tube["triangles"], tube["rest"], tailor.Fabric(), settings)
    for name, a, b in tube["seams"]:
        sim.add_seam(a, b, name=name)
    v, t = box(0.06, 0.15)  # inside the tube
    cid = sim.add_mesh_collider(v, t)
    top = np.flatnonzero(tube["positions"][:, 2] > 0.299)
    pins = bake.ColliderPins(cid, [(top, 100.0)])
    # One preroll frame only (`preroll_max`), so that the seams close in recorded frames.
    run = bake.Bake(sim, [bake.Collider("box", cid, len(v))], fps=30.0, start=1, preroll=1, pins=pins,
                    preroll_max=1)
    gap0 = sim.seam_gaps()[0]
    attached_at = None
    for frame in range(1, 16):
        rec = run.step([v])
        if attached_at is None and pins.attached:
            attached_at = frame
            assert rec["seam_gap_max_m"] <= settings.ramp_gap_threshold < 0.05 * gap0, rec  # all had met
            assert sorted(sim.collider_attached.tolist()) == sorted(top.tolist())
        if attached_at is None:
            assert len(sim.collider_attached) == 0
    assert attached_at is not None and attached_at > 1, attached_at  # not from the first frame
    before = sim.positions[top]
    end = run.next_frame + 10
    run.run(lambda f: [v + np.float32([0.0, 0.0, 0.005 * (f - end + 10)])], end)
    moved = sim.positions[top] - before
    # The box rose 5 cm: so did the pinned top edge, without drifting sideways.
    np.testing.assert_allclose(moved[:, 2], 0.05, atol=2e-3)
    assert np.abs(moved[:, :2]).max() < 2e-3


def test_collider_pins_wait_for_every_seam_but_not_past_the_ramp(tube):
    """Released while a seam is still open (the ramp releases when most pairs have met), the
    pins wait; once the release is over ("done") they are attached whatever the gap, so that
    a seam that never closes does not leave the garment unpinned."""
    sim = tailor.Simulation(tube["positions"], tube["triangles"], tube["rest"], tailor.Fabric(), tailor.Settings())
    for name, a, b in tube["seams"]:
        sim.add_seam(a, b, name=name)
    cid = sim.add_mesh_collider(*box(0.06, 0.15))
    pins = bake.ColliderPins(cid, [(np.arange(4), 100.0)])
    assert sim.seam_gaps()[0] > sim.settings.ramp_gap_threshold  # 8 cm open
    assert not pins.after_frame(sim, "closing") and not pins.after_frame(sim, "releasing")
    assert len(sim.collider_attached) == 0
    assert pins.after_frame(sim, "done") and sorted(sim.collider_attached.tolist()) == [0, 1, 2, 3]


def test_records_judge_the_garment_on_the_body_and_the_summary_gives_the_verdict(square):
    """A cloth resting on a box passes; pushed a metre off it (the box moved away, the cloth
    left behind) the records say it fell, and the summary names the check with its first frame;
    the worst on-body figures are over the judged (assembled) frames only."""
    run = new_bake(square)
    run.run(lambda f: [box(0.3, -0.15)[0]], 4)
    assert [r["failed"] for r in run.records] == [[]] * 4
    assert run.records[0]["centroid_shift_m"] == 0.0 and run.records[0]["on_body_fraction"] == 1.0
    s = run.summary()
    assert s["verdict"] == [] and s["on_body_fraction"] == 1.0 and s["assembled_frames"] == 4
    assert bake.summary_text(s).endswith("passes its checks") and "on body min 100 %" in bake.summary_text(s)
    run.run(lambda f: [box(0.3, -0.15)[0] + np.float32([1.0, 0.0, 0.0])], 6)
    last = run.records[-1]
    assert last["on_body_fraction"] == 0.0 and last["centroid_shift_m"] > 0.9, last
    assert [f["check"] for f in last["failed"]] == ["fell"]
    s = run.summary()
    assert [(v["check"], v["frame"]) for v in s["verdict"]] == [("fell", 5)], s["verdict"]
    assert s["on_body_fraction"] == 0.0 and s["centroid_shift_m"] > 0.9
    assert bake.verdict_lines(s)[0].startswith("fell from frame 5: the garment's centroid moved")
    assert "FAILS: fell (frame 5)" in bake.summary_text(s)
    # Frames still assembling are not judged on the body, nor counted in its worst figures.
    assembling = [dict(r, seams_closing=True, on_body_fraction=0.0, failed=[]) for r in run.records[:2]]
    s = bake.summarize(assembling + run.records[2:4])
    assert s["assembled_frames"] == 2 and s["on_body_fraction"] == 1.0 and s["verdict"] == []
    assert "still assembling" in bake.summary_text(bake.summarize(assembling))
    # A run that ends still assembling was never judged on the body: it fails "open" at its end.
    s = bake.summarize(assembling)
    assert [(v["check"], v["frame"]) for v in s["verdict"]] == [("open", 2)], s["verdict"]
    assert "still closing at the last frame" in s["verdict"][0]["reason"]


def test_judge_states_its_thresholds_and_refuses_a_dict_it_cannot_read(square):
    t = tailor.VERDICT_THRESHOLDS
    assert (t["on_body_distance_m"], t["on_body_min"], t["fell_shift_m"], t["open_gap_m"]) == (0.1, 0.25, 0.2, 0.01)
    assert t["fell_top_shift_m"] == 0.1
    assert t["checks"] == ["fell", "open", "inside", "nan"]
    run = new_bake(square)
    run.run(lambda f: [box(0.3, -0.15)[0]], 1)
    m = run.sim.metrics(run.metrics_collider)
    assert tailor.judge(m) == {"centroid_shift_m": 0.0, "top_shift_m": 0.0, "failed": []}
    open_seam = dict(m, seam_gap=0.02, seams_closing=False)
    assert [f["check"] for f in tailor.judge(open_seam, m, nan=True)["failed"]] == ["open", "nan"]
    assert tailor.judge(dict(open_seam, seams_closing=True), m)["failed"] == []
    with pytest.raises(tailor.InvalidParameterError, match="'on_body_fraction'"):
        tailor.judge({k: v for k, v in m.items() if k != "on_body_fraction"})
    with pytest.raises(tailor.InvalidParameterError, match="'centroid'"):
        tailor.judge(dict(m, centroid="up"))


def test_the_preroll_goes_on_while_the_seams_close(tube):
    """The assembly does not end on a clock: past `preroll` frames it goes on while the seams
    are still closing (the tube's 8 cm gap takes about 5 frames at 0.5 m/s), so the recorded
    frames start sewn; `preroll_max` bounds it."""
    def run(**kw):
        sim = tailor.Simulation(tube["positions"], tube["triangles"], tube["rest"], tailor.Fabric(),
                                tailor.Settings(substeps=4, iterations=10, gravity=(0.0, 0.0, 0.0)))
        for name, a, b in tube["seams"]:
            sim.add_seam(a, b, name=name)
        v, t = box(0.06, 0.15)
        cid = sim.add_mesh_collider(v, t)
        b = bake.Bake(sim, [bake.Collider("box", cid, len(v))], fps=30.0, start=1, preroll=1, **kw)
        rec = b.step([v])
        return b, rec

    b, rec = run()
    assert 3 <= b.preroll_frames < b.preroll_limit() and b.preroll_limit() == round(bake.ASSEMBLY_MAX_S * 30)
    assert not b.sim.metrics()["seams_closing"] and rec["seam_gap_max_m"] < 2e-3, (b.preroll_frames, rec)
    capped, rec = run(preroll_max=2)
    assert capped.preroll_frames == 2 and rec["seam_gap_max_m"] > 0.01, rec


def test_frames_are_judged_from_the_garment_as_sewn(square):
    """`judged_from`: the first frame until one is assembled, then the first assembled frame
    for good. Pieces that travel 30 cm while their seams close do not count as a fall; a fall
    after that does, measured from where the garment was sewn."""
    run = new_bake(square)
    run.run(lambda f: [box(0.3, -0.15)[0]], 1)
    m = run.sim.metrics(run.metrics_collider)
    placed = dict(m, seams_closing=True)
    def shifted(d, by):  # the whole garment moved: its centroid and its top
        return dict(d, **{k: [c + e for c, e in zip(d[k], by)] for k in ("centroid", "top")})

    moved = shifted(m, (0.0, 0.3, 0.0))
    travelling = dict(moved, seams_closing=True)
    ref = bake.judged_from(None, placed)
    assert bake.judged_from(ref, travelling) is ref  # still closing: still the placement
    sewn = bake.judged_from(ref, moved)
    assert sewn is moved and tailor.judge(moved, sewn)["failed"] == []
    assert [f["check"] for f in tailor.judge(moved, placed)["failed"]] == ["fell"]  # what it used to say
    fallen = shifted(moved, (0.0, 0.0, -0.25))
    assert bake.judged_from(sewn, fallen) is sewn  # for good
    assert [f["check"] for f in tailor.judge(fallen, sewn)["failed"]] == ["fell"]
    # Unfolded below its top (a skirt sewn up round the waist drops to its length): draping.
    unfolded = dict(fallen, top=sewn["top"])
    assert tailor.judge(unfolded, sewn)["failed"] == [] and tailor.judge(unfolded, sewn)["top_shift_m"] == 0.0
    # A dict without a top (written before it was measured) is judged by its centroid.
    old = {k: v for k, v in fallen.items() if k != "top"}
    assert [f["check"] for f in tailor.judge(old, {k: v for k, v in sewn.items() if k != "top"})["failed"]] == ["fell"]


def test_the_assembly_frames_are_reported_and_solve_the_same(tube):
    """`on_assembly_frame` sees every preroll frame (the hold while the seams close included)
    and every transition frame, in order, with its time, step statistics and the collider
    positions it was solved with (the smoothstep from the assembly pose to the start frame's);
    the frames solved are bit for bit those of a bake without it (which steps the preroll in one
    call)."""
    def run(**kw):
        sim = tailor.Simulation(tube["positions"], tube["triangles"], tube["rest"], tailor.Fabric(),
                                tailor.Settings(substeps=4, iterations=10, gravity=(0.0, 0.0, 0.0)))
        for name, a, b in tube["seams"]:
            sim.add_seam(a, b, name=name)
        v, t = box(0.06, 0.15)
        cid = sim.add_mesh_collider(v, t)
        b = bake.Bake(sim, [bake.Collider("box", cid, len(v))], fps=30.0, start=1, preroll=2, assembly=[v],
                      transition=3, **kw)
        b.run(lambda f: [v + np.float32([0.0, 0.0, 0.01 * f])], 3)
        return b, v

    seen: list[bake.AssemblyFrame] = []
    reported, v = run(on_assembly_frame=seen.append)
    plain, _ = run()
    np.testing.assert_array_equal(reported.positions(), plain.positions())
    assert reported.preroll_frames == plain.preroll_frames > 2  # the tube's 8 cm gap holds the rest pose
    n = reported.preroll_frames
    assert [(f.phase, f.index) for f in seen] == [("preroll", k) for k in range(1, n + 1)] + \
        [("transition", k) for k in (1, 2, 3)]
    assert seen[n - 2].stats["ramp_phase"] == "closing" and seen[n - 1].stats["ramp_phase"] != "closing"
    assert all(f.ms > 0 and "seam_gap_max" in f.stats for f in seen)
    np.testing.assert_array_equal(seen[0].colliders[0], v)
    lift = [float(np.mean(f.colliders[0][:, 2] - v[:, 2])) for f in seen[n:]]
    np.testing.assert_allclose(lift, [0.01 * (3 * t * t - 2 * t ** 3) for t in (1 / 3, 2 / 3, 1.0)], atol=1e-6)


def test_a_failed_frame_is_recorded_as_nan_and_the_run_goes_on(square):
    """`record_failure` (what `tailor simulate` does after a `SimulationError`): frame
    `next_frame` is recorded with `nan` set, no time and the positions as they are, judged
    against the same reference, and the next `step` solves the frame after it."""
    run = new_bake(square)
    run.run(moving_box, 2)
    ref = run.start_metrics
    rec = run.record_failure()
    assert rec["frame"] == 3 and rec["nan"] and rec["ms"] == 0.0 and run.records[-1] is rec
    np.testing.assert_array_equal(run.frames[-1], run.frames[-2])
    assert run.start_metrics is ref and run.next_frame == 4
    assert run.step(moving_box(4))["frame"] == 4 and run.summary()["nan"]


def test_records_say_which_backend_solved_each_frame(tube):
    """Every solved frame's record carries the backend that solved it and why the CPU did when
    the GPU was asked for; the summary counts frames per backend. Asked for the CPU, every frame
    is the CPU's, with no warning."""
    sim = tailor.Simulation(tube["positions"], tube["triangles"], tube["rest"], backend="cpu")
    run = bake.Bake(sim, [], fps=30.0, start=1)
    for _ in range(4):
        run.step([])
    assert run.records[0]["backend"] is None  # the start frame: no step of its own
    assert [r["backend"] for r in run.records[1:]] == ["cpu"] * 3
    assert all(r["backend_warning"] is None for r in run.records)
    assert run.summary()["backends"] == {"cpu": 3}
    # Where each solved frame's time went: the stages sum to their total, within the frame's.
    assert run.records[0]["stages_ms"] is None
    # No collider: nothing rests on a body, so no contact motion.
    assert all(r["contact_motion_m"] is None for r in run.records)
    for r in run.records[1:]:
        st = r["stages_ms"]
        parts = st["prediction"] + st["local"] + st["global"] + st["damping"]
        assert st["total"] > 0 and abs(parts - st["total"]) <= 1e-6 * max(1.0, st["total"]), st
        assert st["total"] <= r["ms"] and all(st[k] >= 0 for k in ("hash", "contacts", "self", "resolve")), st


def run_polled(sim, request) -> dict:
    """A request computed as the add-on's Live computes it: on a native thread (`start_async`),
    collected once `done` (polled, never waited on)."""
    pending = bake.start_async(sim, request)
    with pytest.raises(tailor.SimulationError, match="in use"):
        sim.positions  # busy while the native thread has the solver
    while not pending.done():
        pass
    return pending.finish()


def test_a_bake_driven_on_native_threads_solves_the_same_frames(tube):
    """`Bake.solves` driven with `step_async` / `metrics_async` (the add-on's Live and modal
    bake: no Python thread in Blender) gives the very frames and quality figures `step` gives,
    assembly, pins waiting for the seams and the records' frame time included."""

    def new_run():
        settings = tailor.Settings(substeps=4, iterations=10, gravity=(0.0, 0.0, 0.0))
        sim = tailor.Simulation(tube["positions"], tube["triangles"], tube["rest"], tailor.Fabric(), settings)
        for name, a, b in tube["seams"]:
            sim.add_seam(a, b, name=name)
        v, t = box(0.06, 0.15)
        cid = sim.add_mesh_collider(v, t)
        top = np.flatnonzero(tube["positions"][:, 2] > 0.299)
        run = bake.Bake(sim, [bake.Collider("box", cid, len(v))], fps=30.0, start=1, preroll=2,
                        pins=bake.ColliderPins(cid, [(top, 100.0)]), preroll_max=2)
        return run, v

    here, v = new_run()
    there, _ = new_run()
    for frame in range(1, 8):
        a = here.step([v])
        b = bake.drive(there.solves([v]), there.sim, run_polled)
        assert b is there.records[-1] and b["ms"] > 0.0
        timed = ("ms", "stages_ms")
        assert {k: x for k, x in a.items() if k not in timed} == {k: x for k, x in b.items() if k not in timed}
        assert (a["stages_ms"] or {}).keys() == (b["stages_ms"] or {}).keys()
        np.testing.assert_array_equal(here.frames[-1], there.frames[-1])
    assert there.pins.attached and here.sim.state_hash() == there.sim.state_hash()


def test_a_native_step_hands_back_its_error_and_the_simulation(square):
    """`Simulation.step_async`: the simulation says busy until `finish`, which raises the step's
    error (a diverged step rolled back, as `step`'s) and gives the simulation back either way;
    `finish` twice is an error, `wait` with a timeout does not block for ever."""
    pos, tris, rest = square
    sim = tailor.Simulation(pos, tris, rest)
    pending = sim.step_async(1.0 / 30.0, 3)
    assert pending.wait(30.0)
    stats = pending.finish()
    assert stats["wall_s"] > 0.0 and stats["substeps"] > 0
    with pytest.raises(tailor.SimulationError, match="already finished"):
        pending.finish()
    before = sim.positions
    sim.velocities = np.full((len(pos), 3), 3e38, np.float32)
    pending = sim.step_async(1.0)
    with pytest.raises(tailor.SimulationError, match="in use"):
        sim.step(1.0)
    with pytest.raises(tailor.SimulationError, match="rolled back"):
        pending.finish()
    np.testing.assert_array_equal(sim.positions, before)
    m = sim.metrics_async(None).finish()
    assert m == sim.metrics(None)


def test_the_summarys_frame_time_leaves_the_start_frame_out(tube):
    """The start frame (the assembly's end) is marked `start` and its time, the whole assembly's,
    is not a frame's: the summary's mean `ms` is over the frames that were a step (over the
    start frame alone when it is the only record)."""
    sim = tailor.Simulation(tube["positions"], tube["triangles"], tube["rest"], backend="cpu")
    run = bake.Bake(sim, [], fps=30.0, start=1, preroll=5)
    for _ in range(3):
        run.step([])
    assert [r["start"] for r in run.records] == [True, False, False]
    assert bake.summarize(run.records)["ms"] == pytest.approx(np.mean([r["ms"] for r in run.records[1:]]))
    assert bake.summarize(run.records[:1])["ms"] == pytest.approx(run.records[0]["ms"])
