"""Drives Live mode in a real Blender window: the modal operator on its timer while the timeline plays.

Run by Blender itself (Debian's 3.4.1 or newer), under a virtual X server:

    xvfb-run -a -s "-screen 0 800x600x24" blender --factory-startup --enable-event-simulate \
        --python tests/gui/live_driver.py -- --addon-dir addon --out out/gui

(tests/gui/test_gui_live.py runs exactly this; `make test-gui`.) The scene is built here, cheap
enough for a loaded 2-core machine and free of files from newer Blenders (Blender 3.4 cannot
read sample_blends/character.blend): the two-panel skirt (SVG fixture, ~5 cm triangles) lying
flat 2 cm above a plate (a plane marked as collider, friction 1) whose location is keyframed:
still while the cloth lands, then sliding +x, carrying the cloth by friction. Then, as an
artist would:

  1. `tailor.live` is invoked in the 3D view's context (`INVOKE_DEFAULT`: the modal operator on
     its 1/60 s timer, the solve on the worker thread);
  2. `screen.animation_play` plays the timeline; this script (itself a `bpy.app.timers`
     function) samples every ~20 ms of wall time: the frame, the frames Live applied, the
     garment's evaluated world centroid, the plate's location, and the gap since its previous
     call (the UI's responsiveness: timers only run when the main loop is free);
  3. playback is stopped, a screenshot of the view with Live's overlay is taken; playback
     starts again and an Esc event stops it, not Live; Stop Live (`tailor.live_stop`) ends Live;
  4. Live is started again and another file opened (`wm.read_homefile`): Blender cancels Live.

Checks: frames were solved and applied while the timeline advanced; the overlay's fps is above
zero and its text is drawn; the Fit Map (strain) overlay drew both pieces; the garment moved, stayed finite, and followed the plate (its
centroid moved +x by a good part of the plate's travel and stayed on top of it); the largest
gap between timer calls stayed under a generous bound (the main thread never waited for a
solve); Esc stopped playback and left Live running; Stop Live ended Live (its modal operator
too) and put the pieces' meshes back exactly; opening a file during Live left no session, run,
overlay or worker thread behind. Writes `live_result.json` and
`live_mode.png` (+ a 560-pixel `live_mode_small.png` for the docs) into `--out`; exits 0 only
if every check passed.
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
from window import key, override, view3d  # noqa: E402
SKIRT = ROOT / "native/tailor-core/tests/data/svg/skirt_two_panels.svg"
PAUSE = 0.15
TRAVEL = 0.4  # metres the plate slides along +x
DRAPE_END, MOVE_END = 8, 40  # frames: still while the cloth drapes, then sliding (1 cm per frame)
PLAY_SECONDS = 20.0  # at most, of wall time: software GL under Xvfb plays only a few frames a second
MAX_GAP_S = 1.0  # generous: under Xvfb one playback redraw alone takes 0.1-0.5 s on a loaded 2-core machine
#: On a heavily loaded machine playback alone can pause longer than MAX_GAP_S: the bound is then
#: that baseline's longest pause with this much headroom (one frame's main-thread share, not a solve).
BASELINE_HEADROOM = 1.5
BASELINE_S = 1.5  # playback without Live first, for the gap it costs by itself


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("--addon-dir", default=str(ROOT / "addon"), help="folder holding tailor_addon/")
    p.add_argument("--out", default=str(ROOT / "out" / "gui"), help="screenshot and live_result.json")
    return p.parse_args(argv)


# A segfault prints every thread's Python stack before Blender's own crash report.
faulthandler.enable(all_threads=True)
ARGS = parse_args()
OUT = Path(ARGS.out)
OUT.mkdir(parents=True, exist_ok=True)
RESULT: dict = {"checks": [], "screenshots": [], "figures": {}, "ok": False}


def check(what: str, ok: bool, detail="") -> None:
    RESULT["checks"].append({"what": what, "ok": bool(ok), "detail": str(detail)})
    print(f"GUI LIVE {'PASS' if ok else 'FAIL'}: {what} {detail}", flush=True)
    if not ok:
        raise AssertionError(f"{what}: {detail}")


def screenshot(name: str) -> Path:
    path = OUT / f"{name}.png"
    with override():
        bpy.ops.screen.screenshot_area(filepath=str(path))
    check(f"screenshot {name}", path.is_file() and path.stat().st_size > 1000, path)
    return path


def bright_pixels(path: Path, box: tuple[int, int, int, int]) -> int:
    """Pixels brighter than 0.85 in every channel inside `box` (x0, y0, x1, y1; from the image's
    bottom-left, where the overlay's text is drawn)."""
    import numpy as np

    img = bpy.data.images.load(str(path))
    try:
        w, h = img.size
        px = np.empty(w * h * 4, np.float32)
        img.pixels.foreach_get(px)
    finally:
        bpy.data.images.remove(img)
    x0, y0, x1, y1 = box
    rgb = px.reshape(h, w, 4)[y0:y1, x0:x1, :3]
    return int((rgb > 0.85).all(axis=2).sum())


def small_copy(path: Path, width: int = 560) -> Path:
    img = bpy.data.images.load(str(path))
    w, h = img.size
    img.scale(width, round(h * width / w))
    small = path.with_name(path.stem + "_small.png")
    img.filepath_raw = str(small)
    img.file_format = "PNG"
    img.save()
    bpy.data.images.remove(img)
    return small


def world_positions(obj):
    """(n, 3) world positions of the evaluated mesh (what the viewport shows)."""
    import numpy as np

    dg = bpy.context.evaluated_depsgraph_get()
    ev = obj.evaluated_get(dg)
    co = np.empty(len(ev.data.vertices) * 3, np.float64)
    ev.data.vertices.foreach_get("co", co)
    m = np.array(ev.matrix_world, np.float64)
    return co.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]


def mesh_co(obj):
    import numpy as np

    co = np.empty(len(obj.data.vertices) * 3, np.float32)
    obj.data.vertices.foreach_get("co", co)
    return co


def scenario():
    import addon_utils
    import numpy as np
    from mathutils import Euler, Vector

    sys.path.insert(0, ARGS.addon_dir)
    addon_utils.enable("tailor_addon", default_set=True)
    addon = sys.modules["tailor_addon"]
    check("add-on enabled", hasattr(bpy.ops.tailor, "live"))
    RESULT["blender"] = bpy.app.version_string
    bpy.context.preferences.view.smooth_view = 0
    key("ESC")  # the splash screen
    yield PAUSE

    # ---- the scene -----------------------------------------------------------------------------
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    scene = bpy.context.scene
    assert bpy.ops.tailor.import_pattern(filepath=str(SKIRT), edge_length=0.05) == {"FINISHED"}
    pieces = [bpy.data.objects["skirt front"], bpy.data.objects["skirt back"]]
    flat = np.concatenate([world_positions(o) for o in pieces])
    lo, hi = flat.min(axis=0), flat.max(axis=0)
    centre = (lo + hi) / 2
    start = Vector((centre[0], centre[1], hi[2] - 0.02))  # 2 cm under the cloth
    bpy.ops.mesh.primitive_plane_add(size=1.6, location=start)
    plate = bpy.context.view_layer.objects.active
    plate.name = "Plate"
    for obj in scene.objects:
        obj.select_set(obj == plate)
    bpy.context.view_layer.objects.active = plate
    with override():
        assert bpy.ops.tailor.mark_collider() == {"FINISHED"}
    plate.select_set(False)
    plate.tailor_collider.friction_static = plate.tailor_collider.friction_kinetic = 1.0
    for frame, x in ((1, 0.0), (DRAPE_END, 0.0), (MOVE_END, TRAVEL)):
        plate.location = start + Vector((x, 0.0, 0.0))
        plate.keyframe_insert("location", frame=frame)
    scene.frame_start, scene.frame_end = 1, MOVE_END + 20
    scene.render.fps, scene.render.fps_base = 24, 1.0
    scene.sync_mode = "NONE"  # every frame shown (none skipped): the plate moves 1 cm per solved frame
    s = scene.tailor_simulate
    s.preset = "PREVIEW"
    s.fit_map = "STRAIN"  # Live colours the pieces, and the overlay draws them over the solid shading
    scene.frame_set(1)
    check("scene built", plate.tailor_collider.is_collider and all(o.tailor_piece.is_piece for o in pieces))

    # A three-quarter view of the plate's whole path.
    win, area, region, rv3d = view3d()
    space = area.spaces.active
    space.shading.type = "SOLID"
    space.shading.color_type = "OBJECT"  # the cloth in orange on a blue-grey plate
    space.overlay.show_cursor = False
    plate.color = (0.25, 0.32, 0.42, 1.0)
    for o in pieces:
        o.color = (0.9, 0.55, 0.25, 1.0)
    for o in scene.objects:
        o.select_set(False)
    space.overlay.show_floor = space.overlay.show_axis_x = space.overlay.show_axis_y = False
    space.show_region_toolbar = False
    rv3d.view_perspective = "PERSP"
    rv3d.view_rotation = Euler((math.radians(65), 0.0, math.radians(20)), "XYZ").to_quaternion()
    rv3d.view_location = start + Vector((TRAVEL / 2, 0.0, 0.0))
    rv3d.view_distance = 2.4
    area.tag_redraw()
    yield 0.3
    # Baseline: what playback alone costs the UI here (redraws in software GL), then back to frame 1.
    with override():
        bpy.ops.screen.animation_play()
    base, last = [], time.monotonic()
    while sum(base) < BASELINE_S:
        yield 0.02
        now = time.monotonic()
        base.append(now - last)
        last = now
    with override():
        bpy.ops.screen.animation_cancel(restore_frame=True)
    scene.frame_set(1)
    yield 0.2
    RESULT["figures"].update(baseline_median_gap_ms=round(float(np.median(base)) * 1e3, 1),
                             baseline_max_gap_ms=round(max(base) * 1e3, 1))
    before = {o.name: mesh_co(o) for o in pieces}

    # ---- 1. Live, in the window's context ------------------------------------------------------
    with override():
        started = bpy.ops.tailor.live("INVOKE_DEFAULT")
    check("tailor.live starts modal", started == {"RUNNING_MODAL"}, started)
    live = addon.simulate.live
    session = live.SESSIONS.get(scene.name)
    check("a Live session runs", session is not None and s.live_running)

    # ---- 2. play the timeline ------------------------------------------------------------------
    with override():
        played = bpy.ops.screen.animation_play()
    check("the timeline plays", played == {"FINISHED"} and win.screen.is_animation_playing, played)
    samples = []
    gaps = []
    t0 = last = time.monotonic()
    while True:
        yield 0.02
        now = time.monotonic()
        gaps.append(now - last)
        last = now
        samples.append((now - t0, scene.frame_current, session.frames_applied,
                        np.concatenate([world_positions(o) for o in pieces]), plate.matrix_world.translation.copy()))
        if now - t0 > PLAY_SECONDS or scene.frame_current >= MOVE_END:
            break
    with override():
        bpy.ops.screen.animation_cancel(restore_frame=False)
    yield 0.3  # the last frame in flight applied, the overlay redrawn
    wall = time.monotonic() - t0

    # ---- checks on what happened while it played -----------------------------------------------
    first_frame, last_frame = samples[0][1], samples[-1][1]
    applied = session.frames_applied
    ticks = session.ticks
    max_gap = max(gaps)
    stats = session.stats()
    fig = RESULT["figures"]
    fig.update(wall_s=round(wall, 2), timeline_frames=last_frame - first_frame, frames_solved=applied,
               modal_ticks=ticks, max_ui_gap_ms=round(max_gap * 1e3, 1),
               median_ui_gap_ms=round(float(np.median(gaps)) * 1e3, 1), live_fps=round(stats["fps"], 1),
               solve_ms=round(stats["solve_ms"], 1), seam_gap_mm=round(stats["seam_gap_mm"], 2))
    print(f"GUI LIVE figures: {json.dumps(fig)}", flush=True)
    check("the timeline advanced", last_frame - first_frame >= 20, (first_frame, last_frame))
    check("Live solved and applied frames while it played", applied >= 20 and ticks > applied, (applied, ticks))
    check("the overlay's fps is above zero", stats["fps"] > 0 and stats["frame"] is not None, stats)
    bound = max(MAX_GAP_S, BASELINE_HEADROOM * fig["baseline_max_gap_ms"] / 1e3)
    fig["max_ui_gap_bound_ms"] = round(bound * 1e3, 1)
    check("the UI kept handling timers (no freeze for a solve)", max_gap < bound,
          f"max gap {max_gap * 1e3:.0f} ms over {len(gaps)} calls (bound {bound * 1e3:.0f} ms)")
    now_pos = np.concatenate([world_positions(o) for o in pieces])
    check("no NaN in the garment", bool(np.isfinite(now_pos).all()))
    check("the garment moved", float(np.abs(now_pos - flat).max()) > 0.02, np.abs(now_pos - flat).max())
    # Follows the plate: from the sample where the plate starts sliding to the end.
    slide = [smp for smp in samples if smp[4].x > start.x + 1e-4]
    check("the plate slid while Live ran", len(slide) >= 5 and slide[-1][4].x - start.x > TRAVEL / 3,
          (len(slide), slide[-1][4].x - start.x if slide else 0.0))
    c_start = samples[0][3].mean(axis=0)
    plate_dx = float(plate.matrix_world.translation.x - start.x)
    cloth_dx = float(now_pos.mean(axis=0)[0] - c_start[0])
    fig.update(plate_dx_m=round(plate_dx, 3), garment_dx_m=round(cloth_dx, 3))
    check("the garment followed the plate (+x)", cloth_dx > 0.5 * plate_dx,
          f"garment {cloth_dx:.3f} m, plate {plate_dx:.3f} m")
    at = np.array(plate.matrix_world.translation)
    check("the garment stays on the plate", abs(now_pos.mean(axis=0)[0] - at[0]) < 0.2
          and np.abs(now_pos[:, 2] - at[2]).max() < 0.02, (now_pos.mean(axis=0), at))
    # The centroid advanced with the plate through the slide (not one jump at the end).
    mid = slide[len(slide) // 2]
    check("... all along the slide", mid[3].mean(axis=0)[0] > c_start[0] + 0.25 * (mid[4].x - start.x),
          (mid[3].mean(axis=0)[0] - c_start[0], mid[4].x - start.x))

    # The fit-map overlay drew both pieces in the last redraw, from the colours Live wrote.
    drawn = dict(addon.simulate.fit_map_draw.LAST)
    fig.update(fit_map_overlay=drawn)
    check("the fit-map overlay draws the pieces", drawn["objects"] == len(pieces) and drawn["triangles"] > 0, drawn)

    # ---- 3. screenshot with the overlay; Esc stops playback, not Live; Stop Live ends it --------
    shot = screenshot("live_mode")
    RESULT["screenshots"].append(str(shot))
    small = small_copy(shot)
    RESULT["screenshots"].append(str(small))
    with override():
        bpy.ops.screen.animation_play()
    yield 0.3
    # Over the 3D view, whose keymap (Frames) takes Esc for stopping playback.
    _, _, region, _ = view3d()
    key("ESC", x=region.x + region.width // 2, y=region.y + region.height // 2)
    yield 0.4
    check("Esc stops playback, not Live", not win.screen.is_animation_playing and live.SESSIONS.get(scene.name)
          is session and s.live_running, (win.screen.is_animation_playing, s.live_running))
    with override():
        stopped = bpy.ops.tailor.live_stop()
    yield 0.4
    check("Stop Live ends Live", stopped == {"FINISHED"} and scene.name not in live.SESSIONS
          and not s.live_running and not addon.simulate.runs.RUNNING, (stopped, s.live_running))
    for o in pieces:
        check(f"{o.name} restored", np.array_equal(mesh_co(o), before[o.name]))
    after = screenshot("live_stopped")
    RESULT["screenshots"].append(str(after))
    box = (15, 35, 340, 135)  # the overlay's four lines, drawn from (20, 60) up
    lit, unlit = bright_pixels(shot, box), bright_pixels(after, box)
    fig.update(overlay_text_pixels=lit, without_overlay=unlit)
    check("the overlay's text is drawn", lit > 200 and lit > 3 * unlit, (lit, unlit))

    # ---- 4. a file opened while Live runs cancels it -------------------------------------------
    # As an artist opening another file mid-Live: Blender cancels the modal operator (its
    # `cancel()`) after the load_pre handler ends the run while the old file is still loaded.
    # Nothing of the old scene is touched after the load (it is gone).
    runs, draw = addon.simulate.runs, addon.simulate.draw
    with override():
        again = bpy.ops.tailor.live("INVOKE_DEFAULT")
    yield 0.8
    session = live.SESSIONS.get(scene.name)
    running = again == {"RUNNING_MODAL"} and session is not None and bool(runs.RUNNING)
    check("Live runs again", running, (again, list(live.SESSIONS), len(runs.RUNNING)))
    solver = session.solver
    with override():
        bpy.ops.wm.read_homefile()
    yield 0.6
    # The solver runs its frames on a native thread (tailor's, not Python's): stopped, with no
    # frame in progress, it has no work left there.
    check("opening a file ends Live: no session, no run, no overlay, no worker left",
          not live.SESSIONS and not runs.RUNNING and draw._handle is None and solver.stopped and not solver.busy,
          (list(live.SESSIONS), len(runs.RUNNING), draw._handle, solver.stopped, solver.busy))
    check("the new file has no Live running", not bpy.context.scene.tailor_simulate.live_running)
    RESULT["ok"] = True


def finish(code: int) -> None:
    (OUT / "live_result.json").write_text(json.dumps(RESULT, indent=2))
    print(f"GUI LIVE RESULT {'OK' if code == 0 else 'FAILED'} ({len(RESULT['checks'])} checks) -> {OUT}", flush=True)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)  # a clean quit would run the exit handlers of a half-driven UI


STEPS = scenario()
DEADLINE = time.monotonic() + 90.0


def step():
    try:
        if time.monotonic() > DEADLINE:
            raise TimeoutError("the Live scenario took more than 90 s")
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


# Persistent: the scenario opens another file at its end (step 4), which would remove it.
bpy.app.timers.register(step, first_interval=0.5, persistent=True)
