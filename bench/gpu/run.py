"""``make bench-gpu``: the GPU engine against the CPU on this machine, as one table.

What a machine with a GPU runs once (issue 27: prepare here, run there), in minutes:

1. the solver alone on growing cloths with body and self collision (the core's `gpu_bench
   --collisions`: 10k, 100k and 1M particles, an animated sphere-mesh body, self-collision on),
   ms per frame on each backend;
2. the four sample garments on the sample character's walk (``tailor simulate`` with
   ``--backend gpu`` and ``--backend cpu``, the Final preset): ms per frame (median of the frames
   after assembly), how many frames each backend solved, and the two runs' seam gap,
   penetration and strain at the last frame, so a GPU figure is never read without its
   agreement with the CPU;
3. with ``--two-level-samples``, those samples again with the two-level global step
   (``--two-level``: `gpu/coarse.wgsl` on the GPU), on both backends.

Writes ``OUT/bench-gpu.md`` (the tables, the adapter, the command, the commit and the machine)
and the raw reports beside it. Usage: ``python bench/gpu/run.py [--out out/bench-gpu]
[--frames 90] [--sizes 10000 100000 1000000] [--budget 2] [--samples tshirt,skirt,trousers,layered]
[--two-level-samples tshirt,skirt] [--bench-bin PATH] [--timeout S]``. ``--bench-bin`` runs a prebuilt ``gpu_bench`` (a GPU machine
without a Rust toolchain gets the binary built elsewhere); ``--timeout`` bounds each run, so a
slow backend costs its row, not the table.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
SAMPLES = REPO / "sample_blends"


def sh(cmd: list[str], **kw) -> subprocess.CompletedProcess:
    print("$ " + " ".join(cmd), flush=True)
    return subprocess.run(cmd, cwd=REPO, text=True, capture_output=True, **kw)


def machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        lines = Path("/proc/cpuinfo").read_text().splitlines()
        cpu = next((ln.split(":", 1)[1].strip() for ln in lines if ln.startswith("model name")), cpu)
    except OSError:
        pass
    load = " ".join(f"{x:.2f}" for x in os.getloadavg())
    return f"{os.cpu_count()} × {cpu}, load average {load}"


def commit() -> str:
    """The checkout's commit, or ``TAILOR_BENCH_COMMIT`` where the tree is a copy without git."""
    try:
        r = sh(["git", "rev-parse", "--short", "HEAD"])
        rev = r.stdout.strip() if r.returncode == 0 else ""
    except OSError:
        rev = ""
    return rev or os.environ.get("TAILOR_BENCH_COMMIT", "unknown")


def solver_table(sizes: list[str], budget: float, bench_bin: str | None, timeout: float) -> str:
    """The core's benchmark with body and self collision (its Markdown table as printed)."""
    program = [bench_bin] if bench_bin else ["cargo", "run", "--release", "-q", "-p", "tailor-core", "--features",
                                             "gpu", "--example", "gpu_bench", "--"]
    cmd = [*program, "--collisions", "--kernels", "--budget", str(budget), *sizes]
    try:
        r = sh(cmd, timeout=timeout)
    except subprocess.TimeoutExpired as e:
        done = e.stdout.decode() if isinstance(e.stdout, bytes) else (e.stdout or "")
        return f"`{' '.join(cmd)}` ran past {timeout:.0f} s; the rows it finished:\n\n{done}\n"
    if r.returncode != 0:
        return f"`{' '.join(cmd)}` failed:\n\n```\n{r.stderr[-2000:]}\n```\n"
    return f"`{' '.join(cmd)}`\n\n{r.stdout}\n"


def sample_run(name: str, backend: str, frames: int, out: Path, timeout: float, extra: tuple[str, ...] = ()) -> dict:
    report = out / f"{name}-{backend}{''.join(extra).replace('--', '-')}.json"
    cmd = [sys.executable, "-m", "tailor", "simulate", str(SAMPLES / f"{name}.json"), "--collider",
           str(SAMPLES / "character.glb"), "--frames", str(frames), "--backend", backend, "--preset", "final",
           # Assembled on the walk's first pose and recorded: the assembly's frames are counted
           # and compared too (the default assembles at rest, unrecorded).
           "--assemble-at", "start", *extra,
           "--report", str(report)]
    t0 = time.perf_counter()
    try:
        r = sh(cmd, timeout=timeout)
    except subprocess.TimeoutExpired as e:
        err = e.stderr.decode(errors="replace") if isinstance(e.stderr, bytes) else (e.stderr or "")
        print(f"{name} on {backend}: ran past {timeout:.0f} s; its last output:\n{err[-600:]}", flush=True)
        return {"error": [f"ran past {timeout:.0f} s"], "wall_s": time.perf_counter() - t0}
    wall = time.perf_counter() - t0
    if not report.exists():
        print(f"{name} on {backend}: no report; its last output:\n{(r.stderr or r.stdout)[-600:]}", flush=True)
        return {"error": (r.stderr or r.stdout).strip().splitlines()[-1:] or ["no report"], "wall_s": wall}
    rep = json.loads(report.read_text())
    recs = rep["frames"]
    assembled = [f for f in recs if not f.get("seams_closing")] or recs
    last = recs[-1]
    return {
        "ms_median": float(np.median([f["ms"] for f in assembled])),
        "backends": rep["summary"].get("backends", {}),
        "seam_gap_mm": last["seam_gap_max_m"] * 1e3,
        "penetration_mm": last["penetration_max_m"] * 1e3,
        "strain_max": last["strain_max"],
        "centroid_shift_m": last["centroid_shift_m"],
        "verdict": [v["check"] for v in rep["summary"]["verdict"]],
        "adapter": rep.get("adapter"),
        "particles": None,
        "wall_s": wall,
    }


def agreement(g: dict, c: dict) -> str:
    """The GPU run against the CPU run of one sample, by the bounds of the T-shirt's test
    (`tests/test_gpu.py`): every frame on the GPU, the same verdict, and at the last frame seam
    gaps within 0.5 mm, deepest penetrations within 2 mm, peak strain within 10 % and centroid
    shifts within 1 cm. A sample that fails its verdict on both backends agrees; its verdict
    column says it failed."""
    if "error" in g or "error" in c:
        return "not compared (a run failed)"
    bad = []
    if g["backends"].get("cpu"):
        bad.append(f"{g['backends']['cpu']} frames on the CPU")
    if g["verdict"] != c["verdict"]:
        bad.append(f"verdict {g['verdict'] or 'passes'} vs {c['verdict'] or 'passes'}")
    if abs(g["seam_gap_mm"] - c["seam_gap_mm"]) >= 0.5:
        bad.append(f"seam gap {g['seam_gap_mm']:.2f} vs {c['seam_gap_mm']:.2f} mm")
    if abs(g["penetration_mm"] - c["penetration_mm"]) >= 2.0:
        bad.append(f"penetration {g['penetration_mm']:.2f} vs {c['penetration_mm']:.2f} mm")
    if abs(g["strain_max"] - c["strain_max"]) >= 0.1 * c["strain_max"]:
        bad.append(f"strain {g['strain_max']:.3f} vs {c['strain_max']:.3f}")
    if abs(g["centroid_shift_m"] - c["centroid_shift_m"]) >= 0.01:
        bad.append(f"centroid {g['centroid_shift_m'] * 100:.1f} vs {c['centroid_shift_m'] * 100:.1f} cm")
    return "agrees" if not bad else "differs: " + "; ".join(bad)


def samples_table(names: list[str], frames: int, out: Path, timeout: float,
                  two_level: list[str] = ()) -> tuple[str, str | None, bool]:
    rows = ["| sample | backend | frames solved (cpu / gpu) | ms/frame, assembled (median) | seam gap, mm | "
            "penetration, mm | strain max | verdict | GPU against CPU |", "|---|---|---|---:|---:|---:|---:|---|---|"]
    adapter, all_agree = None, True
    runs_of = [(name, ()) for name in names] + [(name, ("--two-level",)) for name in two_level]
    for name, extra in runs_of:
        runs = {backend: sample_run(name, backend, frames, out, timeout, extra) for backend in ("gpu", "cpu")}
        label = f"{name}, two-level" if extra else name
        agree = agreement(runs["gpu"], runs["cpu"])
        all_agree &= agree == "agrees"
        for backend, r in runs.items():
            if "error" in r:
                rows.append(f"| {label} | {backend} | failed: {' '.join(r['error'])} | | | | | | |")
                continue
            adapter = adapter or r["adapter"]
            b = r["backends"]
            rows.append(f"| {label} | {backend} | {b.get('cpu', 0)} / {b.get('gpu', 0)} | {r['ms_median']:.1f} | "
                        f"{r['seam_gap_mm']:.2f} | {r['penetration_mm']:.2f} | {r['strain_max']:.3f} | "
                        f"{', '.join(r['verdict']) or 'passes'} | {agree if backend == 'gpu' else ''} |")
    return "\n".join(rows) + "\n", adapter, all_agree


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="out/bench-gpu")
    ap.add_argument("--frames", type=int, default=90)
    ap.add_argument("--sizes", nargs="*", default=["10000", "100000", "1000000"])
    ap.add_argument("--budget", type=float, default=2.0)
    ap.add_argument("--samples", default="tshirt,skirt,trousers,layered")
    ap.add_argument("--two-level-samples", default="", help="samples to run again with --two-level (comma-separated)")
    ap.add_argument("--bench-bin", default=None, help="a prebuilt gpu_bench instead of cargo run")
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds each run may take")
    args = ap.parse_args(argv)
    out = (REPO / args.out) if not Path(args.out).is_absolute() else Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    before = machine()
    solver = solver_table(args.sizes, args.budget, args.bench_bin, args.timeout) if args.sizes else ""
    (out / "solver.md").write_text(solver)  # kept even if the samples do not finish
    samples, adapter, agree = samples_table([s for s in args.samples.split(",") if s], args.frames, out,
                                            args.timeout, [s for s in args.two_level_samples.split(",") if s])
    text = (f"# bench-gpu\n\nCommand: `python bench/gpu/run.py {' '.join(argv or sys.argv[1:])}` ({started}, commit "
            f"{commit()}). Machine: {before}; at the end: {machine()}. GPU adapter: {adapter or 'none'}.\n\n"
            f"## The solver alone, body and self collision\n\n{solver}\n"
            f"## The samples on the walk, Final preset ({args.frames} frames, the assembly included; a frame "
            f"the GPU could not run is counted under cpu)\n\n{samples}")
    (out / "bench-gpu.md").write_text(text)
    print(text)
    print(f"wrote {out / 'bench-gpu.md'}")
    if not agree:
        print("bench-gpu: a sample on the GPU differs from the CPU beyond the stated bounds (see the table)")
    return 0 if agree else 1


if __name__ == "__main__":
    sys.exit(main())
