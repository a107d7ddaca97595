"""The add-on preferences (solver backend, default cache folder) used by the bake and Live where
a scene does not choose its own."""

from __future__ import annotations

import bpy
import pytest

from conftest import MODULE
from simulate_scene import shirt_on_character


@pytest.fixture
def prefs(addon):
    """The add-on's preferences, put back as they were after the test (they outlive a file)."""
    p = bpy.context.preferences.addons[MODULE].preferences
    saved = (p.backend, p.cache_dir, p.threads)
    yield p
    p.backend, p.cache_dir, p.threads = saved


def test_a_scene_takes_the_preferences_backend_unless_it_chooses_one(addon, scene, prefs):
    gather = addon.simulate.gather
    s = scene.tailor_simulate
    assert s.backend == "PREFERENCES" and prefs.backend == "AUTO"
    assert gather.sim_settings(scene).backend == "auto"
    prefs.backend = "CPU"
    assert gather.sim_settings(scene).backend == "cpu"
    s.backend = "GPU"  # the scene's own choice wins
    assert gather.sim_settings(scene).backend == "gpu"


def test_bake_and_live_use_the_preferences_folder_and_backend(addon, tmp_path, prefs):
    sc = shirt_on_character(tmp_path / "scene.blend", frames=(1, 1), preroll=0)
    scene = sc["scene"]
    s = scene.tailor_simulate
    s.transition = 0
    assert s.cache_dir == ""  # the preferences' folder
    studio = tmp_path / "studio_cache"
    prefs.cache_dir = str(studio)
    prefs.backend = "CPU"
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    assert next(studio.glob("*.report.json")) and list(studio.glob("*.pc2"))
    assert not (tmp_path / "tailor_cache").exists()
    job, _ = addon.simulate.job.job_for(scene, resume=False)
    assert job.settings.backend == "cpu" and job.folder == str(studio)
    # A scene's own folder wins.
    s.cache_dir = "//own_cache"
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    assert list((tmp_path / "own_cache").glob("*.pc2"))
    # Live builds its solver with the same backend, on the preferences' threads.
    prefs.threads = 1
    assert bpy.ops.tailor.live_step(count=1) == {"FINISHED"}
    try:
        session = addon.simulate.live.SESSIONS[scene.name]
        assert session.settings.backend == "cpu" and session.solver.run.sim.threads == 1
    finally:
        bpy.ops.tailor.live_stop()


def test_solver_threads_are_one_per_core_unless_set(addon, scene, prefs):
    """Solver Threads 0 leaves the module's pool (one thread per core); n is gathered for the
    solver (the Live test above checks a simulation built on it)."""
    gather = addon.simulate.gather
    assert prefs.threads == 0 and gather.sim_settings(scene).threads is None
    prefs.threads = 3
    assert gather.sim_settings(scene).threads == 3
