"""What the quality metrics of one frame cost beside its solve: the T-shirt and the skirt samples
dressed on the walking character (`tailor.dress`, 8 x 15), `Simulation.metrics(body)` timed five
times at frames 5 (pieces still round the body), 30 and 60, median printed with the frame's step
time and the on-body share (the figure whose cost this measures: docs/benchmarks.md, "Quality
metrics per frame").

    .venv/bin/python bench/metrics/run.py [--samples tshirt,skirt] [--frames 5,30,60]
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

from tailor.dress import dress
from tailor.motion import ColliderMotion

ROOT = Path(__file__).resolve().parents[2]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--samples", default="tshirt,skirt")
    ap.add_argument("--frames", default="5,30,60")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    frames = sorted(int(f) for f in args.frames.split(","))
    body = ColliderMotion(ROOT / "sample_blends/character.glb", fps=30, loop=True)
    print(f"{'sample':8} {'frame':>5} {'step ms':>8} {'metrics ms':>11} {'on body':>8}")
    for name in args.samples.split(","):
        d = dress(ROOT / f"sample_blends/{name}.json", body.rest, body.triangles, 8, 15)
        for k in range(1, frames[-1] + 1):
            d.move_body(body.at(k))
            st = d.step(1 / 30)
            if k in frames:
                ts = []
                for _ in range(args.repeat):
                    t0 = time.perf_counter()
                    m = d.sim.metrics(d.collider)
                    ts.append(time.perf_counter() - t0)
                print(f"{name:8} {k:5d} {1e3 * st['wall_s']:8.0f} {1e3 * statistics.median(ts):11.1f} "
                      f"{m['on_body_fraction']:8.4f}", flush=True)


if __name__ == "__main__":
    main()
