"""Drives the add-on's interactive tools in a real Blender window with simulated mouse events.

Run by Blender itself (Debian's 3.4.1 or newer), under a virtual X server:

    xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup --enable-event-simulate \
        --python tests/gui/driver.py -- --addon-dir addon --out out/gui

(`make test-gui` and tests/gui/test_gui.py run exactly this.) It enables the add-on from
`--addon-dir` (a folder holding `tailor_addon/`, loaded as a legacy add-on: `bl_info`, the
bundled wheel unpacked by `compat.ensure_tailor`), imports the two-panel skirt, frames it in a
top view, and then, with `Window.event_simulate` (mouse moves, clicks, keys that Blender handles
exactly like a user's):

  1. manual seam: a1, a wrong an undone with Backspace, an, b1, a hover on each side of b1
     (the n-vertex path follows the cursor), bn; then a second run cancelled with Esc;
  2. automatic suggestion: re-triangulate the back finer, start and cancel with right click,
     then hover the front panel's side, click it, click the back's facing side (unequal seam);
  3. bend: place the axis on the front panel, drag 180 px (90 degrees), live preview, commit;
     then a second drag cancelled with right click;
  and Ctrl+Z / Ctrl+Shift+Z undo and redo the manual seam.

After each step it checks the scene data against the module (seam count, pieces, contour
positions, vertex counts, mode, bend angle and positions), and saves screenshots of the tools
in use into `--out` (with 560-pixel-wide `*_small.png` copies for the docs). It writes
`result.json` there and exits 0 only if every check passed.

Events are only processed by Blender's main loop, so the script is a generator stepped by a
timer: each `yield` returns control to the loop for that many seconds (events handled, the
viewport redrawn) before the next step.
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
PAUSE = 0.15  # seconds for the loop to handle queued events and redraw


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("--addon-dir", default=str(ROOT / "addon"), help="folder holding tailor_addon/")
    p.add_argument("--out", default=str(ROOT / "out" / "gui"), help="screenshots and result.json")
    p.add_argument("--pattern", default=str(SKIRT))
    return p.parse_args(argv)


# A segfault prints every thread's Python stack before Blender's own crash report.
faulthandler.enable(all_threads=True)
ARGS = parse_args()
OUT = Path(ARGS.out)
OUT.mkdir(parents=True, exist_ok=True)
RESULT: dict = {"checks": [], "screenshots": [], "ok": False}


def check(what: str, ok: bool, detail="") -> None:
    RESULT["checks"].append({"what": what, "ok": bool(ok), "detail": str(detail)})
    print(f"GUI {'PASS' if ok else 'FAIL'}: {what} {detail}", flush=True)
    if not ok:
        raise AssertionError(f"{what}: {detail}")


# ---- the window (view3d, override, to_window, key: window.py) ------------------------------


def move(x, y):
    view3d()[0].event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)


def click(x, y, button="LEFTMOUSE"):
    win = view3d()[0]
    win.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
    win.event_simulate(type=button, value="PRESS", x=x, y=y)
    win.event_simulate(type=button, value="RELEASE", x=x, y=y)


def screenshot(name: str):
    """The 3D view as the artist sees it (header prompt and drawing included)."""
    path = OUT / f"{name}.png"
    with override():
        bpy.ops.screen.screenshot_area(filepath=str(path))
    RESULT["screenshots"].append(str(path))
    check(f"screenshot {name}", path.is_file() and path.stat().st_size > 0, path)


def oblique_view():
    """Turns the 3D view to a perspective three-quarter view of the pieces; returns the old view."""
    from mathutils import Euler

    _, _, _, rv3d = view3d()
    old = (rv3d.view_rotation.copy(), rv3d.view_perspective, rv3d.view_location.copy(), rv3d.view_distance)
    rv3d.view_rotation = Euler((math.radians(62), 0.0, math.radians(-28)), "XYZ").to_quaternion()
    rv3d.view_perspective = "PERSP"
    rv3d.view_distance = old[3] * 0.8
    view3d()[1].tag_redraw()
    return old


def restore_view(old) -> None:
    _, area, _, rv3d = view3d()
    rv3d.view_rotation, rv3d.view_perspective, rv3d.view_location, rv3d.view_distance = old
    area.tag_redraw()


def small_copies(width: int = 560) -> None:
    """`<name>_small.png`: the screenshots scaled to `width` pixels, for the docs."""
    for path in list(RESULT["screenshots"]):
        img = bpy.data.images.load(path)
        w, h = img.size
        img.scale(width, round(h * width / w))
        img.filepath_raw = path.replace(".png", "_small.png")
        img.file_format = "PNG"
        img.save()
        bpy.data.images.remove(img)


# ---- geometry helpers (the module's) -----------------------------------------------------


def addon_module():
    return sys.modules["tailor_addon"]


def mesh(obj):
    return addon_module().core.mesh_of(obj.tailor_piece)


def contour_world(obj, position, inward=0.0):
    """World position of contour vertex `position`, moved `inward` metres towards the piece's
    centre (a click lands on the piece, not beside it)."""
    import numpy as np
    from mathutils import Vector

    m = mesh(obj)
    co = np.array(obj.data.vertices[int(m.contour[position])].co, np.float64)
    if inward:
        centre = np.array([v.co for v in obj.data.vertices], np.float64).mean(axis=0)
        d = centre - co
        co = co + inward * d / np.linalg.norm(d)
    return obj.matrix_world @ Vector(co)


def run_middle(obj, start, end):
    """World point in the middle of the contour run start..end (counter-clockwise)."""
    m = mesh(obj)
    n = len(m.contour)
    return contour_world(obj, (start + ((end - start) % n) // 2) % n, inward=0.01)


def invoke(op_name: str):
    with override():
        result = getattr(bpy.ops.tailor, op_name)("INVOKE_DEFAULT")
    check(f"{op_name} starts modal", result == {"RUNNING_MODAL"}, result)


# ---- the scenario ------------------------------------------------------------------------


def scenario():
    import addon_utils
    import numpy as np

    sys.path.insert(0, ARGS.addon_dir)
    addon_utils.enable("tailor_addon", default_set=True)
    import tailor  # importable once the add-on has unpacked its bundled wheel

    check("add-on enabled", hasattr(bpy.ops.tailor, "seam_pick") and "tailor_addon" in sys.modules)
    check("tailor from the bundled wheel", "_vendor" in tailor.__file__ or "tailor_vendor" in tailor.__file__,
          tailor.__file__)
    RESULT["blender"] = bpy.app.version_string

    bpy.context.preferences.view.smooth_view = 0  # view changes at once, not animated
    key("ESC")  # close the splash screen (factory settings show it)
    yield PAUSE
    win, area, region, rv3d = view3d()
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    assert bpy.ops.tailor.import_pattern(filepath=ARGS.pattern, edge_length=0.05) == {"FINISHED"}
    front, back = bpy.data.objects["skirt front"], bpy.data.objects["skirt back"]
    check("pattern imported", front.tailor_piece.is_piece and back.tailor_piece.is_piece)
    space = area.spaces.active
    space.overlay.show_floor = space.overlay.show_axis_x = space.overlay.show_axis_y = False
    space.shading.type = "SOLID"
    space.show_region_toolbar = False
    space.show_gizmo_navigate = False
    from mathutils import Quaternion

    rv3d.view_rotation = Quaternion((1.0, 0.0, 0.0, 0.0))  # top view, looking down -z
    rv3d.view_perspective = "ORTHO"
    for obj in bpy.data.objects:
        obj.select_set(obj in (front, back))
    bpy.context.view_layer.objects.active = front
    with override():
        bpy.ops.view3d.view_selected()
    for obj in bpy.data.objects:
        obj.select_set(False)
    yield 0.5
    scene = bpy.context.scene
    mf, mb = mesh(front), mesh(back)
    cf, cb = list(mf.corners), list(mb.corners)
    check("four corners per panel", len(cf) == 4 and len(cb) == 4, (cf, cb))

    def side_x(obj, m, run):
        return (contour_world(obj, run[0]).x + contour_world(obj, run[1]).x) / 2

    def runs(cs):
        return list(zip(cs, cs[1:] + cs[:1]))

    # The sides: front's left and right, back's left and right (the panels lie side by side).
    f_left = min(runs(cf), key=lambda r: side_x(front, mf, r))
    f_right = max(runs(cf), key=lambda r: side_x(front, mf, r))
    b_left = min(runs(cb), key=lambda r: side_x(back, mb, r))
    b_right = max(runs(cb), key=lambda r: side_x(back, mb, r))

    # 1. Manual seam: front's left side (a1 at its first corner) to back's right side.
    invoke("seam_pick")
    yield PAUSE
    a1, an = f_left
    click(*to_window(contour_world(front, a1, inward=0.004)))
    yield PAUSE
    wrong = (a1 + 2) % len(mf.contour) if (a1 + 2) % len(mf.contour) != an else (a1 + 3) % len(mf.contour)
    click(*to_window(contour_world(front, wrong, inward=0.004)))
    yield PAUSE
    key("BACK_SPACE")  # undo the wrong an
    yield PAUSE
    move(*to_window(contour_world(front, an, inward=0.004)))
    yield 0.4
    screenshot("manual_seam_an")
    click(*to_window(contour_world(front, an, inward=0.004)))
    yield PAUSE
    path_a = tailor.shortest_path(mf, a1, an)
    n = len(path_a.positions)
    b1 = b_right[1]  # the hem corner of the back's right side, the hem end of the front's left
    click(*to_window(contour_world(back, b1, inward=0.004)))
    yield PAUSE
    target = b_right[0]
    move(*to_window(contour_world(back, target, inward=0.004)))
    yield 0.4
    screenshot("manual_seam_bn")
    check("no seam before bn", len(scene.tailor.seams) == 0, len(scene.tailor.seams))
    bn_point = contour_world(back, target, inward=0.004)
    click(*to_window(bn_point))
    yield 0.3
    check("manual seam created", len(scene.tailor.seams) == 1, len(scene.tailor.seams))
    s = scene.tailor.seams[0]
    expected_b = tailor.nearer_candidate(mb, b1, n, tuple(mb.contour_point(target)))
    check("manual seam pieces", (s.piece_a, s.piece_b) == (front, back), (s.piece_a, s.piece_b))
    check("manual seam side A", np.allclose(s.a_start, mf.contour_point(a1), atol=1e-5)
          and np.allclose(s.a_end, mf.contour_point(an), atol=1e-5)
          and s.a_direction == path_a.direction.upper(), (tuple(s.a_start), tuple(s.a_end), s.a_direction))
    check("manual seam side B", np.allclose(s.b_start, mb.contour_point(b1), atol=1e-5)
          and np.allclose(s.b_end, mb.contour_point(expected_b.positions[-1]), atol=1e-5)
          and s.b_direction == expected_b.direction.upper(), (tuple(s.b_start), tuple(s.b_end), s.b_direction))
    check("manual seam counts", (s.a_count, s.b_count, s.mode) == (n, n, "EQUAL"), (s.a_count, s.b_count, s.mode))
    last = bpy.context.window_manager.operators[-1]
    check("redo panel is the tool's, with Add Seam's properties",
          last.bl_idname == "TAILOR_OT_seam_pick" and (last.properties.a_start, last.properties.a_end) == (a1, an)
          and last.properties.b_start == b1, (last.bl_idname, last.properties.a_start, last.properties.a_end))
    stored = (tuple(s.a_start), tuple(s.a_end), tuple(s.b_start), tuple(s.b_end))
    key("Z", ctrl=True)
    yield 0.3
    scene = bpy.context.scene  # undo reloads the file's data: fetch it again
    check("Ctrl+Z undoes the seam", len(scene.tailor.seams) == 0, len(scene.tailor.seams))
    key("Z", ctrl=True, shift=True)
    yield 0.3
    scene = bpy.context.scene
    front, back = bpy.data.objects["skirt front"], bpy.data.objects["skirt back"]
    s = scene.tailor.seams[0] if len(scene.tailor.seams) == 1 else None
    check("Ctrl+Shift+Z redoes it", s is not None and s.piece_a == front and
          (tuple(s.a_start), tuple(s.a_end), tuple(s.b_start), tuple(s.b_end)) == stored)

    # Esc cancels a second manual seam half-way: nothing changes.
    invoke("seam_pick")
    yield PAUSE
    click(*to_window(contour_world(front, f_right[0], inward=0.004)))
    yield PAUSE
    click(*to_window(contour_world(front, f_right[1], inward=0.004)))
    yield PAUSE
    key("ESC")
    yield PAUSE
    check("Esc cancels", len(scene.tailor.seams) == 1, len(scene.tailor.seams))

    # 2. Automatic suggestion: the facing sides (front's right, back's left), after the back is
    # re-triangulated finer, so the counts differ and the seam is sewn unequal.
    for obj in bpy.data.objects:
        obj.select_set(obj == back)
    bpy.context.view_layer.objects.active = back
    with override():
        assert bpy.ops.tailor.set_resolution(edge_length=0.03) == {"FINISHED"}
    back.select_set(False)
    mb = mesh(back)
    cb = list(mb.corners)
    b_left = min(runs(cb), key=lambda r: side_x(back, mb, r))
    # Right click cancels the tool half-way.
    invoke("seam_suggest")
    yield PAUSE
    click(*to_window(run_middle(front, *f_right)))
    yield PAUSE
    click(*to_window(run_middle(front, *f_right)), button="RIGHTMOUSE")
    yield PAUSE
    check("right click cancels", len(scene.tailor.seams) == 1, len(scene.tailor.seams))
    invoke("seam_suggest")
    yield PAUSE
    move(*to_window(run_middle(front, *f_right)))
    yield 0.4
    screenshot("suggest_hover")
    click(*to_window(run_middle(front, *f_right)))
    yield PAUSE
    move(*to_window(run_middle(back, *b_left)))
    yield 0.4
    screenshot("suggest_partner")
    click(*to_window(run_middle(back, *b_left)))
    yield 0.3
    check("suggested seam created", len(scene.tailor.seams) == 2, len(scene.tailor.seams))
    s = scene.tailor.seams[1]
    a_run = tailor.candidate_paths(mf, f_right[0], (f_right[1] - f_right[0]) % len(mf.contour) + 1)[0]
    check("suggested side A", np.allclose(s.a_start, mf.contour_point(f_right[0]), atol=1e-5)
          and np.allclose(s.a_end, mf.contour_point(f_right[1]), atol=1e-5) and s.a_direction == "CCW",
          (tuple(s.a_start), tuple(s.a_end)))
    # b1 is the end of the back's left side nearer a1 (sewn edge to edge, not crossed).
    ends = sorted(b_left, key=lambda p: (contour_world(back, p) - contour_world(front, f_right[0])).length)
    check("suggested side B", s.piece_b == back and np.allclose(s.b_start, mb.contour_point(ends[0]), atol=1e-5)
          and np.allclose(s.b_end, mb.contour_point(ends[1]), atol=1e-5), (tuple(s.b_start), tuple(s.b_end)))
    b_run = (b_left[1] - b_left[0]) % len(mb.contour) + 1
    check("suggested seam counts and mode", (s.a_count, s.b_count, s.mode) == (len(a_run.positions), b_run, "UNEQUAL")
          and s.a_count != s.b_count, (s.a_count, s.b_count, s.mode))
    garment = addon_module().scene_data.build_garment(scene)
    check("seams resolve for the solver", len(garment.seams) == 2)

    # 3. Bend with live preview: axis through the front panel's middle, drag 180 px = 90 degrees.
    bpy.context.view_layer.objects.active = front
    front.select_set(True)
    flat = addon_module().scene_data.vertex_positions(front, world=False)
    invoke("bend_interactive")
    yield PAUSE
    rest = np.asarray(mf.rest)
    centre = (rest.min(axis=0) + rest.max(axis=0)) / 2
    from mathutils import Vector

    cx, cy = to_window(front.matrix_world @ Vector((centre[0], centre[1], 0.0)))
    move(cx, cy)
    yield 0.3
    screenshot("bend_axis")
    click(cx, cy)
    yield PAUSE
    move(cx + 90, cy)
    yield PAUSE
    move(cx + 180, cy)
    yield 0.4
    live = addon_module().scene_data.vertex_positions(front, world=False)
    check("live preview bends the mesh", np.abs(live[:, 2]).max() > 0.05, np.abs(live[:, 2]).max())
    top = oblique_view()  # the angle drag reads only the mouse's x: the view may turn meanwhile
    yield 0.4
    screenshot("bend_preview")
    restore_view(top)
    yield PAUSE
    click(cx + 180, cy)
    yield 0.3
    p = front.tailor_piece
    check("bend committed at 90 degrees", abs(math.degrees(p.bend_angle) - 90.0) < 1e-3, math.degrees(p.bend_angle))
    bent = addon_module().scene_data.vertex_positions(front, world=False)
    ref = addon_module().bend.operators.bend_positions(
        front, p.bend_axis_point, p.bend_axis_direction, p.bend_angle,
        (tuple(p.bend_symmetry_point), tuple(p.bend_symmetry_direction)) if p.bend_symmetry else None,
        p.bend_threshold,
    )
    check("bend is the module's", np.allclose(bent, ref, atol=1e-6) and not np.allclose(bent, flat))
    # A second drag cancelled with right click leaves the committed bend as it was.
    invoke("bend_interactive")
    yield PAUSE
    move(cx, cy)
    yield PAUSE
    click(cx, cy)
    yield PAUSE
    move(cx - 120, cy)
    yield PAUSE
    click(cx - 120, cy, button="RIGHTMOUSE")
    yield PAUSE
    after = addon_module().scene_data.vertex_positions(front, world=False)
    check("right click cancels the bend", np.allclose(after, bent, atol=1e-7) and
          abs(math.degrees(p.bend_angle) - 90.0) < 1e-3)
    oblique_view()
    yield 0.4
    screenshot("seams_and_bend")
    small_copies()
    RESULT["ok"] = True


# ---- the timer that steps the scenario -----------------------------------------------------


def finish(code: int) -> None:
    (OUT / "result.json").write_text(json.dumps(RESULT, indent=2))
    print(f"GUI RESULT {'OK' if code == 0 else 'FAILED'} ({len(RESULT['checks'])} checks) -> {OUT}", flush=True)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)  # a clean quit would run the exit handlers of a half-driven UI


STEPS = scenario()
DEADLINE = time.monotonic() + 240.0


def step():
    try:
        if time.monotonic() > DEADLINE:
            raise TimeoutError("the GUI scenario took more than 240 s")
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
