"""`python demo/run.py` (the README's `make demo`) with a reduced frame count: the sample skirt
assembles on the walking character through `tailor.bake.Bake`, and the rendered frames, the
contact sheet and the animated GIF are images of the garment (not empty frames). Skips without
the bpy wheel (it renders with Workbench). And the demo is not in the package that ships in the
add-on."""

import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import tailor
from tailor import bake

ROOT = Path(__file__).resolve().parents[1]

needs_bpy = pytest.mark.skipif(
    importlib.util.find_spec("bpy") is None, reason='bpy wheel not installed: .venv/bin/pip install "bpy==4.5.*"'
)

# Reads PNGs with Blender (the bpy wheel) in a process of its own: mean RGB per image and the
# number of pixels whose colour differs from the body-only render by more than 0.1, and the
# number of garment-red pixels (the skirt: red well above green and blue).
READ = r"""
import json, sys
import bpy, numpy as np
def px(p):
    img = bpy.data.images.load(p); w, h = img.size
    a = np.empty(w * h * 4, np.float32); img.pixels.foreach_get(a)
    return a.reshape(h, w, 4)[:, :, :3]
ref = px(sys.argv[1])
out = {}
for p in sys.argv[1:]:
    a = px(p)
    red = (a[:, :, 0] > a[:, :, 1] + 0.2) & (a[:, :, 0] > a[:, :, 2] + 0.15)
    diff = np.abs(a - ref).max(axis=2) > 0.1 if a.shape == ref.shape else np.ones(a.shape[:2], bool)
    out[p] = {"shape": list(a.shape), "red": int(red.sum()), "differs": int(diff.sum()), "std": float(a.std())}
print("RESULT" + json.dumps(out))
"""


@needs_bpy
def test_demo_renders_the_garment_on_the_character(tmp_path):
    out = tmp_path / "demo"
    r = subprocess.run(
        [sys.executable, str(ROOT / "demo" / "run.py"), "--out", str(out), "--assemble", "30", "--blend", "4",
         "--frames", "4", "--render-every", "8", "--size", "240x180", "--gif-width", "160"],
        capture_output=True, text=True, timeout=900, cwd=ROOT,
    )
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    for line in ("timing:", "assembly:", "walk:", "render:", "particles"):
        assert line in r.stdout, r.stdout
    report = json.loads((out / "report.json").read_text())
    s = report["summary"]
    # At least 30 frames at rest (more while the seams close), 4 into the walk, then the walk's
    # frames 0-4 as `Bake` records them (frame 0: the garment as it enters the walk, no step).
    assert s["preroll_frames"] >= 30 and s["action_start_step"] == s["preroll_frames"] + 4
    assert len(report["assembly"]) == s["action_start_step"] and s["frames"] == s["action_start_step"] + 4
    assert [r["frame"] for r in report["frames"]] == [0, 1, 2, 3, 4] and set(bake.FIELDS) <= set(report["frames"][0])
    assert [r["phase"] for r in report["assembly"]] == ["assemble"] * s["preroll_frames"] + ["blend"] * 4
    assert s["phases"]["assemble"]["frames"] == s["preroll_frames"] and s["phases"]["animate"]["frames"] == 4
    assert s["verdict"] == s["action"]["verdict"] == [] and s["seams_met_at_step"] <= s["preroll_frames"]
    walk = s["phases"]["animate"]
    assert not walk["nan"] and walk["penetration_max_m"] <= s["thickness_m"], walk
    assert walk["seam_gap_max_m"] < 0.03, walk  # assembled: the 28 cm gaps of the flat panels closed
    cache = tailor.read_pc2(str(out / "garment.pc2"))["frames"]  # after 0, 1, ... steps
    assert len(cache) == s["frames"] + 1
    frames = sorted((out / "frames").glob("frame_*.png"))
    assert [f.name for f in frames] == s["render"]["frames"] and len(frames) >= 2
    sheet, body = out / "contact_sheet.png", out / "body_only.png"
    assert sheet.is_file() and body.is_file()
    read = subprocess.run([sys.executable, "-c", READ, str(body), *map(str, frames), str(sheet)],
                          capture_output=True, text=True, timeout=300)
    assert read.returncode == 0, read.stderr[-2000:]
    stats = json.loads(read.stdout.split("RESULT", 1)[1])
    assert stats[str(body)]["red"] < 20  # the body alone has no garment colour
    for f in frames:
        st = stats[str(f)]
        assert st["shape"] == [180, 240, 3]
        assert st["red"] > 400, (f.name, st)  # the skirt covers a good part of the frame
    # The last frame shows the same body as body_only.png plus the skirt: they differ where it is.
    assert stats[str(frames[-1])]["differs"] > 400
    assert stats[str(sheet)]["red"] > 400 * len(s["render"]["contact_sheet"])

    # The animated GIF: every rendered frame, in order, scaled to 160 pixels; animated (the
    # frames differ: the garment assembles and the body walks) and showing the garment.
    from PIL import Image, ImageSequence

    anim = s["render"]["animation"]
    gif = out / anim["file"]
    assert gif.name == "animation.gif" and gif.stat().st_size == anim["bytes"] > 1000
    with Image.open(gif) as im:
        assert im.format == "GIF" and im.is_animated and im.size == (160, 120)
        assert im.info.get("loop") == 0 and im.info.get("duration", 0) > 0
        gif_frames = [np.asarray(f.convert("RGB"), np.float32) / 255.0 for f in ImageSequence.Iterator(im)]
    assert len(gif_frames) == anim["frames"] == len(frames) >= 4
    for i, a in enumerate(gif_frames):
        red = (a[:, :, 0] > a[:, :, 1] + 0.2) & (a[:, :, 0] > a[:, :, 2] + 0.15)
        assert red.sum() > 150, (i, int(red.sum()))  # the skirt, at (160/240)^2 of the PNGs' 400 pixels
        assert a.std() > 0.05, i  # not a flat frame
    changed = [float((np.abs(b - a).max(axis=2) > 0.1).mean()) for a, b in zip(gif_frames, gif_frames[1:])]
    assert all(c > 0.005 for c in changed), changed  # each frame differs from the one before


def test_the_demo_is_not_in_the_package():
    """The package is the wheel inside the add-on: no demo, nothing that imports `bpy`, and the
    command line has no `demo` (it lives in demo/, outside the package)."""
    package = Path(tailor.__file__).parent
    assert not list(package.rglob("demo*.py")), list(package.rglob("demo*.py"))
    assert not [p for p in package.rglob("*.py") if "import bpy" in p.read_text()]
    r = subprocess.run([sys.executable, "-m", "tailor", "demo"], capture_output=True, text=True)
    assert r.returncode == 2 and "invalid choice: 'demo'" in r.stderr, r.stderr


def demo(*args):
    return subprocess.run([sys.executable, str(ROOT / "demo" / "run.py"), *map(str, args)], capture_output=True,
                          text=True, timeout=600)


def test_the_sleeve_scene_runs_and_reports(tmp_path):
    r = demo("--scene", "sleeve", "--frames", "30", "--out", tmp_path)
    assert r.returncode == 0, r.stderr
    assert "ns per particle-iteration" in r.stdout and "seam gap" in r.stdout
    report = json.loads((tmp_path / "report.json").read_text())
    s = report["summary"]
    assert s["frames"] == 30 and not s["nan"]
    assert s["seam_gap_max_m"] < 2e-3 and s["penetration_count"] == 0
    assert len(report["frames"]) == 30
    assert (tmp_path / "sleeve.obj").read_text().count("\nf ") == s["triangles"]


def test_an_unknown_action_is_one_line_naming_the_clips(tmp_path):
    r = demo("--action", "dance", "--no-render", "--out", tmp_path)
    assert r.returncode == 2 and r.stdout == "", (r.returncode, r.stdout)
    assert r.stderr.strip().count("\n") == 0 and "no animation 'dance' (its animations: 'run', 'walk')" in r.stderr
