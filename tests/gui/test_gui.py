"""The interactive tools in a real Blender window: runs tests/gui/driver.py in Blender under
Xvfb with simulated mouse events (see the driver's docstring for the scenario) and checks its
verdict. Skipped when `blender` or `xvfb-run` is not installed (`.ci/bootstrap` installs both);
needs the add-on's bundled wheel (`make addon`). Run with `make test-gui`.
"""

from __future__ import annotations

from pathlib import Path

from harness import needs_window, run_driver

pytestmark = needs_window


def test_interactive_tools_in_a_real_window(tmp_path):
    # Everything in out/gui except the Live test's files (live_*).
    result = run_driver(tmp_path, "driver.py", "1280x800", "result.json", "[!l]*", timeout=400)
    names = {c["what"] for c in result["checks"]}
    for what in ("manual seam created", "Esc cancels", "suggested seam created", "bend committed at 90 degrees",
                 "right click cancels the bend"):
        assert what in names
    shots = [Path(p) for p in result["screenshots"]]
    assert len(shots) >= 5 and all(p.is_file() and p.stat().st_size > 1000 for p in shots)
