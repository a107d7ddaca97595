"""Checks that each sample garment file assembles on the sample character at rest (module only).

    .venv/bin/python sample_blends/build/check_garments.py [--frames 60] [--only tshirt,skirt]

For each of sample_blends/{tshirt,skirt,trousers,layered}.json: the garment is built with its
own fabric, collision levels and thickness (`tailor.dress.dress`), the body of
character.glb in its rest pose is the mesh collider, and the garment is simulated for --frames
frames at 30 fps. Printed per garment: particles, ms/frame, the frame the seams closed (< 1 mm),
and at the end the seam gap, the penetrations (count and deepest, against the thickness), the
strain and the self-intersections. Exits 1 if a seam gap stays >= 1 mm or a particle ends
deeper inside the body than the thickness.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

SAMPLES = Path(__file__).resolve().parent.parent
NAMES = ("tshirt", "skirt", "trousers", "layered")


def check(name: str, frames: int, character) -> dict:
    from tailor import dress as dressing

    d = dressing.dress(SAMPLES / f"{name}.json", character.rest, character.triangles)
    closed, ms = None, []
    for f in range(frames):
        t0 = time.perf_counter()
        st = d.step(1.0 / 30.0)
        ms.append((time.perf_counter() - t0) * 1e3)
        if closed is None and st["seam_gap_max"] < 1e-3:
            closed = f + 1
    q = d.record(frames)
    ok = q["seam_gap_max_m"] < 1e-3 and q["penetration_max_m"] <= d.info["thickness_m"] and not q["nan"]
    print(f"{name:9s} {d.info['particles']:6d} particles {d.info['seams']:3d} seams  {np.median(ms):6.0f} ms/frame  "
          f"closed at frame {closed}  after {frames}: seam gap {q['seam_gap_max_m'] * 1e3:.3f} mm, "
          f"penetrations {q['penetration_count']} (deepest {q['penetration_max_m'] * 1e3:.2f} mm, thickness "
          f"{d.info['thickness_m'] * 1e3:.1f} mm), strain max {q['strain_max']:.3f}, "
          f"self-intersections {q['self_intersections']}  {'ok' if ok else 'FAIL'}", flush=True)
    return {**d.info, **q, "closed_at_frame": closed, "ms_per_frame": float(np.median(ms)), "ok": ok}


def main(argv=None) -> int:
    from tailor.motion import ColliderMotion

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--frames", type=int, default=60)
    ap.add_argument("--only", help="comma-separated sample names")
    args = ap.parse_args(argv)
    character = ColliderMotion(SAMPLES / "character.glb")  # its rest pose
    names = args.only.split(",") if args.only else NAMES
    results = [check(n, args.frames, character) for n in names]
    return 0 if all(r["ok"] for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
