"""One bake, two faces (issue 24): the add-on's Bake and `tailor simulate` on the same scene
give the same frames. The shirt on the walking character is baked in the add-on with its
defaults (assembly at the rest pose, 60 frames and on while the seams close, 40 frames into the
walk); its garment file (Export Tailor Garment), its collider's rest pose (OBJ) and motion (PC2,
the evaluated collider frame by frame) go to `tailor simulate` with no setting but the up axis;
the command line's per-piece cache and its report are compared with the pieces the add-on
plays and its bake's records, frame by frame."""

from __future__ import annotations

import json
import subprocess
import sys

import bpy
import numpy as np

from conftest import evaluated_world
from simulate_scene import shirt_on_character

FRAMES = (1, 4)
#: Both solve the same frames with the same arithmetic; what is left is the add-on's caches
#: being stored in each piece's local space (its transform applied and undone in float32).
BOUND_M = 1e-5


def world_positions(objects) -> np.ndarray:
    """The objects' evaluated vertices in world space, one after another."""
    return np.concatenate([evaluated_world(o) for o in objects])


def test_the_command_line_bakes_the_frames_the_addon_bakes(addon, tmp_path):
    import tailor

    sc = shirt_on_character(tmp_path / "scene.blend", frames=FRAMES)
    scene, pieces = sc["scene"], sc["pieces"]
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    garment = tmp_path / "shirt.json"
    assert bpy.ops.tailor.export_garment(filepath=str(garment)) == {"FINISHED"}
    objects = {o.name: o for o in pieces}
    ordered = [objects[p.name] for p in tailor.Garment.load(garment).pieces]
    gather = addon.simulate.gather
    colliders = gather.read_scene(scene)[4]
    assert len(colliders) == 1
    # The collider as the bake read it: its rest pose, triangulated at the start frame (Blender
    # splits a deformed quad by its pose), and its positions at every frame of the range.
    rest = gather.rest_pose_positions(scene, colliders)[0]
    scene.frame_set(FRAMES[0])
    tris = gather.evaluated_triangles(colliders[0], bpy.context.evaluated_depsgraph_get())
    tailor.write_obj(str(tmp_path / "body.obj"), rest.astype(np.float32), np.asarray(tris, np.uint32))
    frames = range(FRAMES[0], FRAMES[1] + 1)
    motion = np.stack([gather.colliders_at(scene, colliders, f)[0] for f in frames]).astype(np.float32)
    tailor.write_pc2(str(tmp_path / "walk.pc2"), motion, 0.0, 1.0)
    added = {}
    for f in frames:
        scene.frame_set(f)
        added[f] = world_positions(ordered)
    r = subprocess.run([sys.executable, "-m", "tailor", "simulate", str(garment), "--collider", str(tmp_path / "body.obj"),
                        "--collider-anim", str(tmp_path / "walk.pc2"), "--up", "z", "--frames", str(len(frames)),
                        "--per-piece", "--report", str(tmp_path / "r.json"), "-o", str(tmp_path / "cli.pc2")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    cli = tailor.read_pc2(str(tmp_path / "cli.pc2"))["frames"]
    assert len(cli) == len(frames)
    moved = 0.0
    for k, f in enumerate(frames):  # the command line's frame k + 1 is the add-on's frame FRAMES[0] + k
        np.testing.assert_allclose(cli[k], added[f], atol=BOUND_M, err_msg=f"frame {f}")
        moved = max(moved, float(np.abs(added[f] - added[FRAMES[0]]).max()))
    assert moved > 0.01, "the garment does not move: the comparison shows nothing"
    # The reports agree too: the same assembly, and each frame measured the same.
    report = json.loads((tmp_path / "r.json").read_text())
    (baked_report,) = (tmp_path / "tailor_cache").glob("*.report.json")
    baked = json.loads(baked_report.read_text())
    assert report["assembly"]["at"] == "rest" and report["assembly"]["preroll_frames"] >= 60
    assert report["assembly"]["transition_frames"] == scene.tailor_simulate.transition == 40
    assert not report["summary"]["verdict"] and not baked["summary"]["verdict"]
    assert [r["frame"] for r in report["frames"]] == list(range(1, len(frames) + 1))
    for ours, theirs in zip(report["frames"], baked["frames"]):
        for key in ("seam_gap_max_m", "penetration_count", "penetration_max_m", "strain_max", "self_intersections",
                    "on_body_fraction", "start"):
            assert ours[key] == theirs[key], (ours["frame"], key, ours[key], theirs[key])
