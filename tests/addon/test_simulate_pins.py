"""Painted pins in Bake, on the sample skirt (`sample_blends/skirt.blend`: its waistband pinned
with weight 1) and the walking sample character, through the installed add-on.

Pin mode ATTACH (the default): the waistband is not held while the seams close, is attached to
the body once they have met, and from then on rides on it through the walk. Pin mode FIXED
holds the waistband where it was placed from the first frame, which holds the skirt's seams
open (the bug this mode used to be the only behaviour of).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import bpy

ROOT = Path(__file__).resolve().parents[2]
SKIRT = ROOT / "sample_blends" / "skirt.blend"
FRAMES = (1, 6)
#: Assembly frames at the rest pose, then frames into the walk's first pose (the panel's
#: defaults are 60 and 40; the skirt's seams meet within about 25 frames).
PREROLL, TRANSITION = 40, 10


def bake_skirt(addon, tmp_path: Path, pin_mode: str, frames: tuple[int, int] = FRAMES) -> dict:
    bpy.ops.wm.open_mainfile(filepath=str(SKIRT))
    scene = bpy.context.scene
    body = bpy.data.objects["Body"]
    for o in scene.objects:
        o.select_set(o == body)
    bpy.context.view_layer.objects.active = body
    assert bpy.ops.tailor.mark_collider() == {"FINISHED"}
    # The samples are saved with the rig in its rest pose: play the walk.
    bpy.data.objects["Rig"].data.pose_position = "POSE"
    s = scene.tailor_simulate
    s.pin_mode = pin_mode
    s.preroll, s.transition = PREROLL, TRANSITION
    s.cache_dir = str(tmp_path / "cache")
    scene.frame_start, scene.frame_end = frames
    scene.frame_set(frames[0])
    pieces = sorted((o for o in scene.objects if o.type == "MESH" and o.tailor_piece.is_piece), key=lambda o: o.name)
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    report = json.loads(next((tmp_path / "cache").glob("*.report.json")).read_text())
    import tailor

    caches = {p.name: tailor.read_pc2(str(p))["frames"] for p in sorted((tmp_path / "cache").glob("*.pc2"))}
    return {"scene": scene, "body": body, "pieces": pieces, "report": report, "caches": caches}


def pinned_world(pieces, caches: dict, k: int) -> np.ndarray:
    """World positions at cached frame `k` of the vertices painted with pin weight 1."""
    out = []
    for o in pieces:
        c = next(v for name, v in caches.items() if name.endswith(f"__{bpy.path.clean_name(o.name)}.pc2"))
        vg = o.vertex_groups.get("tailor_pin")
        if vg is None:
            continue
        idx = [v.index for v in o.data.vertices for g in v.groups if g.group == vg.index and g.weight >= 0.999]
        m = np.array(o.matrix_world, np.float64)
        out.append(c[k][idx].astype(np.float64) @ m[:3, :3].T + m[:3, 3])
    return np.concatenate(out)


def test_pins_ride_on_the_walking_body_once_the_seams_have_met(addon, tmp_path):
    b = bake_skirt(addon, tmp_path, "ATTACH")
    frames = b["report"]["frames"]
    assert [r["frame"] for r in frames] == list(range(FRAMES[0], FRAMES[1] + 1))
    assert not any(r["nan"] for r in frames)
    # The seams have closed (held open by fixed pins they stay 35 cm apart: the next test).
    worst = max(r["seam_gap_max_m"] for r in frames)
    print(f"attached pins: seam gap at most {worst * 1e3:.2f} mm")
    assert worst < 0.01, worst
    # The pinned waistband moves with the body: each pinned vertex's motion over the recorded
    # walk matches that of the body vertex nearest to it, while the body moves several times
    # as far as that mismatch.
    scene, body = b["scene"], b["body"]
    gather = addon.simulate.gather
    pins = [pinned_world(b["pieces"], b["caches"], k) for k in (0, FRAMES[1] - FRAMES[0])]
    body_at = []
    for f in FRAMES:
        scene.frame_set(f)
        body_at.append(gather.evaluated_positions(body, bpy.context.evaluated_depsgraph_get()).astype(np.float64))
    nearest = np.array([np.argmin(((body_at[0] - p) ** 2).sum(axis=1)) for p in pins[0]])
    body_motion = body_at[1][nearest] - body_at[0][nearest]
    pin_motion = pins[1] - pins[0]
    mismatch = np.linalg.norm(pin_motion - body_motion, axis=1)
    moved = np.linalg.norm(body_motion, axis=1)
    print(f"pins: {len(nearest)}, body moved median {np.median(moved) * 1e3:.1f} mm (max {moved.max() * 1e3:.1f}), "
          f"pin motion off the body's by median {np.median(mismatch) * 1e3:.2f} mm (max {mismatch.max() * 1e3:.2f})")
    assert np.median(moved) > 5e-3, "the body hardly moves over these frames: the test shows nothing"
    # Measured: 138 pins, the body moved 12.2 mm (median), the pins' motion is off the body's by
    # 1.4 mm (median), 7.9 mm at most (a soft attachment, 100 N/m, with the skirt hanging on it);
    # since mesh contacts are decided by the nearest triangle (2026-11-22) 16.9 mm at most, at 2
    # of the 138 pins (12-17 mm; the rest under 6.1 mm): contacts the old cell test missed now
    # push those waistband particles off their attachment (not located further).
    assert np.median(mismatch) < 0.25 * np.median(moved)
    assert mismatch.max() < 0.02


def test_fixed_pins_hold_the_waistband_in_place(addon, tmp_path):
    b = bake_skirt(addon, tmp_path, "FIXED", frames=(1, 2))
    pins = [pinned_world(b["pieces"], b["caches"], k) for k in (0, 1)]
    np.testing.assert_allclose(pins[1], pins[0], atol=1e-5)  # held in world space, not riding
    worst = max(r["seam_gap_max_m"] for r in b["report"]["frames"])
    print(f"fixed pins: seam gap {worst * 1e3:.1f} mm")
    assert worst > 0.05, worst
