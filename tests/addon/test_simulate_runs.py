"""The modal bake's and Live's runs (`simulate/runs.py`) ended the ways Blender ends them: the
operator cancelled (a file opened, Blender quitting: `Operator.cancel` calls `run.cancel`) and
a file opened (the `load_pre` handler ends every run while the old file is still loaded).

The bpy wheel has no event loop for modal operators, so the tests drive the runs the operators
hold: real window manager timers, the real solver on its native threads, the real scene."""

from __future__ import annotations

import time

import numpy as np
import pytest

import bpy

from simulate_scene import shirt_on_character


def mesh_co(obj) -> np.ndarray:
    co = np.empty(len(obj.data.vertices) * 3, np.float32)
    obj.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def bake_scene(tmp_path, frames=(1, 3)) -> dict:
    sc = shirt_on_character(tmp_path / "scene.blend", frames=frames, preroll=0)
    sc["scene"].tailor_simulate.transition = 0
    return sc


def bake_run_mid_frame(addon, scene):
    """A modal bake ticked until a frame is done and the next one is solving."""
    job, _ = addon.simulate.job.job_for(scene, resume=False)
    run = addon.simulate.runs.BakeRun(bpy.context, job)
    deadline = time.monotonic() + 120
    while not (job.run.frames and run.solver.busy):
        assert not run.tick(bpy.context), "the bake ended before it could be cancelled"
        assert time.monotonic() < deadline
        time.sleep(0.005)
    return run


def assert_stopped(solver) -> None:
    assert not solver.busy
    with pytest.raises(RuntimeError, match="stopped"):
        solver.submit(1, [])


def test_blender_cancelling_the_modal_bake_stops_it_and_writes_nothing(addon, tmp_path):
    sc = bake_scene(tmp_path)
    scene, pieces = sc["scene"], sc["pieces"]
    runs, job_mod = addon.simulate.runs, addon.simulate.job
    assert "cancel" in vars(addon.simulate.operators.TAILOR_OT_bake)
    run = bake_run_mid_frame(addon, scene)
    assert run.running and run in runs.RUNNING
    solver = run.solver
    run.cancel(bpy.context)
    assert not run.running and run not in runs.RUNNING and run.timer is None
    assert_stopped(solver)
    # Nothing half-applied: no cache, no report, no modifier, no job kept for resume; the
    # timeline is back at the start frame.
    assert not list((tmp_path / "tailor_cache").glob("*"))
    s = scene.tailor_simulate
    assert s.baked_frames == 0 and s.bake_report == ""
    assert all(o.modifiers.get(job_mod.MODIFIER) is None for o in pieces)
    assert not job_mod.JOBS and scene.frame_current == 1
    run.cancel(bpy.context)  # a second cancel (after the load_pre handler's) does nothing
    assert not run.running


def test_esc_ends_the_modal_bake_keeping_and_reporting_the_frames_done(addon, tmp_path):
    sc = bake_scene(tmp_path)
    scene = sc["scene"]
    run = bake_run_mid_frame(addon, scene)
    message = run.end(bpy.context, cancelled=True)  # what the operator does on Esc, then reports
    assert message.startswith("Cancelled after frames 1-") and "Resume continues" in message
    assert 1 <= scene.tailor_simulate.baked_frames < 3 and not run.running
    assert list((tmp_path / "tailor_cache").glob("*.pc2"))
    addon.simulate.job.JOBS.clear()


def test_blender_cancelling_live_stops_it_and_restores_the_pieces(addon, tmp_path):
    sc = shirt_on_character(tmp_path / "scene.blend", frames=(1, 32), pins=False)
    scene, pieces = sc["scene"], sc["pieces"]
    runs, live, draw = addon.simulate.runs, addon.simulate.live, addon.simulate.draw
    assert "cancel" in vars(addon.simulate.operators.TAILOR_OT_live)
    before = {o.name: mesh_co(o) for o in pieces}
    run = runs.LiveRun(bpy.context)
    session = run.session
    assert scene.tailor_simulate.live_running and draw._handle is not None and run.running
    for _ in range(2):
        scene.frame_set(scene.frame_current + 1)
        session.tick(bpy.context, block=True)
    assert session.frames_applied == 2 and session.error is None
    assert max(np.abs(mesh_co(o) - before[o.name]).max() for o in pieces) > 1e-4
    session.submit(bpy.context)  # a frame in progress when Blender cancels
    run.cancel(bpy.context)
    assert not scene.tailor_simulate.live_running and scene.name not in live.SESSIONS
    assert draw._handle is None and run.timer is None and run not in runs.RUNNING
    assert_stopped(session.solver)
    for o in pieces:
        np.testing.assert_array_equal(mesh_co(o), before[o.name])


def test_opening_a_file_ends_every_run_while_the_old_file_is_loaded(addon, tmp_path):
    sc = bake_scene(tmp_path, frames=(1, 32))
    scene = sc["scene"]
    runs, live = addon.simulate.runs, addon.simulate.live
    live_run = runs.LiveRun(bpy.context)
    session = live_run.session
    session.tick(bpy.context, block=True)
    bake = bake_run_mid_frame(addon, scene)
    bake_solver = bake.solver
    bpy.ops.wm.read_homefile(use_empty=True)  # runs the load_pre handler, then loads
    assert not live.SESSIONS and live_run.session is None and bake.job is None
    assert_stopped(session.solver)
    assert_stopped(bake_solver)
    assert not addon.simulate.job.JOBS
    # Blender then cancels the operators: only the window manager's timers are left to remove.
    live_run.cancel(bpy.context)
    bake.cancel(bpy.context)
    assert not runs.RUNNING and not live_run.running and not bake.running
