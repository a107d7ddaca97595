"""Add-on level benchmark of the sample garments on the walking character (`make bench-addon`):
Tailor through the installed add-on against Blender's own Cloth modifier with sewing springs
on the same pieces, seams and body, side by side in one run, with the quality of both
measured by the same code on the same recorded frames.

Per garment (`sample_blends/NAME.blend`; the scene as `cloth_scene.walking_scene` sets it up:
60 frames of assembly at the rest pose without gravity, 40 frames into the walk's first pose,
then `--frames` recorded frames of the walk), each run from the saved scene in turn:

* Tailor Live (per preset): `tailor.live_step(count=1)` per frame from the first recorded frame
  (advance the timeline, evaluate the collider, solve on the worker, write the pieces); live
  fps = 1 / the median wall time of a frame after `--warmup` frames. Live has no assembly
  stage: the pieces start open on the walking body.
* Tailor Bake (per preset): `tailor.bake` over the recorded frames (its preroll and transition
  included); s/frame = the operator's wall time / every frame it solved (preroll + transition
  + recorded), and the median solve of a recorded frame from its report.
* Blender Cloth (quality steps `--blender-quality`): the pieces joined into one mesh, seams
  as loose edges, sewing springs on (`bench/peers/peer_blender.py`'s mapping), the collider
  with a Collision modifier, simulated from frame 1 with the same pose keys, gravity keyed off
  for the preroll. Live = timeline stepping, `scene.frame_set(f)` one frame at a time from an
  empty cache; its fps is 1 / the median over the recorded frames after the warm-up, and the
  frames before them are its assembly. Bake = `bpy.ops.ptcache.bake` on a freshly opened scene:
  its wall time / every frame it solved.

Quality, on every recorded frame, by `bench/peers/metrics.quality` (as the peer benchmark):
seam gap over Tailor's sewn pairs (Blender's rounded vertex pairs in brackets), penetration
into the character's evaluated mesh at that frame, strain of the mesh edges against their
rest lengths, self-intersecting triangle pairs, NaN; plus the garment's highest point at the
last frame (a garment that fell off the body has trivially good metrics). Worst frame shown.

Prints a Markdown table and writes every figure to `--out` (JSON)."""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import tempfile
import time
from importlib import import_module
from pathlib import Path

from bench_env import MODULE, ROOT, install  # noqa: E402  (before bpy: Blender's user directory)

import bpy  # noqa: E402
import numpy as np  # noqa: E402

import cloth_scene  # noqa: E402

GARMENTS = ("tshirt", "skirt", "trousers", "layered")


def load() -> float:
    return os.getloadavg()[0]


def open_scene(path: Path):
    bpy.ops.wm.open_mainfile(filepath=str(path))
    return bpy.context.scene


# ---- quality ------------------------------------------------------------------------------------


def body_at(scene, frame: int) -> np.ndarray:
    gather = import_module(MODULE + ".simulate.gather")
    scene.frame_set(frame)
    return gather.evaluated_positions(bpy.data.objects[cloth_scene.BODY], bpy.context.evaluated_depsgraph_get())


def quality(scene, arrays: dict, frames: dict[int, np.ndarray], vertex_pairs=None) -> dict:
    """Worst case over the recorded frames of `metrics.quality`, each frame against the body
    evaluated at that frame; the garment's top at the last frame."""
    _, _, metrics = cloth_scene.peers()
    per = []
    for f, x in sorted(frames.items()):
        arrays["body_vertices"] = body_at(scene, f)
        per.append(metrics.quality(arrays, x, vertex_pairs))
    last = frames[max(frames)]
    top = float(np.nanmax(last[:, 2])) if np.isfinite(last).any() else None
    out = {"nan": any(q["nan"] for q in per), "top_m": top, "frames": len(per)}
    for key in ("seam_gap_m", "seam_gap_vertex_pairs_m", "penetration_max_m", "penetration_count", "strain_max",
                "strain_mean", "self_intersections"):
        vals = [q[key] for q in per if key in q]
        if vals:
            out[key] = max(vals)
    return out


# ---- Tailor -------------------------------------------------------------------------------------


def tailor_live(path: Path, setup: dict, preset: str, warmup: int) -> dict:
    scene = open_scene(path)
    scene.tailor_simulate.preset = preset
    live = import_module(MODULE + ".simulate.live")
    ticks = setup["end"] - setup["start"]
    wall, cpu, solve = [], [], []
    l0 = load()
    for k in range(ticks):
        w0, c0 = time.perf_counter(), time.process_time()
        assert bpy.ops.tailor.live_step(count=1) == {"FINISHED"}
        if k >= warmup:
            wall.append(time.perf_counter() - w0)
            cpu.append(time.process_time() - c0)
            solve.append(live.SESSIONS[scene.name].last.solve_ms / 1e3)
    bpy.ops.tailor.live_stop()
    w = statistics.median(wall)
    return {"fps": 1.0 / w, "s_per_frame": w, "cpu_s_per_frame": statistics.median(cpu),
            "solver_fps": 1.0 / statistics.median(solve), "frames_measured": len(wall), "load": [l0, load()]}


def tailor_bake(path: Path, setup: dict, preset: str, name: str) -> dict:
    scene = open_scene(path)
    s = scene.tailor_simulate
    s.preset = preset
    arrays, pieces = cloth_scene.garment_arrays(scene, name)
    l0 = load()
    w0, c0 = time.perf_counter(), time.process_time()
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    report = json.loads(next((path.parent / "tailor_cache").glob("*.report.json")).read_text())
    recs = report["frames"]
    solved = s.preroll + s.transition + len(recs) - 1
    import tailor

    parts = []
    for o in pieces:
        local = tailor.read_pc2(bpy.path.abspath(o.modifiers["Tailor Cache"].filepath))["frames"].astype(np.float64)
        m = np.array(o.matrix_world, np.float64)
        parts.append((local @ m[:3, :3].T + m[:3, 3]).astype(np.float32))
    world = np.concatenate(parts, axis=1)
    frames = {setup["start"] + i: world[i] for i in range(len(world))}
    out = {"s_per_frame": wall / solved, "cpu_s_per_frame": cpu / solved, "frames_solved": solved,
           "recorded_median_s": statistics.median(r["ms"] for r in recs[1:]) / 1e3,
           "assembly_s": recs[0]["ms"] / 1e3, "load": [l0, load()],
           "report_summary": report["summary"]}
    out["quality"] = quality(scene, arrays, frames)
    return out


# ---- Blender's Cloth ----------------------------------------------------------------------------


def unpinned(arrays: dict) -> dict:
    """The garment without pins: Blender's pin group holds a vertex where it is from the first
    frame (it cannot wait for the seams to close and then ride on the body, as Tailor's pins do),
    so with the samples' pins its seams stay open; without them is its best case here."""
    return {**arrays, "pinned": arrays["pinned"][:0], "pin_weights": arrays["pin_weights"][:0]}


def blender_live(path: Path, setup: dict, name: str, q: int, warmup: int, unpin: bool) -> dict:
    scene = open_scene(path)
    arrays, _ = cloth_scene.garment_arrays(scene, name)
    if unpin:
        arrays = unpinned(arrays)
    obj, mod, pairs = cloth_scene.blender_cloth(scene, arrays, setup, q)
    wall, cpu = {}, {}
    l0 = load()
    for f in range(setup["first"] + 1, setup["end"] + 1):
        w0, c0 = time.perf_counter(), time.process_time()
        scene.frame_set(f)
        wall[f], cpu[f] = time.perf_counter() - w0, time.process_time() - c0
    rec = [f for f in wall if f > setup["start"] + warmup]
    w = statistics.median(wall[f] for f in rec)
    return {"fps": 1.0 / w, "s_per_frame": w, "cpu_s_per_frame": statistics.median(cpu[f] for f in rec),
            "assembly_s": sum(wall[f] for f in wall if f <= setup["start"]), "frames_measured": len(rec),
            "load": [l0, load()], "vertex_pairs": len(pairs)}


def blender_bake(path: Path, setup: dict, name: str, q: int, unpin: bool) -> dict:
    scene = open_scene(path)
    arrays, _ = cloth_scene.garment_arrays(scene, name)
    if unpin:
        arrays = unpinned(arrays)
    obj, mod, pairs = cloth_scene.blender_cloth(scene, arrays, setup, q)
    l0 = load()
    w0, c0 = time.perf_counter(), time.process_time()
    with bpy.context.temp_override(point_cache=mod.point_cache):
        assert bpy.ops.ptcache.bake(bake=True) == {"FINISHED"}
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    if not mod.point_cache.is_baked:
        raise RuntimeError("Blender's cloth cache is not baked after ptcache.bake")
    solved = setup["end"] - setup["first"]
    frames = {}
    for f in range(setup["start"], setup["end"] + 1):
        scene.frame_set(f)
        frames[f] = cloth_scene.evaluated_vertices(obj)
    moved = float(np.abs(frames[setup["end"]] - arrays["positions"]).max())
    out = {"s_per_frame": wall / solved, "cpu_s_per_frame": cpu / solved, "frames_solved": solved,
           "load": [l0, load()], "moved_m": moved}
    out["quality"] = quality(scene, arrays, frames, pairs)
    return out


# ---- table --------------------------------------------------------------------------------------


def fmt_quality(q: dict, pairs: bool = False) -> str:
    if q.get("nan") and "seam_gap_m" not in q:
        return "NaN | | | | |"
    gap = f"{q['seam_gap_m'] * 1e3:.2f}"
    if pairs and "seam_gap_vertex_pairs_m" in q:
        gap += f" ({q['seam_gap_vertex_pairs_m'] * 1e3:.2f})"
    return (f"{gap} | {q.get('penetration_max_m', 0.0) * 1e3:.1f} ({q.get('penetration_count', 0)}) | "
            f"{q['strain_max']:.3f} | {q['self_intersections']} | {q['top_m']:.2f}"
            + (" | NaN" if q["nan"] else " | no"))


HEADER = ("| garment | run | live fps | live CPU s/frame | bake s/frame | bake CPU s/frame | assembly s | "
          "seam gap max mm | penetration max mm (particles) | strain max | self-int. max | top at last frame m | NaN | "
          "load |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|")


def row(g: str, run: str, lv: dict, bk: dict, pairs: bool) -> str:
    if "error" in lv and "error" in bk and lv["error"] == bk["error"]:
        return f"| {g} | {run} | did not run: {lv['error']} |||||||||||"
    live = (f"{lv['fps']:.2f} | {lv['cpu_s_per_frame']:.3f}" if "error" not in lv else f"failed: {lv['error']} |")
    if "error" in bk:
        return f"| {g} | {run} | {live} | bake failed: {bk['error']} |||||||||"
    assembly = bk.get("assembly_s", lv.get("assembly_s", float("nan")))
    loads = lv.get("load", []) + bk["load"]
    return (f"| {g} | {run} | {live} | {bk['s_per_frame']:.3f} | {bk['cpu_s_per_frame']:.3f} | {assembly:.1f} | "
            f"{fmt_quality(bk['quality'], pairs)} | {min(loads):.1f}-{max(loads):.1f} |")


def attempt(what: str, fn, *a):
    """`fn(*a)`, or {"error": ...} when it raises: a run that fails is a row saying why."""
    try:
        return fn(*a)
    except Exception as exc:  # recorded in the table and the JSON, not hidden
        msg = f"{type(exc).__name__}: {str(exc).strip().splitlines()[0]}"
        print(f"{what}: FAILED {msg}", flush=True)
        return {"error": msg}


def bench_garment(g: str, path: Path, args) -> dict:
    """Every run of garment `g`, one after the other on the same saved scene."""
    setup = cloth_scene.walking_scene(g, path, frames=args.frames, preroll=args.preroll, transition=args.transition,
                                      proxy_voxel=args.proxy, unpin=args.unpin)
    res = {"setup": setup, "tailor": {}, "blender": {}}
    for preset in args.presets.split(","):
        lv = attempt(f"{g} Tailor Live {preset}", tailor_live, path, setup, preset, args.warmup)
        bk = attempt(f"{g} Tailor Bake {preset}", tailor_bake, path, setup, preset, g)
        res["tailor"][preset] = {"live": lv, "bake": bk}
        print(f"{g} Tailor {preset.lower()}: {json.dumps(lv)[:300]} {json.dumps(bk)[:600]}", flush=True)
    scene = open_scene(path)
    arrays = attempt(f"{g} garment", lambda: cloth_scene.garment_arrays(scene, g)[0])
    if "error" not in arrays:
        res["particles"] = int(len(arrays["positions"]))
        res["seam_pairs"] = int(len(arrays["seam_a_vertices"]))
        res["placed_top_m"] = float(arrays["positions"][:, 2].max())
        res["fabrics_differ"] = bool(arrays["fabrics_differ"])
        res["self_collision"] = bool(arrays["self_collision"])
    q = args.blender_quality
    blv = attempt(f"{g} Blender live", blender_live, path, setup, g, q, args.warmup, args.blender_unpin)
    bbk = attempt(f"{g} Blender bake", blender_bake, path, setup, g, q, args.blender_unpin)
    res["blender"] = {"quality_steps": q, "live": blv, "bake": bbk}
    print(f"{g} Blender q{q}: {json.dumps(blv)[:300]} {json.dumps(bbk)[:600]}", flush=True)
    return res


def rows(g: str, res: dict) -> list[str]:
    if "particles" in res:
        label = (f"{g} ({res['particles']:,} p., {res['seam_pairs']} sewn pairs"
                 f"{', self-collision' if res['self_collision'] else ''}, placed top {res['placed_top_m']:.2f} m)")
    else:
        label = g
    out = []
    for preset, r in res["tailor"].items():
        out.append(row(label, f"Tailor {preset.lower()}", r["live"], r["bake"], False))
    b = res["blender"]
    pairs = b["live"].get("vertex_pairs")
    out.append(row(label, f"Blender Cloth q{b['quality_steps']}" + (f" ({pairs} vertex pairs)" if pairs else ""),
                   b["live"], b["bake"], True))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--garments", default="tshirt,skirt", help=f"comma-separated, of {','.join(GARMENTS)}")
    ap.add_argument("--frames", type=int, default=24, help="recorded frames of the walk")
    ap.add_argument("--preroll", type=int, default=60, help="assembly frames at the rest pose, without gravity")
    ap.add_argument("--transition", type=int, default=40, help="frames from the rest pose into the walk")
    ap.add_argument("--warmup", type=int, default=4, help="recorded frames left out of the live medians")
    ap.add_argument("--presets", default="PREVIEW,FINAL", help="Tailor's quality presets")
    ap.add_argument("--blender-quality", type=int, default=5, help="Blender's Cloth quality steps (default: its own)")
    ap.add_argument("--proxy", type=float, default=None, help="collide with the add-on's isotropic proxy at this "
                    "voxel size (m) instead of the character's mesh (both simulators)")
    ap.add_argument("--unpin", action="store_true", help="without the samples' painted pins (weight 1 pins "
                    "in place: a seam between two pinned bands cannot close)")
    ap.add_argument("--blender-unpin", action="store_true", help="Blender's Cloth without the painted pins "
                    "(its pins cannot wait for the seams and then ride on the body); Tailor keeps them")
    ap.add_argument("--out", default=str(ROOT / "out" / "bench-addon" / "garments.json"))
    args = ap.parse_args()
    garments = [g for g in args.garments.split(",") if g]
    for g in garments:
        if g not in GARMENTS:
            sys.exit(f"unknown garment '{g}': pick from {', '.join(GARMENTS)}")
    install()
    import tailor

    results = {"argv": sys.argv[1:], "started": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
               "machine": f"{platform.machine()}, {os.cpu_count()} CPUs", "blender": bpy.app.version_string,
               "tailor": tailor.__version__, "garments": {}}
    print(f"tailor {tailor.__version__}, Blender {bpy.app.version_string} (bpy wheel), {results['machine']}, "
          f"load {load():.1f}, {results['started']}", flush=True)
    lines = []
    try:
        for g in garments:
            with tempfile.TemporaryDirectory(prefix=f"tailor-bench-{g}-") as d:
                res = bench_garment(g, Path(d) / f"{g}_walk.blend", args)
            results["garments"][g] = res
            lines += rows(g, res)
        results["finished"] = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
        out = Path(args.out)
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(json.dumps(results, indent=1, default=float))
        print(f"\n{HEADER}")
        print("\n".join(lines))
        print(f"\nwrote {out}; load {load():.1f} at the end, {results['finished']}")
    finally:
        bpy.ops.preferences.addon_disable(module=MODULE)  # bpy 4.5 hangs at exit otherwise


if __name__ == "__main__":
    main()
