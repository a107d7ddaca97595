"""The interactive tools in a real Blender window: runs tests/gui/driver.py in Blender under
Xvfb with simulated mouse events (see the driver's docstring for the scenario) and checks its
verdict. Skipped when `blender` or `xvfb-run` is not installed (`.ci/bootstrap` installs both);
needs the add-on's bundled wheel (`make addon`). Run with `make test-gui`.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DRIVER = ROOT / "tests" / "gui" / "driver.py"
OUT = ROOT / "out" / "gui"
BLENDER = shutil.which("blender")
XVFB = shutil.which("xvfb-run")

pytestmark = pytest.mark.skipif(
    BLENDER is None or XVFB is None, reason="needs Blender and xvfb-run (apt install blender xvfb xauth)"
)


def test_interactive_tools_in_a_real_window(tmp_path):
    source = ROOT / "addon" / "tailor_addon"
    if not list((source / "wheels").glob("tailor-*.whl")):
        pytest.fail("the add-on has no bundled wheel: build it with `make addon`")
    # A fresh copy of the add-on folder, so the wheel is unpacked anew (no stale _vendor).
    addons = tmp_path / "addons"
    shutil.copytree(source, addons / "tailor_addon", ignore=shutil.ignore_patterns("_vendor", "__pycache__"))
    OUT.mkdir(parents=True, exist_ok=True)
    for old in OUT.glob("*"):
        old.unlink()
    env = dict(
        os.environ,
        BLENDER_USER_CONFIG=str(tmp_path / "config"),
        BLENDER_USER_SCRIPTS=str(tmp_path / "scripts"),
        BLENDER_USER_DATAFILES=str(tmp_path / "datafiles"),
    )
    cmd = [
        XVFB, "-a", "-s", "-screen 0 1280x800x24",
        BLENDER, "--factory-startup", "--enable-event-simulate", "--python", str(DRIVER),
        "--", "--addon-dir", str(addons), "--out", str(OUT),
    ]  # fmt: skip
    run = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=400)
    log = run.stdout[-6000:] + run.stderr[-3000:]
    result_file = OUT / "result.json"
    assert result_file.is_file(), f"the driver wrote no result (exit {run.returncode}):\n{log}"
    result = json.loads(result_file.read_text())
    failed = [c for c in result["checks"] if not c["ok"]]
    assert run.returncode == 0 and result["ok"], f"{failed} {result.get('error', '')}\n{log}"
    names = {c["what"] for c in result["checks"]}
    for what in ("manual seam created", "Esc cancels", "suggested seam created", "bend committed at 90 degrees",
                 "right click cancels the bend"):
        assert what in names
    shots = [Path(p) for p in result["screenshots"]]
    assert len(shots) >= 5 and all(p.is_file() and p.stat().st_size > 1000 for p in shots)
