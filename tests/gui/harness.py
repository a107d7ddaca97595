"""Runs a driver script in Debian's Blender under Xvfb (simulated events need a real window) and
returns the verdict it wrote: what test_gui.py and test_gui_live.py share."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "out" / "gui"
BLENDER = shutil.which("blender")
XVFB = shutil.which("xvfb-run")

needs_window = pytest.mark.skipif(
    BLENDER is None or XVFB is None, reason="needs Blender and xvfb-run (apt install blender xvfb xauth)"
)


def run_driver(tmp_path: Path, driver: str, screen: str, result_name: str, clear: str, timeout: int) -> dict:
    """Runs tests/gui/`driver` on a fresh copy of the add-on folder (so its bundled wheel is
    unpacked anew, no stale _vendor) with a throw-away Blender user directory, after removing
    the files of out/gui matching `clear`; asserts the driver's result file says every check
    passed and returns it."""
    source = ROOT / "addon" / "tailor_addon"
    if not list((source / "wheels").glob("tailor-*.whl")):
        pytest.fail("the add-on has no bundled wheel: build it with `make addon`")
    addons = tmp_path / "addons"
    shutil.copytree(source, addons / "tailor_addon", ignore=shutil.ignore_patterns("_vendor", "__pycache__"))
    OUT.mkdir(parents=True, exist_ok=True)
    for old in OUT.glob(clear):
        old.unlink()
    env = dict(
        os.environ,
        BLENDER_USER_CONFIG=str(tmp_path / "config"),
        BLENDER_USER_SCRIPTS=str(tmp_path / "scripts"),
        BLENDER_USER_DATAFILES=str(tmp_path / "datafiles"),
    )
    cmd = [
        XVFB, "-a", "-s", f"-screen 0 {screen}x24",
        BLENDER, "--factory-startup", "--enable-event-simulate", "--python", str(ROOT / "tests" / "gui" / driver),
        "--", "--addon-dir", str(addons), "--out", str(OUT),
    ]  # fmt: skip
    result_file = OUT / result_name
    run = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
    log = run.stdout[-6000:] + run.stderr[-3000:]
    assert result_file.is_file(), f"the driver wrote no result (exit {run.returncode}):\n{log}"
    result = json.loads(result_file.read_text())
    failed = [c for c in result["checks"] if not c["ok"]]
    assert run.returncode == 0 and result["ok"], f"{failed} {result.get('error', '')}\n{log}"
    return result
