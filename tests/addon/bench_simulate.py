"""Add-on level benchmark of Simulate (`make bench-addon-shirt`): Live frames per second and Bake
seconds per frame for the GarmentCode shirt on the walking sample character, through the
installed add-on on the bpy wheel (as `tests/addon/conftest.py` installs it).

Live: `tailor.live_step` advancing the timeline one frame per tick, so each frame pays the
main thread's share (evaluating the collider, writing the pieces) and the worker's solve;
figures are medians over the measured ticks after a warm-up. Bake: `tailor.bake` over the
range; the preroll (assembly) is reported apart from the recorded frames. Each configuration
runs with the isotropic proxy as collider and with the character's own 47.5k-triangle mesh.
Prints a Markdown table (docs/benchmarks.md)."""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import tempfile
import time
from pathlib import Path

from bench_env import MODULE, install  # noqa: E402  (before bpy: Blender's user directory)

import bpy  # noqa: E402


def bench_live(scene_dir: Path, proxy: float | None, edge: float, ticks: int, preset: str) -> dict:
    from simulate_scene import shirt_on_character

    sc = shirt_on_character(scene_dir / "live.blend", edge=edge, proxy_voxel=proxy, frames=(1, 400))
    scene = sc["scene"]
    scene.tailor_simulate.preset = preset
    bpy.ops.tailor.live_step(count=5)  # start, warm up
    from importlib import import_module

    live = import_module(MODULE + ".simulate.live")
    session = live.SESSIONS[scene.name]
    wall, solve = [], []
    for _ in range(ticks):
        t0 = time.perf_counter()
        bpy.ops.tailor.live_step(count=1)
        wall.append(time.perf_counter() - t0)
        solve.append(session.last.solve_ms / 1e3)
    n = session.garment.num_particles
    bpy.ops.tailor.live_stop()
    w, s = statistics.median(wall), statistics.median(solve)
    return {"particles": n, "fps": 1.0 / w, "solver_fps": 1.0 / s, "main_ms": (w - s) * 1e3}


def bench_bake(scene_dir: Path, proxy: float | None, edge: float, frames: int, preset: str) -> dict:
    from simulate_scene import shirt_on_character

    sc = shirt_on_character(scene_dir / "bake.blend", edge=edge, proxy_voxel=proxy, frames=(1, frames))
    scene = sc["scene"]
    scene.tailor_simulate.preset = preset
    t0 = time.perf_counter()
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    total = time.perf_counter() - t0
    report = json.loads(next((scene_dir / "tailor_cache").glob("*.report.json")).read_text())
    recs = report["frames"]
    assembly = recs[0]["ms"] / 1e3
    per_frame = statistics.median(r["ms"] for r in recs[1:]) / 1e3
    s = report["summary"]
    # Where the garment is at the last frame (metrics of a garment that slid off are trivially good).
    import tailor

    tops = []
    for o in sc["pieces"]:
        mod = o.modifiers["Tailor Cache"]
        last = tailor.read_pc2(bpy.path.abspath(mod.filepath))["frames"][-1].astype("float64")
        m = [list(r) for r in o.matrix_world]
        tops.append(max(sum(m[2][j] * p[j] for j in range(3)) + m[2][3] for p in last))
    return {
        "top_m": max(tops),
        "total_s": total,
        "assembly_s": assembly,
        "s_per_frame": per_frame,
        "overhead_s_per_frame": (total - sum(r["ms"] for r in recs) / 1e3) / len(recs),
        "seam_gap_mm": s["seam_gap_max_m"] * 1e3,
        "penetration_mm": s["penetration_max_m"] * 1e3,
        "strain": s["strain_max"],
        "nan": s["nan"],
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ticks", type=int, default=40)
    ap.add_argument("--frames", type=int, default=24)
    ap.add_argument("--edge", type=float, default=0.03)
    args = ap.parse_args()
    install()
    import tailor

    print(f"tailor {tailor.__version__}, Blender {bpy.app.version_string}, {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} CPUs, shirt at {args.edge * 100:g} cm")
    print("| collider | preset | particles | live fps | solver fps | main thread ms/frame | bake s/frame | "
          "assembly s | bake overhead s/frame | seam gap mm | penetration mm | strain | garment top m |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    try:
        for proxy, label in ((0.02, "proxy 2 cm (12.7k tris)"), (None, "body (47.5k tris)")):
            for preset in ("PREVIEW", "FINAL"):
                with tempfile.TemporaryDirectory() as d:
                    lv = bench_live(Path(d), proxy, args.edge, args.ticks, preset)
                with tempfile.TemporaryDirectory() as d:
                    bk = bench_bake(Path(d), proxy, args.edge, args.frames, preset)
                print(f"| {label} | {preset.lower()} | {lv['particles']} | {lv['fps']:.1f} | {lv['solver_fps']:.1f} | "
                      f"{lv['main_ms']:.1f} | {bk['s_per_frame']:.3f} | {bk['assembly_s']:.2f} | "
                      f"{bk['overhead_s_per_frame']:.3f} | {bk['seam_gap_mm']:.2f} | {bk['penetration_mm']:.2f} | "
                      f"{bk['strain']:.3f} | {bk['top_m']:.2f} |", flush=True)
    finally:
        bpy.ops.preferences.addon_disable(module=MODULE)  # bpy 4.5 hangs at exit otherwise


if __name__ == "__main__":
    main()
