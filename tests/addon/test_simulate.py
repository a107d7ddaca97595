"""Simulate: the GarmentCode shirt baked on the walking sample character, through the add-on.

The scene (`simulate_scene.py`): `sample_blends/character.blend` (rigged mean body, walk
action), the shirt imported with `tailor.import_pattern` at 3 cm (at 4 cm a sleeve catches in
the arm while the seams close) and lifted 4 cm, an isotropic collider proxy of the body (voxel remesh at 2 cm
bound by Surface Deform: 12.7k triangles instead of the body's 47.5k, lighter for 2-core CI).
The garment assembles at the rest pose without gravity (60 frames of preroll), moves into the
walk's first pose over 40 frames, then 8 frames of the walk are recorded.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import bpy

from simulate_scene import shirt_on_character

FRAMES = (1, 8)


def evaluated_local(obj) -> np.ndarray:
    dg = bpy.context.evaluated_depsgraph_get()
    ev = obj.evaluated_get(dg)
    me = ev.to_mesh()
    co = np.empty(len(me.vertices) * 3, np.float32)
    me.vertices.foreach_get("co", co)
    ev.to_mesh_clear()
    return co.reshape(-1, 3)


def world_frame(pieces, caches: dict, k: int) -> np.ndarray:
    """Frame `k` of the per-piece caches (piece-local) in world space, all pieces."""
    out = []
    for o, c in zip(pieces, caches.values()):
        m = np.array(o.matrix_world, np.float64)
        out.append(c[k].astype(np.float64) @ m[:3, :3].T + m[:3, 3])
    return np.concatenate(out).astype(np.float32)


def cache_dir(tmp_path):
    return tmp_path / "tailor_cache"


def read_caches(tmp_path) -> dict:
    import tailor

    return {p.name: tailor.read_pc2(str(p))["frames"] for p in sorted(cache_dir(tmp_path).glob("*.pc2"))}


def test_proxy_is_isotropic_follows_the_body_and_is_hidden_from_render(addon, tmp_path):
    sc = shirt_on_character(tmp_path / "scene.blend", frames=FRAMES)
    proxy, body = sc["collider"], sc["body"]
    c = proxy.tailor_collider
    assert c.is_collider and c.proxy_of == body and not body.tailor_collider.is_collider
    assert proxy.hide_render and proxy.display_type == "WIRE"
    # The spread of edge lengths shrinks: the body's long limb triangles are gone.
    assert c.spread_proxy_ratio < 0.5 * c.spread_source_ratio, (c.spread_source_ratio, c.spread_proxy_ratio)
    assert c.spread_proxy_cv < c.spread_source_cv
    # On or outside the body's surface (the voxel surface alone lies up to half a voxel inside).
    import tailor

    dg = bpy.context.evaluated_depsgraph_get()
    gather = addon.simulate.gather
    body_tris = gather.evaluated_triangles(body, dg).astype(np.uint32)
    inside = tailor.penetration(gather.evaluated_positions(proxy, dg), gather.evaluated_positions(body, dg), body_tris)
    assert inside["count"] == 0, inside
    # Bound by Surface Deform: it moves with the walking body.
    scene = sc["scene"]
    scene.frame_set(1)
    a = evaluated_local(proxy)
    scene.frame_set(9)
    b = evaluated_local(proxy)
    assert np.abs(a - b).max() > 0.05


def test_bake_walks_plays_back_and_keeps_quality(addon, tmp_path, capsys):
    import tailor

    sc = shirt_on_character(tmp_path / "scene.blend", frames=FRAMES)
    scene, pieces = sc["scene"], sc["pieces"]
    rest_co = {o.name: np.array([v.co[:] for v in o.data.vertices], np.float32) for o in pieces}
    capsys.readouterr()
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    n = FRAMES[1] - FRAMES[0] + 1
    # Headless, the log shows every frame (a render farm's only progress).
    lines = [line for line in capsys.readouterr().out.splitlines() if line.startswith("Tailor: frame ")]
    assert len(lines) == n and lines[-1].startswith(f"Tailor: frame {FRAMES[1]} ({n}/{n}) "), lines
    # One PC2 per piece, beside the .blend, and the quality report.
    caches = read_caches(tmp_path)
    assert len(caches) == len(pieces)
    assert all(c.shape == (n, len(o.data.vertices), 3) for c, o in zip(caches.values(), pieces))
    assert not list(cache_dir(tmp_path).glob("*partial*"))
    report = json.loads(next(cache_dir(tmp_path).glob("*.report.json")).read_text())
    assert [r["frame"] for r in report["frames"]] == list(range(FRAMES[0], FRAMES[1] + 1))
    assert not any(r["nan"] for r in report["frames"])
    assert scene.tailor_simulate.baked_frames == n
    all_frames = np.concatenate(list(caches.values()), axis=1)
    assert np.isfinite(all_frames).all()
    # It hangs on the shoulders at every frame (metrics of a garment that fell off are trivially
    # good): its top at the shoulders, its hem no more than 15 cm below where it was placed
    # (sewn and hanging from the shoulders it settles about 10 cm lower), and it moves with the walk.
    placed_hem = min(np.concatenate([np.array([o.matrix_world @ v.co for v in o.data.vertices])[:, 2]
                                     for o in pieces]))
    for k in range(n):
        z = world_frame(pieces, caches, k)[:, 2]
        assert z.max() > 1.35 and z.min() > placed_hem - 0.15, (k, z.min(), z.max(), placed_hem)
    assert np.abs(all_frames[-1] - all_frames[0]).max() > 0.01
    # Played back by Mesh Cache modifiers: the evaluated pieces are the cached frames, and the
    # pieces' own meshes are untouched.
    for f in (FRAMES[0], 4, FRAMES[1]):
        scene.frame_set(f)
        for o in pieces:
            mod = o.modifiers["Tailor Cache"]
            assert mod.type == "MESH_CACHE" and mod.cache_format == "PC2"
            cache = tailor.read_pc2(bpy.path.abspath(mod.filepath))["frames"]
            np.testing.assert_allclose(evaluated_local(o), cache[f - FRAMES[0]], atol=1e-6)
    for o in pieces:
        np.testing.assert_array_equal(np.array([v.co[:] for v in o.data.vertices], np.float32), rest_co[o.name])


def test_baked_frames_meet_the_quality_thresholds(addon, tmp_path):
    """The issue's thresholds at every recorded frame: seam gap under 1 mm, penetration (into the
    collider and into the character's own mesh) under the thickness, no NaN. The shirt as the
    scene makes it (shoulder lines pinned, the 2 cm proxy, the panel's Final preset) on the
    walk after the 60-frame assembly and the 40-frame transition; measured 2026-11-22: seam gap
    0.25-0.51 mm, nothing inside, the same with 1 and 2 threads."""
    import tailor

    sc = shirt_on_character(tmp_path / "scene.blend", frames=FRAMES)
    scene, pieces, body = sc["scene"], sc["pieces"], sc["body"]
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    report = json.loads(next(cache_dir(tmp_path).glob("*.report.json")).read_text())
    print("frames (seam gap, penetration mm):",
          [(r["frame"], round(r["seam_gap_max_m"] * 1e3, 2), round(r["penetration_max_m"] * 1e3, 2)) for r in report["frames"]])
    thickness = scene.tailor_simulate.thickness
    caches = read_caches(tmp_path)
    gather = addon.simulate.gather
    for r in report["frames"]:
        assert not r["nan"], r
        assert r["seam_gap_max_m"] < 1e-3, r
        assert r["penetration_max_m"] < thickness, r
        scene.frame_set(r["frame"])
        dg = bpy.context.evaluated_depsgraph_get()
        pen = tailor.penetration(world_frame(pieces, caches, r["frame"] - FRAMES[0]),
                                 gather.evaluated_positions(body, dg),
                                 gather.evaluated_triangles(body, dg).astype(np.uint32))
        assert pen["max_depth"] < thickness, (r["frame"], pen)


def test_per_garment_cache_plays_on_a_joined_object(addon, tmp_path):
    sc = shirt_on_character(tmp_path / "scene.blend", frames=(1, 2))
    scene = sc["scene"]
    scene.tailor_simulate.cache_mode = "GARMENT"
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    caches = read_caches(tmp_path)
    assert list(caches) == ["shirt_mean_specification.pc2"]
    joined = bpy.data.objects["shirt_mean_specification (baked)"]
    scene.frame_set(2)
    np.testing.assert_allclose(evaluated_local(joined), caches["shirt_mean_specification.pc2"][1], atol=1e-6)


def test_a_bake_that_crashes_keeps_its_checkpoints_and_resumes(addon, tmp_path, monkeypatch):
    """A running bake writes checkpoints (every `CHECKPOINT_S`) beside the caches, so a crash
    mid-bake keeps the frames written, the previous bake's caches stay whole, and Resume
    continues from the checkpoint."""
    sc = shirt_on_character(tmp_path / "scene.blend", frames=FRAMES)
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    whole = read_caches(tmp_path)
    job_mod = addon.simulate.job
    job_mod.JOBS.clear()
    monkeypatch.setattr(job_mod, "CHECKPOINT_S", 0.0)  # a checkpoint after every frame
    step = job_mod.BakeJob.step

    def crash_after_four(job):
        if len(job.run.frames) == 4:
            raise RuntimeError("the machine went down")
        return step(job)

    monkeypatch.setattr(job_mod.BakeJob, "step", crash_after_four)
    with pytest.raises(RuntimeError, match="went down"):
        bpy.ops.tailor.bake()
    import tailor

    points = sorted(cache_dir(tmp_path).glob("*.checkpoint.pc2"))
    assert len(points) == len(whole)
    for p in points:
        c = tailor.read_pc2(str(p))["frames"]
        np.testing.assert_array_equal(c, whole[p.name.replace(".checkpoint", "")][:4])
    # The previous bake, which the scene plays, is whole.
    for name, c in read_caches(tmp_path).items():
        if ".checkpoint" not in name:
            np.testing.assert_array_equal(c, whole[name])
    monkeypatch.setattr(job_mod.BakeJob, "step", step)
    job_mod.JOBS.clear()  # a new session after the crash: the checkpoint's frames are solved again
    job, resumed = job_mod.job_for(sc["scene"], resume=True)
    assert resumed == 4
    while not job.done:
        job.step()
    job_mod.finish(sc["scene"], job, cancelled=False)
    assert read_caches(tmp_path).keys() == whole.keys()  # the checkpoint is gone
    for name, c in read_caches(tmp_path).items():
        np.testing.assert_allclose(c, whole[name], atol=1e-6, rtol=0)
    assert sc["scene"].frame_current == FRAMES[0]


def test_cancel_and_resume_give_the_uninterrupted_frames(addon, tmp_path):
    sc = shirt_on_character(tmp_path / "scene.blend", frames=FRAMES)
    scene = sc["scene"]
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    whole = read_caches(tmp_path)
    job_mod = addon.simulate.job
    for kept_in_memory in (True, False):
        # What Esc does in the modal bake: stop between frames, write the frames done.
        job, _ = job_mod.job_for(scene, resume=False)
        assert job.run.run(job.colliders_at, FRAMES[1], cancel=lambda: len(job.run.frames) >= 3) is False
        message = job_mod.finish(scene, job, cancelled=True)
        assert "Cancelled after frames 1-3" in message
        partial = read_caches(tmp_path)
        assert all(len(c) == 3 for c in partial.values())
        for name, c in partial.items():
            np.testing.assert_array_equal(c, whole[name][:3])
        if not kept_in_memory:  # a new session: the cached frames are solved again and checked
            job_mod.JOBS.clear()
        assert bpy.ops.tailor.bake(resume=True) == {"FINISHED"}
        resumed = read_caches(tmp_path)
        for name, c in resumed.items():
            if kept_in_memory:
                np.testing.assert_array_equal(c, whole[name])
            else:  # re-solved frames go through the pieces' local frames again: float rounding
                np.testing.assert_allclose(c, whole[name], atol=1e-6, rtol=0)
        assert not job_mod.JOBS


def _scene_state(scene) -> tuple:
    objs = sorted(o.name for o in bpy.data.objects)
    mods = sorted((o.name, m.name) for o in bpy.data.objects for m in o.modifiers)
    co = {o.name: np.array([v.co[:] for v in o.data.vertices]) for o in bpy.data.objects if o.type == "MESH"}
    return objs, mods, scene.frame_current, co


def _same_state(a, b) -> None:
    assert a[:3] == b[:3]
    assert a[3].keys() == b[3].keys()
    for k in a[3]:
        np.testing.assert_array_equal(a[3][k], b[3][k])


def test_bad_settings_fail_with_a_report_and_change_nothing(addon, tmp_path):
    sc = shirt_on_character(tmp_path / "scene.blend", frames=(3, 5))
    scene = sc["scene"]
    scene.frame_set(7)
    s = scene.tailor_simulate
    s.preset = "CUSTOM"
    s.substeps = 0
    before = _scene_state(scene)
    with pytest.raises(RuntimeError, match=r"Baking failed: substeps is 0: must be at least 1"):
        bpy.ops.tailor.bake()
    _same_state(before, _scene_state(scene))
    assert not cache_dir(tmp_path).exists()
    s.substeps = 8
    # A collider with a NaN vertex.
    me = bpy.data.meshes.new("broken")
    me.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0), (float("nan"), 0, 1)], [], [(0, 1, 2), (0, 2, 3)])
    broken = bpy.data.objects.new("Broken Collider", me)
    scene.collection.objects.link(broken)
    broken.tailor_collider.is_collider = True
    before = _scene_state(scene)
    with pytest.raises(RuntimeError, match=r"Baking failed: collider 'Broken Collider': vertex 3 is not finite"):
        bpy.ops.tailor.bake()
    _same_state(before, _scene_state(scene))
    assert not cache_dir(tmp_path).exists()


def test_workbench_render_of_a_baked_frame_shows_the_garment(addon, tmp_path):
    sc = shirt_on_character(tmp_path / "scene.blend", frames=(1, 3))
    scene, pieces = sc["scene"], sc["pieces"]
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    scene.frame_set(3)
    r = scene.render
    r.engine = "BLENDER_WORKBENCH"
    r.resolution_x, r.resolution_y, r.resolution_percentage = 240, 360, 100
    r.image_settings.file_format = "PNG"
    # Workbench's default grey is the body's too: give the shirt a blue material.
    mat = bpy.data.materials.new("Shirt")
    mat.diffuse_color = (0.15, 0.35, 0.8, 1.0)
    for o in pieces:
        o.data.materials.append(mat)

    def render(path, show_garment: bool) -> np.ndarray:
        for o in pieces:
            o.hide_render = not show_garment
        r.filepath = str(path)
        bpy.ops.render.render(write_still=True)
        assert path.is_file() and path.stat().st_size > 0
        img = bpy.data.images.load(str(path))
        px = np.array(img.pixels[:], np.float32).reshape(img.size[1], img.size[0], -1)
        bpy.data.images.remove(img)
        return px

    with_garment = render(tmp_path / "baked_frame3.png", True)
    without = render(tmp_path / "body_frame3.png", False)
    background = with_garment[0, 0]
    not_background = np.abs(with_garment - background).max(axis=2) > 0.02
    assert not_background.mean() > 0.05  # the character and the shirt, not an empty image
    # The shirt itself is in the picture: its blue covers a visible share of the frame (about
    # 0.9 % at this size: a fitted shirt on a small full-body figure), and nothing blue without it.
    def blue(px):
        return px[..., 2] - px[..., 0] > 0.15

    assert blue(with_garment).mean() > 0.005, blue(with_garment).sum()
    assert not blue(without).any()
    garment_pixels = (np.abs(with_garment - without).max(axis=2) > 0.02).sum()
    assert garment_pixels >= blue(with_garment).sum(), garment_pixels


def test_the_panel_opens_in_final_with_the_modules_numbers(addon, tmp_path):
    """One source for presets and defaults: the panel opens labelled Final with the module's
    Final preset, choosing a preset gives its numbers, and the setup defaults are the module's."""
    import tailor

    sc = shirt_on_character(tmp_path / "scene.blend", frames=(1, 2))
    s = sc["scene"].tailor_simulate
    final = tailor.Settings.preset("final")
    assert s.preset == "FINAL"
    assert (s.substeps, s.iterations) == (final.substeps, final.iterations)
    assert s.tolerance == pytest.approx(final.tolerance)
    s.preset = "PREVIEW"
    preview = tailor.Settings.preset("preview")
    assert (s.substeps, s.iterations, round(s.tolerance, 6)) == (preview.substeps, preview.iterations,
                                                                 round(preview.tolerance, 6))
    s.preset = "FINAL"
    assert (s.substeps, s.iterations) == (final.substeps, final.iterations)
    setup = tailor.DEFAULT_SETUP
    assert s.thickness == pytest.approx(setup["thickness"]) and s.pin_stiffness == pytest.approx(setup["pin_stiffness"])
    assert (s.friction_static, s.friction_kinetic) == (pytest.approx(setup["friction"]["static"]),
                                                       pytest.approx(setup["friction"]["kinetic"]))
    assert s.seam_bend_stiffness == pytest.approx(setup["seam_bend_stiffness"])


def test_an_exported_garment_bakes_in_the_module_as_in_the_addon(addon, tmp_path):
    """Round trip: the garment exported by the add-on, baked by the module's bake loop
    (`tailor.bake.Bake`) with the same settings, collider positions per frame and assembly
    schedule, gives the add-on's own bake of it, bit for bit (both build the simulation in
    the core from the same garment: pieces as they stand, setup, painted pins)."""
    import tailor
    from tailor import bake

    sc = shirt_on_character(tmp_path / "scene.blend", frames=(1, 3))
    scene, s = sc["scene"], sc["scene"].tailor_simulate
    s.preroll, s.transition = 3, 2
    job = addon.simulate.job.BakeJob(scene)
    job.run.preroll_max = 3  # a short assembly (the shirt is not sewn by then): the same on both sides
    positions = {f: job.colliders_at(f) for f in range(job.start, job.end + 1)}
    assert job.run.run(lambda f: positions[f], job.end)
    ours = job.run.positions()

    out = tmp_path / "shirt.json"
    assert bpy.ops.tailor.export_garment(filepath=str(out)) == {"FINISHED"}
    g = tailor.Garment.load(str(out))
    sim, _ = g.build_simulation(settings=job.settings.to_tailor(), backend=job.settings.backend)
    dg = bpy.context.evaluated_depsgraph_get()
    colliders = []
    for c, o, start in zip(job.run.colliders, job.collider_objects, job.run.assembly):
        tris = addon.simulate.gather.evaluated_triangles(o, dg)
        cid = sim.add_mesh_collider(start, tris, static_friction=o.tailor_collider.friction_static,
                                    kinetic_friction=o.tailor_collider.friction_kinetic)
        colliders.append(bake.Collider(c.name, cid, c.num_vertices))
    pins = bake.ColliderPins(colliders[0].id, g.attach_groups())
    assert len(pins.particles) > 0  # the shirt's painted shoulder lines
    theirs = bake.Bake(sim, colliders, job.settings.fps, job.start, s.preroll, job.run.assembly, s.transition,
                       (0.0, 0.0, 0.0), pins=pins, preroll_max=3)
    assert theirs.run(lambda f: positions[f], job.end)
    assert ours.shape == theirs.positions().shape == (3, sim.num_particles, 3)
    np.testing.assert_array_equal(theirs.positions(), ours)
