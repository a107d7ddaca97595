"""Where a Live frame of the add-on goes (`make profile-live`; docs/benchmarks.md, "Where a Live
frame goes"): the add-on benchmark's Live run (`bench_garments.tailor_live`: the sample on the
walking character, `tailor.live_step` once per frame) with each part of a frame timed on its
own, plus a cProfile of the operator's Python and every Live frame's positions written out so
that two builds of the add-on can be compared frame for frame.

Per frame, with `perf_counter` spans:

* `frame_set`: the timeline moved one frame (`scene.frame_set`: the rig and the skinned body,
  and the pieces' meshes written the frame before, evaluated by the depsgraph), outside the
  operator (`live_step(advance=False)` then does the rest, as `live_step(count=1)` would);
* `op`: the operator call, split into `gather` (the body's evaluated positions), `edits` (the
  panel's fabric, settings and maps compared with the solver's), `submit` (the solver's
  `submit`: copies, the frame's loop up to its solve), `solve` (the native step's own wall
  time, `wall_s`), `measure` (the rest of the native request: the frame's quality metrics and
  the thread's start and hand-over), `collect` (the frame's loop after the solve, on the main
  thread), `apply` (the positions written into the pieces) and `rest` (the operator's own
  dispatch and whatever was not timed).

`--zip` picks the add-on build (default `dist/tailor_addon.zip`), `--positions FILE.npz`
saves every frame's positions (world space, as the solver returned them) and the pieces'
local vertex positions after the last frame.
"""

from __future__ import annotations

import argparse
import cProfile
import io
import json
import os
import pstats
import shutil
import statistics
import sys
import tempfile
import time
from importlib import import_module
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
# Before bpy: the throw-away user directory, and no development `tailor` on the path.
from bench_env import MODULE, ROOT, USER_DIR, install  # noqa: E402

import bpy  # noqa: E402
import numpy as np  # noqa: E402

SPANS = ("frame_set", "op", "gather", "edits", "submit", "solve", "measure", "collect", "apply", "rest")


class Timed:
    """Spans of the frame in progress, by name (summed when a span runs more than once)."""

    def __init__(self) -> None:
        self.frame: dict[str, float] = {}

    def add(self, name: str, seconds: float) -> None:
        self.frame[name] = self.frame.get(name, 0.0) + seconds

    def wrap(self, owner, attr: str, name: str) -> None:
        fn = getattr(owner, attr)

        def timed(*a, **k):
            t0 = time.perf_counter()
            try:
                return fn(*a, **k)
            finally:
                self.add(name, time.perf_counter() - t0)

        setattr(owner, attr, timed)


class PendingProxy:
    """A `tailor.Pending` whose start-to-finish time and `wall_s` are noted."""

    def __init__(self, pending, timed: Timed) -> None:
        self.pending, self.timed, self.t0 = pending, timed, time.perf_counter()

    def done(self):
        return self.pending.done()

    def wait(self, timeout=None):
        return self.pending.wait(timeout)

    def finish(self):
        end = time.perf_counter()
        out = self.pending.finish()
        solve = float(out.get("wall_s", 0.0)) if "wall_s" in out else 0.0
        self.timed.add("solve", solve)
        self.timed.add("measure", end - self.t0 - solve)
        return out


def instrument(timed: Timed) -> None:
    live = import_module(MODULE + ".simulate.live")
    sl = import_module(MODULE + ".core.simulate_live")
    gather = import_module(MODULE + ".simulate.gather")
    from tailor import bake

    timed.wrap(gather, "evaluated_positions", "gather")
    if hasattr(gather, "BodyReader"):  # a build that reads the colliders through a reader object
        timed.wrap(gather.BodyReader, "read", "gather")
    timed.wrap(live.LiveSession, "pending_edits", "edits")
    timed.wrap(sl.LiveSolver, "submit", "submit")
    timed.wrap(sl.LiveSolver, "_collect", "collect")
    timed.wrap(live.LiveSession, "apply", "apply")
    start_async = bake.start_async
    bake.start_async = lambda sim, request: PendingProxy(start_async(sim, request), timed)


def open_walk(garment: str, frames: int, preset: str):
    """The garment sewn on the walking character (`cloth_scene.walking_scene`, `frames` frames),
    opened, at `preset`: (its setup, the scene, the add-on's Live module)."""
    import cloth_scene

    d = Path(tempfile.mkdtemp(prefix=f"tailor-profile-{garment}-"))
    try:
        setup = cloth_scene.walking_scene(garment, d / f"{garment}_walk.blend", frames=frames)
        bpy.ops.wm.open_mainfile(filepath=str(d / f"{garment}_walk.blend"))
    finally:
        shutil.rmtree(d, ignore_errors=True)
    scene = bpy.context.scene
    scene.tailor_simulate.preset = preset
    return setup, scene, import_module(MODULE + ".simulate.live")


def run(garment: str, frames: int, warmup: int, preset: str, profile: bool) -> dict:
    setup, scene, live = open_walk(garment, frames, preset)
    timed = Timed()
    instrument(timed)
    per: list[dict] = []
    positions = []
    prof = cProfile.Profile() if profile else None
    for k in range(setup["end"] - setup["start"]):
        timed.frame = {}
        t0 = time.perf_counter()
        scene.frame_set(scene.frame_current + 1)
        t1 = time.perf_counter()
        if prof is not None and k >= warmup:
            prof.enable()
        assert bpy.ops.tailor.live_step(count=1, advance=False) == {"FINISHED"}
        if prof is not None:
            prof.disable()
        t2 = time.perf_counter()
        f = dict(timed.frame, frame_set=t1 - t0, op=t2 - t1, wall=t2 - t0)
        f["rest"] = f["op"] - sum(f.get(s, 0.0) for s in ("gather", "edits", "submit", "solve", "measure",
                                                           "collect", "apply"))
        # The submit span holds the gather and edits (called before it, outside): none nested.
        session = live.SESSIONS[scene.name]
        f["solve_ms_record"] = session.last.solve_ms / 1e3
        positions.append(np.array(session.last.positions, np.float32))
        if k >= warmup:
            per.append(f)
    session = live.SESSIONS[scene.name]
    if os.environ.get("PROFILE_LIVE_FRAMES"):
        for f in per:
            print("  " + " ".join(f"{s} {f.get(s, 0.0) * 1e3:.2f}" for s in (*SPANS, "wall")))
        sim, col = session.solver.run.sim, session.solver.run.metrics_collider
        for _ in range(5):
            t0 = time.perf_counter()
            sim.metrics(col)
            t1 = time.perf_counter()
            sim.metrics(None)
            print(f"  metrics({col}) {(t1 - t0) * 1e3:.2f} ms, metrics(None) {(time.perf_counter() - t1) * 1e3:.2f} ms")
    local = [np.array([v.co[:] for v in o.data.vertices], np.float32) for o in session.objects]
    bpy.ops.tailor.live_stop()
    med = {s: statistics.median(f.get(s, 0.0) for f in per) * 1e3 for s in (*SPANS, "wall", "solve_ms_record")}
    lo = {s: min(f.get(s, 0.0) for f in per) * 1e3 for s in (*SPANS, "wall")}
    hi = {s: max(f.get(s, 0.0) for f in per) * 1e3 for s in (*SPANS, "wall")}
    out = {"garment": garment, "frames_measured": len(per), "median_ms": med, "min_ms": lo, "max_ms": hi,
           "fps": 1e3 / med["wall"], "positions": positions, "local": local}
    if prof is not None:
        s = io.StringIO()
        pstats.Stats(prof, stream=s).sort_stats("tottime").print_stats(25)
        out["profile"] = s.getvalue()
    return out


def run_modal(garment: str, seconds: float, preset: str, tick_s: float) -> dict:
    """Live as its modal timer runs it, emulated (the bpy wheel has no event loop): the
    timeline plays at the scene's rate for `seconds` (Blender's playback, dropping frames: the
    frame is the one the clock is at), and every `tick_s` seconds the timer's tick
    (`LiveSession.tick`) collects a finished frame, submits the next and writes the pieces.
    Returns Live's frames applied per second, and how long the solver sat idle between
    frames (a finished solve waiting for the next tick, then the main thread's turn)."""
    fps_scene = 30
    frames = int(seconds * fps_scene) + 2
    setup, scene, live = open_walk(garment, frames, preset)
    session = live.start(bpy.context)
    from tailor import bake

    spans = []  # (start, finish) of each native request
    start_async = bake.start_async

    class Noted(PendingProxy):
        def finish(self):
            picked = time.perf_counter()
            out = self.pending.finish()
            spans.append((self.t0, picked, picked - self.t0 - float(out.get("wall_s", 0.0))))
            return out

    bake.start_async = lambda sim, request: Noted(start_async(sim, request), Timed())
    applied, ticks = [], 0
    t0 = time.perf_counter()
    next_tick = t0
    while True:
        now = time.perf_counter()
        if now - t0 >= seconds:
            break
        if now < next_tick:
            time.sleep(next_tick - now)
            continue
        next_tick = now + tick_s  # a window manager timer: the next event an interval after this one
        frame = setup["start"] + min(int((now - t0) * fps_scene), frames - 1)
        if frame != scene.frame_current:
            scene.frame_set(frame)
        res = session.tick(bpy.context)
        ticks += 1
        if session.error is not None:
            raise session.error
        if res is not None:
            applied.append(time.perf_counter())
    elapsed = time.perf_counter() - t0
    live.stop(scene)
    bake.start_async = start_async
    busy = sum(b - a for a, b, _ in spans if a >= t0)
    # From the solve's end to the tick that picks it up (with the frame's measurement, when it
    # was measured): the median is an unmeasured frame's wait for the timer.
    late = statistics.median(w for a, _, w in spans if a >= t0) if spans else 0.0
    return {"garment": garment, "tick_s": tick_s, "seconds": elapsed, "frames": len(applied),
            "fps": len(applied) / elapsed, "solver_busy": busy / elapsed, "ticks": ticks, "pickup_ms": late * 1e3}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--zip", type=Path, default=ROOT / "dist" / "tailor_addon.zip")
    ap.add_argument("--garments", default="tshirt,skirt")
    ap.add_argument("--frames", type=int, default=24, help="Live frames of the walk (as the benchmark)")
    ap.add_argument("--warmup", type=int, default=4)
    ap.add_argument("--preset", default="FINAL")
    ap.add_argument("--profile", action="store_true", help="print the operator's cProfile (25 dearest)")
    ap.add_argument("--positions", type=Path, help="save every frame's positions here (.npz)")
    ap.add_argument("--json", type=Path, help="append the medians as one JSON line here")
    ap.add_argument("--modal", type=float, metavar="TICK_S", help="instead: Live on its (emulated) modal timer, "
                    "ticked every TICK_S seconds while the timeline plays (`run_modal`)")
    ap.add_argument("--seconds", type=float, default=4.0, help="with --modal: how long the timeline plays")
    args = ap.parse_args()
    try:
        install(args.zip)
        import tailor

        assert Path(tailor.__file__).is_relative_to(USER_DIR), tailor.__file__
        saved, line = {}, {"zip": str(args.zip), "load": os.getloadavg()[0],
                           "time": time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime())}
        for g in args.garments.split(",") if args.modal is not None else ():
            r = run_modal(g, args.seconds, args.preset, args.modal)
            print(f"{g}: modal {r['fps']:.2f} fps ({r['frames']} frames in {r['seconds']:.2f} s, tick "
                  f"{args.modal * 1e3:.1f} ms, {r['ticks']} ticks), solver busy {100 * r['solver_busy']:.0f} %, "
                  f"a solve picked up {r['pickup_ms']:.1f} ms after its end (median)",
                  flush=True)
            line[g] = {k: r[k] for k in ("fps", "frames", "seconds", "solver_busy", "tick_s", "pickup_ms")}
        for g in args.garments.split(",") if args.modal is None else ():
            r = run(g, args.frames, args.warmup, args.preset, args.profile)
            m = r["median_ms"]
            print(f"{g}: {r['fps']:.2f} fps, frame {m['wall']:.1f} ms (medians of {r['frames_measured']}): "
                  + ", ".join(f"{s} {m[s]:.2f}" for s in SPANS), flush=True)
            print("   min: " + ", ".join(f"{s} {r['min_ms'][s]:.2f}" for s in SPANS), flush=True)
            if "profile" in r:
                print(r["profile"])
            for i, p in enumerate(r["positions"]):
                saved[f"{g}/frame{i}"] = p
            for i, p in enumerate(r["local"]):
                saved[f"{g}/local{i}"] = p
            line[g] = {"fps": r["fps"], **{k: round(v, 3) for k, v in m.items()}}
        if args.positions:
            np.savez(args.positions, **saved)
        if args.json:
            with open(args.json, "a") as f:
                f.write(json.dumps(line) + "\n")
    finally:
        bpy.ops.preferences.addon_disable(module=MODULE)  # bpy 4.5 hangs at exit otherwise
        shutil.rmtree(USER_DIR, ignore_errors=True)


if __name__ == "__main__":
    main()
