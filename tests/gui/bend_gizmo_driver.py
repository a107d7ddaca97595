"""Drives the bend gizmo (`TAILOR_GGT_bend`) in a real Blender window with simulated mouse events.

Run by Blender itself (Debian's 3.4.1 or newer) under a virtual X server, as tests/gui/driver.py
is (tests/gui/test_gui_bend_gizmo.py runs it). It enables the add-on, imports the two-panel
skirt, turns the Bend panel's *Gizmo* on for the front panel and, with `Window.event_simulate`:

  1. in a front view (looking along the bend axis): presses on the angle dial's ring and drags a
     quarter turn round it, then drags the radius arrow's tip 40 px out;
  2. in a top view: drags the axis line 40 px sideways;
  3. Ctrl+Z once: the axis drag is undone, and only it (one undo step per drag);
and after each drag checks that the piece is exactly what the Bend operator (`tailor.bend`)
gives from the values the drag left in its redo panel (`WindowManager.operators[-1]`). It
writes `bend_gizmo_result.json` and screenshots `bend_gizmo_*.png` into `--out` and exits 0
only if every check passed.
"""

from __future__ import annotations

import argparse
import faulthandler
import json
import math
import os
import sys
import time
import traceback
from pathlib import Path

import bpy

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(Path(__file__).resolve().parent))  # window.py, shared by the drivers
from window import key, override, to_window, view3d  # noqa: E402
SKIRT = ROOT / "native/tailor-core/tests/data/svg/skirt_two_panels.svg"
PAUSE = 0.15


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("--addon-dir", default=str(ROOT / "addon"))
    p.add_argument("--out", default=str(ROOT / "out" / "gui"))
    return p.parse_args(argv)


faulthandler.enable(all_threads=True)
ARGS = parse_args()
OUT = Path(ARGS.out)
OUT.mkdir(parents=True, exist_ok=True)
RESULT: dict = {"checks": [], "screenshots": [], "figures": {}, "ok": False}


def check(what: str, ok: bool, detail="") -> None:
    RESULT["checks"].append({"what": what, "ok": bool(ok), "detail": str(detail)})
    print(f"GUI {'PASS' if ok else 'FAIL'}: {what} {detail}", flush=True)
    if not ok:
        raise AssertionError(f"{what}: {detail}")


def event(kind, value, x, y, **modifiers):
    view3d()[0].event_simulate(type=kind, value=value, x=x, y=y, **modifiers)


def screenshot(name: str):
    path = OUT / f"bend_gizmo_{name}.png"
    with override():
        bpy.ops.screen.screenshot_area(filepath=str(path))
    RESULT["screenshots"].append(str(path))
    check(f"screenshot {name}", path.is_file() and path.stat().st_size > 0, path)


def addon():
    return sys.modules["tailor_addon"]


def positions(obj):
    return addon().scene_data.vertex_positions(obj, world=False)


def drag(points):
    """Press at the first window point, move through the others, release at the last."""
    x, y = points[0]
    event("MOUSEMOVE", "NOTHING", x, y)
    yield 0.3  # the gizmo under the cursor highlights
    event("LEFTMOUSE", "PRESS", x, y)
    yield PAUSE
    for x, y in points[1:]:
        event("MOUSEMOVE", "NOTHING", x, y)
        yield PAUSE
    event("LEFTMOUSE", "RELEASE", x, y)
    yield 0.3


def same_as_the_operator(obj, what: str):
    """The piece as the drag left it against `tailor.bend` run with the redo panel's values."""
    import numpy as np

    last = bpy.context.window_manager.operators[-1]
    check(f"{what}: the drag ran the gizmo's operator", last.bl_idname == "TAILOR_OT_bend_gizmo", last.bl_idname)
    names = ("axis_point", "axis_direction", "angle", "use_symmetry", "symmetry_point", "symmetry_direction",
             "threshold", "use_radius", "radius", "taper")
    values = {n: (tuple(getattr(last.properties, n)) if hasattr(getattr(last.properties, n), "__len__")
                  else getattr(last.properties, n)) for n in names}
    dragged = positions(obj)
    with override():
        assert bpy.ops.tailor.bend("EXEC_DEFAULT", **values) == {"FINISHED"}
    by_operator = positions(obj)
    gap = float(np.abs(dragged - by_operator).max())
    check(f"{what}: the gizmo gives the Bend operator's mesh", gap < 1e-6, gap)
    return values, dragged


def scenario():
    import addon_utils
    import numpy as np
    from mathutils import Euler, Quaternion, Vector

    sys.path.insert(0, ARGS.addon_dir)
    addon_utils.enable("tailor_addon", default_set=True)
    check("add-on enabled", hasattr(bpy.ops.tailor, "bend_gizmo"))
    RESULT["blender"] = bpy.app.version_string
    bpy.context.preferences.view.smooth_view = 0
    key("ESC")
    yield PAUSE
    win, area, region, rv3d = view3d()
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    assert bpy.ops.tailor.import_pattern(filepath=str(SKIRT), edge_length=0.04) == {"FINISHED"}
    front = bpy.data.objects["skirt front"]
    space = area.spaces.active
    space.overlay.show_floor = space.overlay.show_axis_x = space.overlay.show_axis_y = False
    space.show_region_toolbar = False
    space.show_gizmo_navigate = False
    space.show_gizmo = True
    for obj in bpy.data.objects:
        obj.select_set(obj == front)
    bpy.context.view_layer.objects.active = front
    rv3d.view_rotation = Euler((math.radians(90), 0.0, 0.0)).to_quaternion()  # front: along +y
    rv3d.view_perspective = "ORTHO"
    with override():
        bpy.ops.view3d.view_selected()
    rv3d.view_distance *= 1.3
    bpy.context.window_manager.tailor_bend_gizmo = True
    area.tag_redraw()
    yield 0.5
    m = front.matrix_world
    flat = positions(front)
    h, angle = addon().bend.gizmo_group.placement(front)
    check("a flat piece shows angle 0", angle == 0.0, angle)
    screenshot("flat")

    # 1. The dial: press on its ring beside the centre, a quarter turn round it.
    side = np.cross(h.direction, h.out)
    centre = to_window(m @ Vector(h.centre))
    ring = [to_window(m @ Vector(h.centre + h.dial * (math.cos(t) * side + math.sin(t) * h.out)))
            for t in np.linspace(0.0, math.pi / 2, 7)]
    RESULT["figures"]["dial_centre_px"] = centre
    yield from drag(ring)
    p = front.tailor_piece
    check("the dial turned the angle a quarter turn", abs(abs(math.degrees(p.bend_angle)) - 90.0) < 3.0,
          math.degrees(p.bend_angle))
    dial_values, after_dial = same_as_the_operator(front, "dial")
    check("the piece is bent", np.abs(after_dial[:, 2]).max() > 0.05 and not np.allclose(after_dial, flat))
    screenshot("dial")

    # 2. The radius arrow: press near its tip, drag 40 px further out.
    h, _ = addon().bend.gizmo_group.placement(front)
    r0 = h.radius
    base = np.array(to_window(m @ Vector(h.centre)), float)
    tip = np.array(to_window(m @ Vector(h.centre + 0.9 * h.radius * h.out)), float)
    out_px = (tip - base) / np.linalg.norm(tip - base)
    points = [tuple(int(round(c)) for c in tip + k * out_px) for k in (0, 10, 20, 30, 40)]
    yield from drag(points)
    check("the arrow set a radius", p.bend_radius > r0 * 1.05, (r0, p.bend_radius))
    RESULT["figures"]["radius_m"] = (r0, p.bend_radius)
    radius_values, after_radius = same_as_the_operator(front, "radius")
    screenshot("radius")

    # 3. The axis, in a top view: press on its line away from the centre, drag 40 px sideways.
    rv3d.view_rotation = Quaternion((1.0, 0.0, 0.0, 0.0))
    area.tag_redraw()
    yield 0.4
    h, _ = addon().bend.gizmo_group.placement(front)
    a0 = np.array(p.bend_axis_point)
    grip = h.axis_from + 0.8 * (h.axis_to - h.axis_from)  # clear of the dial and the arrow at the centre
    x, y = to_window(m @ Vector(grip))
    yield from drag([(x, y), (x + 10, y), (x + 25, y), (x + 40, y)])
    moved = np.array(p.bend_axis_point) - a0
    check("the axis moved sideways in the piece's plane", moved[0] > 0.01 and abs(moved[2]) < 1e-6, moved)
    check("the symmetry line moved with it", abs(p.bend_symmetry_point[0] - p.bend_axis_point[0]) < 1e-5,
          (tuple(p.bend_symmetry_point), tuple(p.bend_axis_point)))
    same_as_the_operator(front, "axis")
    screenshot("axis")

    # 4. One undo step per drag: Ctrl+Z once gives the piece as the radius drag left it (the
    # checks' own Bend runs, called from this script, push no undo step of their own).
    x, y = to_window(m @ Vector(h.centre + 3 * h.dial * side))
    event("MOUSEMOVE", "NOTHING", x, y)
    yield PAUSE
    key("Z", ctrl=True)
    yield 0.4
    front = bpy.data.objects["skirt front"]
    gap = float(np.abs(positions(front) - after_radius).max())
    check("Ctrl+Z undoes the axis drag alone", gap < 1e-6, gap)
    RESULT["ok"] = True


def finish(code: int) -> None:
    (OUT / "bend_gizmo_result.json").write_text(json.dumps(RESULT, indent=2))
    print(f"GUI RESULT {'OK' if code == 0 else 'FAILED'} ({len(RESULT['checks'])} checks) -> {OUT}", flush=True)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


STEPS = scenario()
DEADLINE = time.monotonic() + 180.0


def step():
    try:
        if time.monotonic() > DEADLINE:
            raise TimeoutError("the bend gizmo scenario took more than 180 s")
        delay = next(STEPS)
    except StopIteration:
        finish(0 if RESULT["ok"] else 1)
        return None
    except BaseException:
        RESULT["error"] = traceback.format_exc()
        print(RESULT["error"], flush=True)
        finish(1)
        return None
    return delay


bpy.app.timers.register(step, first_interval=0.5)
