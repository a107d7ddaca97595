"""Throughput of ``tailor batch`` against the same jobs run one after the other with
``tailor simulate`` (issue 26; docs/batch.md, "Throughput"). A benchmark, not a test.

    python bench/batch/run.py [--repeat 4] [--frames 30] [--out out/bench-batch]

The jobs: the sample skirt and T-shirt on the walking character x the walk and run clips x
`--repeat` copies (each copy a job of its own: another name, the same work), `--frames` frames
of the preview preset after simulate's default assembly. First each job's `tailor simulate`
command, one after the other (every core to each run, its default); then `tailor batch` on a
local Ray instance with one thread per job (one job per core at once). Prints jobs per hour of
both, the batch's start-up and the overhead per job: the batch's wall time over the jobs beyond
their own time inside their tasks, spread over the cores.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SAMPLES = ROOT / "sample_blends"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=4)
    ap.add_argument("--frames", type=int, default=30)
    ap.add_argument("--out", default=str(ROOT / "out" / "bench-batch"))
    args = ap.parse_args()
    out = Path(args.out)
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    settings = {"frames": args.frames, "preset": "preview"}
    jobs = [{"name": f"{g}-{m}-{i}", "garment": str(SAMPLES / f"{g}.json"), "collider": str(SAMPLES / "character.glb"),
             "animation": m} for i in range(args.repeat) for g in ("skirt", "tshirt") for m in ("walk", "run")]
    (out / "jobs.json").write_text(json.dumps({"settings": settings, "jobs": jobs}))
    n = len(jobs)
    cpus = os.cpu_count()

    t = time.time()
    for job in jobs:
        d = out / "sequential" / job["name"]
        d.mkdir(parents=True)
        r = subprocess.run([sys.executable, "-m", "tailor", "simulate", job["garment"], "--collider", job["collider"],
                            "--animation", job["animation"], "--frames", str(args.frames), "--preset", "preview",
                            "--report", str(d / "report.json"), "-o", str(d / "garment.pc2")],
                           capture_output=True, text=True)
        assert r.returncode in (0, 3), r.stderr
    sequential = time.time() - t

    t = time.time()
    r = subprocess.run([sys.executable, "-m", "tailor", "batch", str(out / "jobs.json"), "--out", str(out / "batch"),
                        "--threads", "1"], capture_output=True, text=True)
    batch = time.time() - t
    assert r.returncode == 0, r.stdout + r.stderr
    events = [json.loads(line) for line in (out / "batch" / "batch.jsonl").read_text().splitlines()]
    startup = next(e["elapsed_s"] for e in events if e["event"] == "submit")
    inside = sum(e["seconds"] for e in events if e["event"] == "done")
    same = sum((out / "sequential" / j["name"] / "garment.pc2").read_bytes()
               == (out / "batch" / j["name"] / "garment.pc2").read_bytes() for j in jobs)
    print(f"{n} jobs ({args.frames} frames each, preview, default assembly) on {cpus} cores")
    print(f"tailor simulate one after the other: {sequential:.1f} s, {n / sequential * 3600:.0f} jobs/hour "
          f"({sequential / n:.2f} s a job)")
    print(f"tailor batch (local Ray, 1 thread a job): {batch:.1f} s, {n / batch * 3600:.0f} jobs/hour "
          f"({batch / n:.2f} s a job); Ray start-up {startup:.1f} s")
    print(f"time inside the jobs' tasks: {inside:.1f} s in all, {inside / n:.2f} s a job; overhead per job "
          f"(wall x {cpus} cores - inside) / {n}: {(batch * cpus - inside) / n:.2f} s")
    print(f"caches identical to tailor simulate's: {same} of {n}")


if __name__ == "__main__":
    main()
