"""Does a quality setting hold the samples on the walk? (issue 22, docs/benchmarks.md
"Preview on the walk").

``python bench/preview_walk.py TAG [tailor simulate options...]`` runs ``tailor simulate
sample_blends/SAMPLE.json --collider sample_blends/character.glb --frames N`` (the default
rest-pose assembly, then N walk frames) for each sample, with the options given (``--preset
preview``, ``--substeps 6 --iterations 8``, ...), and prints one line per sample: the median
frame time and the worst seam gap, penetration, edge strain and self-intersections over the
frames. ``SAMPLES`` (comma-separated, default all four) and ``FRAMES`` (default 30) in the
environment choose the runs; the reports go to ``OUT`` (default out/preview-walk), named
TAG-SAMPLE.json.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def main(argv: list[str]) -> int:
    if not argv:
        print(__doc__)
        return 2
    tag, extra = argv[0], argv[1:]
    samples = os.environ.get("SAMPLES", "tshirt,skirt,trousers,layered").split(",")
    frames = int(os.environ.get("FRAMES", "30"))
    out = Path(os.environ.get("OUT", REPO / "out" / "preview-walk"))
    out.mkdir(parents=True, exist_ok=True)
    for s in samples:
        rep = out / f"{tag}-{s}.json"
        cmd = [sys.executable, "-m", "tailor", "simulate", f"sample_blends/{s}.json", "--collider",
               "sample_blends/character.glb", "--frames", str(frames), "--report", str(rep), *extra]
        r = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True)
        if not rep.exists():
            print(f"{tag} {s}: no report (exit {r.returncode}): {r.stderr.strip()[-300:]}")
            continue
        fr = json.loads(rep.read_text())["frames"]
        worst = lambda k: max(f[k] for f in fr)  # noqa: E731
        print(f"{tag:12s} {s:9s} ms {statistics.median(f['ms'] for f in fr):7.1f}  "
              f"gap {worst('seam_gap_max_m') * 1e3:5.2f} mm  inside {worst('penetration_max_m') * 1e3:5.2f} mm "
              f"({worst('penetration_count')})  strain {worst('strain_max'):6.3f}  "
              f"self-intersections {worst('self_intersections')}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
