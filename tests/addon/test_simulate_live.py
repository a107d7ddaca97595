"""Live mode through its non-modal entry point (`tailor.live_step`): the same session, worker
thread and main-thread apply as the modal timer, ticked by the test. The modal operator itself
needs a window: the interactive tests run it under Xvfb (docs/addon.md)."""

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


@pytest.fixture
def live_scene(addon, tmp_path):
    sc = shirt_on_character(tmp_path / "scene.blend", frames=(1, 32), pins=False)  # it paints its own
    yield sc
    bpy.ops.tailor.live_stop()


def test_live_follows_the_timeline_applies_edits_and_restores(addon, live_scene, monkeypatch):
    scene, pieces = live_scene["scene"], live_scene["pieces"]
    live = addon.simulate.live
    before = {o.name: mesh_co(o) for o in pieces}
    # Pins fixed in place (the default, riding on the character, is tested in
    # test_simulate_pins.py).
    scene.tailor_simulate.pin_mode = "FIXED"
    assert bpy.ops.tailor.live_step(count=3, advance=True) == {"FINISHED"}
    session = live.SESSIONS[scene.name]
    assert scene.tailor_simulate.live_running and scene.frame_current == 4
    assert session.frames_applied == 3 and session.last.frame == 4
    moved = max(np.abs(mesh_co(o) - before[o.name]).max() for o in pieces)
    assert moved > 1e-3  # the solved positions were written into the pieces
    stats = session.stats()
    assert stats["fps"] > 0 and stats["seam_gap_mm"] > 0 and np.isfinite(stats["strain"])
    assert addon.simulate.draw.overlay_lines(stats)[0].startswith("Tailor Live")
    # Edits apply without a restart: pin a whole piece (painted) and stiffen a fabric.
    pinned = bpy.data.objects["left_btorso"]
    vg = pinned.vertex_groups.new(name="tailor_pin")
    vg.add(list(range(len(pinned.data.vertices))), 1.0, "REPLACE")
    pieces[0].tailor_piece.stretch *= 2
    solver = session.solver
    assert bpy.ops.tailor.live_step(count=live.MAPS_EVERY + 1, advance=True) == {"FINISHED"}
    assert live.SESSIONS[scene.name] is session and session.solver is solver
    assert session.fabrics[0].stretch == pieces[0].tailor_piece.stretch
    assert len(session.hard_pins) == len(pinned.data.vertices)
    # ... a repainted Bend Scale map re-applies the fabric, and self-collision turned on at 7 mm,
    # with the cloth's friction, reaches the solver.
    applied = []
    monkeypatch.setattr(addon.simulate.live, "_reapply",
                        lambda g, sim, part, real=addon.simulate.live._reapply: (applied.append(part), real(g, sim, part)))
    bent = pieces[1]
    bent.vertex_groups.new(name="tailor_bend_scale").add(list(range(len(bent.data.vertices))), 1.0, "REPLACE")
    scene.tailor_simulate.self_collision = True
    scene.tailor_simulate.self_collision_radius = 0.007
    scene.tailor_simulate.friction_static = 0.65
    assert bpy.ops.tailor.live_step(count=live.MAPS_EVERY + 1, advance=True) == {"FINISHED"}
    assert applied.count("fabric") == 1 and "bend_scale" in session.maps[pieces.index(bent)]
    assert any(n == "bend_scale" and k == pieces.index(bent) for n, k, _ in session.tgarment.particle_params)
    sc = solver.run.sim.self_collision
    assert sc["enabled"] and sc["radius_setting"] == pytest.approx(0.007) and sc["radius"] == pytest.approx(0.007)
    assert sc["static_friction"] == pytest.approx(0.65)
    # Hard pins hold the painted vertices where the artist placed them.
    np.testing.assert_allclose(mesh_co(pinned), before[pinned.name], atol=1e-5)
    # Stopping puts every piece back as it was.
    assert bpy.ops.tailor.live_stop() == {"FINISHED"}
    assert scene.name not in live.SESSIONS and not scene.tailor_simulate.live_running
    for o in pieces:
        np.testing.assert_array_equal(mesh_co(o), before[o.name])


def test_the_solve_runs_off_the_main_thread_with_the_gil_released(addon, live_scene):
    scene = live_scene["scene"]
    assert bpy.ops.tailor.live_step(count=1) == {"FINISHED"}
    session = addon.simulate.live.SESSIONS[scene.name]
    assert session.submit(bpy.context)
    # While the worker solves, Python keeps running here: the step released the GIL.
    spins, t0 = 0, time.perf_counter()
    result = None
    while result is None and time.perf_counter() - t0 < 60:
        result = session.solver.poll()
        spins += 1
    assert result is not None and result.error is None
    assert result.solve_ms > 1.0
    assert spins > 100, (spins, result.solve_ms)  # the main thread was never blocked for the solve


def test_live_with_a_bad_setting_reports_and_changes_nothing(addon, live_scene):
    scene, pieces = live_scene["scene"], live_scene["pieces"]
    before = {o.name: mesh_co(o) for o in pieces}
    scene.tailor_simulate.preset = "CUSTOM"
    scene.tailor_simulate.substeps = 0
    with pytest.raises(RuntimeError, match="Live simulation failed: substeps is 0"):
        bpy.ops.tailor.live_step(count=2)
    assert scene.name not in addon.simulate.live.SESSIONS and not scene.tailor_simulate.live_running
    for o in pieces:
        np.testing.assert_array_equal(mesh_co(o), before[o.name])


def test_saving_during_live_keeps_the_pattern_placement_not_the_drape(addon, live_scene, tmp_path):
    """A save while Live runs writes the pieces as they were before Live (read back from the
    saved file), and the drape is back on them after the save."""
    pieces = live_scene["pieces"]
    before = {o.name: mesh_co(o) for o in pieces}
    assert bpy.ops.tailor.live_step(count=2) == {"FINISHED"}
    draped = {o.name: mesh_co(o) for o in pieces}
    assert any(not np.allclose(draped[n], before[n]) for n in before), "Live moved nothing"
    path = tmp_path / "saved_during_live.blend"
    assert bpy.ops.wm.save_as_mainfile(filepath=str(path), copy=True) == {"FINISHED"}
    for o in pieces:
        np.testing.assert_array_equal(mesh_co(o), draped[o.name])
    names = {o.data.name: o.name for o in pieces}
    with bpy.data.libraries.load(str(path)) as (src, dst):
        dst.meshes = [m for m in src.meshes if m in names]
    assert len(dst.meshes) == len(pieces)
    try:
        for me in dst.meshes:
            co = np.empty(len(me.vertices) * 3, np.float32)
            me.vertices.foreach_get("co", co)
            saved_as = names[me.name.rsplit(".", 1)[0] if me.name not in names else me.name]
            np.testing.assert_array_equal(co.reshape(-1, 3), before[saved_as])
    finally:
        for me in dst.meshes:
            bpy.data.meshes.remove(me)


def test_live_colours_the_pieces_by_a_fit_map(addon, live_scene):
    # Issue 28: with a Fit Map chosen, Live's measured frames write the three maps as point
    # attributes on every piece and the chosen one's colours as the active colour attribute.
    scene, pieces = live_scene["scene"], live_scene["pieces"]
    fit = addon.core.fit_maps
    scene.tailor_simulate.fit_map = "PRESSURE"
    assert bpy.ops.tailor.live_step(count=2, advance=True) == {"FINISHED"}
    session = addon.simulate.live.SESSIONS[scene.name]
    assert session.solver.measured is not None and session.solver.measured.fit_maps is not None
    maps = session.solver.measured.fit_maps
    offsets = list(session.garment.offsets) + [session.garment.num_particles]
    for k, o in enumerate(pieces):
        n = len(o.data.vertices)
        for key, name in fit.ATTRIBUTES.items():
            got = np.empty(n, np.float32)
            o.data.attributes[name].data.foreach_get("value", got)
            # The piece's share of the garment's map, written as it was measured.
            assert np.array_equal(got, np.asarray(maps[key], np.float32)[offsets[k]:offsets[k + 1]]), (o.name, key)
        col = o.data.color_attributes.active_color
        assert col is not None and col.name == fit.COLOUR_ATTRIBUTE
        rgba = np.empty(n * 4, np.float32)
        col.data.foreach_get("color", rgba)
        pressure = np.asarray(maps["pressure"], np.float32)[offsets[k]:offsets[k + 1]]
        assert np.allclose(rgba.reshape(-1, 4), fit.colours("PRESSURE", pressure), atol=1e-6)
    # Two frames in, the shirt is still as placed round the character (Live has no preroll):
    # nothing far inside, and nothing off the body is pressed.
    p, d = np.asarray(maps["pressure"]), np.asarray(maps["distance"])
    assert d.min() > -0.01 and (p >= 0).all() and (p[d > 0.01] == 0).all()
