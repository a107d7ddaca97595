"""Live mode in a real Blender window: runs tests/gui/live_driver.py in Blender under Xvfb (see
the driver's docstring: the modal `tailor.live` on its timer while the timeline plays, the
garment following a moving collider (a plate), the UI kept responsive, Esc stopping playback and
not Live, Stop Live restoring the pieces, a file opened mid-Live cancelling it) and
checks its verdict. Skipped when `blender` or `xvfb-run` is not installed (`.ci/bootstrap`
installs both); needs the add-on's bundled wheel (`make addon`). Run with `make test-gui`.
"""

from __future__ import annotations

from harness import OUT, needs_window, run_driver

pytestmark = needs_window


def test_live_mode_follows_the_playing_timeline_in_a_real_window(tmp_path):
    result = run_driver(tmp_path, "live_driver.py", "800x600", "live_result.json", "live_*", timeout=300)
    names = {c["what"] for c in result["checks"]}
    for what in ("Live solved and applied frames while it played", "the garment followed the plate (+x)",
                 "the UI kept handling timers (no freeze for a solve)", "Esc stops playback, not Live",
                 "Stop Live ends Live", "the overlay's text is drawn", "Live runs again",
                 "opening a file ends Live: no session, no run, no overlay, no worker left",
                 "the new file has no Live running"):
        assert what in names
    fig = result["figures"]
    print(f"Live in the window ({result['blender']}): {fig}")
    assert fig["frames_solved"] >= 20 and fig["max_ui_gap_ms"] < fig["max_ui_gap_bound_ms"]
    shot = OUT / "live_mode.png"
    assert shot.is_file() and shot.stat().st_size > 1000
