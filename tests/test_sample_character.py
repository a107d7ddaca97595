"""The sample character (sample_blends/character.blend, .glb): its glTF export plays in
`tailor.AnimatedMesh` exactly as Blender deforms the body, and its arms (armpits included) stay
out of its torso.

Blender runs in a subprocess (sample_blends/build/evaluate_character.py) so that opening the
.blend leaves the Blender state of other tests alone. Skips without the bpy wheel.
"""

import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import tailor

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "sample_blends"

pytestmark = pytest.mark.skipif(
    importlib.util.find_spec("bpy") is None, reason='bpy wheel not installed: .venv/bin/pip install "bpy==4.5.*"'
)


@pytest.fixture(scope="module")
def evaluated(tmp_path_factory):
    out = tmp_path_factory.mktemp("character") / "evaluated.npz"
    script = SAMPLES / "build" / "evaluate_character.py"
    run = subprocess.run(
        [sys.executable, str(script), str(SAMPLES / "character.blend"), str(out)],
        capture_output=True, text=True, timeout=600,
    )
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    data = np.load(out)
    return json.loads(str(data["meta"])), data


def test_scene_is_set_up(evaluated):
    meta, _ = evaluated
    assert meta["actions"] == ["walk", "run"] and meta["active_action"] == "walk"
    assert meta["fps"] == 30 and meta["frame_range"] == [1, 32]
    assert meta["unit_system"] == "METRIC" and meta["camera"] == "Camera" and meta["modifiers"] == ["ARMATURE"]
    for bone in ("spine", "neck", "head", "shoulder.L", "upper_arm.R", "forearm.L", "hand.R", "thigh.L", "shin.R",
                 "foot.L"):
        assert bone in meta["bones"]


def test_glb_matches_blender_at_every_frame(evaluated):
    meta, data = evaluated
    glb = tailor.AnimatedMesh(SAMPLES / "character.glb")
    names = [name for name, _ in glb.animations]
    assert sorted(names) == ["run", "walk"]
    np.testing.assert_array_equal(glb.triangles, data["triangles"])
    worst = 0.0
    for action in meta["actions"]:
        frames = data[action]
        index = names.index(action)
        # The last frame closes the loop: the animation lasts exactly one cycle.
        assert glb.animations[index][1] == pytest.approx((len(frames) - 1) / meta["fps"], abs=1e-5)
        np.testing.assert_allclose(frames[-1], frames[0], atol=1e-5)
        for f, blender in enumerate(frames):
            y_up = np.stack([blender[:, 0], blender[:, 2], -blender[:, 1]], axis=1)  # glTF is Y-up
            dev = np.abs(glb.positions_at(f / meta["fps"], index) - y_up).max()
            worst = max(worst, float(dev))
        moved = np.linalg.norm(frames - frames[0], axis=2).max()
        assert moved > 0.2, f"{action}: the body hardly moves ({moved:.3f} m)"
    print(f"character.glb vs Blender: max deviation {worst * 1e3:.4f} mm")
    assert worst < 1e-4


def test_arms_stay_out_of_the_torso(evaluated):
    meta, data = evaluated
    tris, dominant, groups = data["triangles"], data["dominant"], meta["groups"]
    bone = np.array(groups)[dominant[tris[:, 0]]]
    torso = np.isin(bone, ["hips", "spine", "chest", "shoulder.L", "shoulder.R"])
    parts = [f"{p}.{s}" for p in ("upper_arm", "forearm", "hand") for s in "LR"]

    def count(p, mask):
        return tailor.count_self_intersections(p, tris[mask])

    for action in meta["actions"]:
        for f in range(0, len(data[action]), 3):
            p = data[action][f]
            base = count(p, torso)
            for part in parts:
                limb = bone == part
                crossings = count(p, torso | limb) - base - count(p, limb)
                assert crossings == 0, f"{action} frame {f + 1}: {part} crosses the torso ({crossings} pairs)"
