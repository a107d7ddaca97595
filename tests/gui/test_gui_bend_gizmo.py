"""The bend gizmo in a real Blender window: runs tests/gui/bend_gizmo_driver.py in Blender under
Xvfb (see its docstring: the dial, the radius arrow and the axis dragged with simulated mouse
events, each drag's mesh against the Bend operator's, one undo step per drag) and checks its
verdict. Skipped when `blender` or `xvfb-run` is not installed; needs the add-on's bundled wheel
(`make addon`). Run with `make test-gui`.
"""

from __future__ import annotations

from harness import needs_window, run_driver

pytestmark = needs_window


def test_bend_gizmo_gives_the_operators_mesh_in_a_real_window(tmp_path):
    result = run_driver(tmp_path, "bend_gizmo_driver.py", "1280x800", "bend_gizmo_result.json", "bend_gizmo_*",
                        timeout=300)
    names = {c["what"] for c in result["checks"]}
    for what in ("dial: the gizmo gives the Bend operator's mesh", "radius: the gizmo gives the Bend operator's mesh",
                 "axis: the gizmo gives the Bend operator's mesh", "Ctrl+Z undoes the axis drag alone"):
        assert what in names
    print(f"Bend gizmo in the window ({result['blender']}): {result['figures']}")
