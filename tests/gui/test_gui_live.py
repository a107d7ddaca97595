"""Live mode in a real Blender window: runs tests/gui/live_driver.py in Blender under Xvfb (see
the driver's docstring: the modal `tailor.live` on its timer while the timeline plays, the
garment following a moving collider (a plate), the UI kept responsive, Esc restoring the pieces) and
checks its verdict. Skipped when `blender` or `xvfb-run` is not installed (`.ci/bootstrap`
installs both); needs the add-on's bundled wheel (`make addon`). Run with `make test-gui`.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DRIVER = ROOT / "tests" / "gui" / "live_driver.py"
OUT = ROOT / "out" / "gui"
BLENDER = shutil.which("blender")
XVFB = shutil.which("xvfb-run")

pytestmark = pytest.mark.skipif(
    BLENDER is None or XVFB is None, reason="needs Blender and xvfb-run (apt install blender xvfb xauth)"
)


def test_live_mode_follows_the_playing_timeline_in_a_real_window(tmp_path):
    source = ROOT / "addon" / "tailor_addon"
    if not list((source / "wheels").glob("tailor-*.whl")):
        pytest.fail("the add-on has no bundled wheel: build it with `make addon`")
    addons = tmp_path / "addons"
    shutil.copytree(source, addons / "tailor_addon", ignore=shutil.ignore_patterns("_vendor", "__pycache__"))
    OUT.mkdir(parents=True, exist_ok=True)
    for old in OUT.glob("live_*"):  # only this test's files: test_gui.py's screenshots stay
        old.unlink()
    env = dict(
        os.environ,
        BLENDER_USER_CONFIG=str(tmp_path / "config"),
        BLENDER_USER_SCRIPTS=str(tmp_path / "scripts"),
        BLENDER_USER_DATAFILES=str(tmp_path / "datafiles"),
    )
    cmd = [
        XVFB, "-a", "-s", "-screen 0 800x600x24",
        BLENDER, "--factory-startup", "--enable-event-simulate", "--python", str(DRIVER),
        "--", "--addon-dir", str(addons), "--out", str(OUT),
    ]  # fmt: skip
    run = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=300)
    log = run.stdout[-6000:] + run.stderr[-3000:]
    result_file = OUT / "live_result.json"
    assert result_file.is_file(), f"the driver wrote no result (exit {run.returncode}):\n{log}"
    result = json.loads(result_file.read_text())
    failed = [c for c in result["checks"] if not c["ok"]]
    assert run.returncode == 0 and result["ok"], f"{failed} {result.get('error', '')}\n{log}"
    names = {c["what"] for c in result["checks"]}
    for what in ("Live solved and applied frames while it played", "the garment followed the plate (+x)",
                 "the UI kept handling timers (no freeze for a solve)", "Esc ends Live", "the overlay's text is drawn"):
        assert what in names
    fig = result["figures"]
    print(f"Live in the window ({result['blender']}): {fig}")
    assert fig["frames_solved"] >= 20 and fig["max_ui_gap_ms"] < 1000
    shot = OUT / "live_mode.png"
    assert shot.is_file() and shot.stat().st_size > 1000
