"""One peer run in its own process: ``run_one.py SCENE.npz PEER KNOB_JSON OUT.json [CAP_S]``.

Runs the peer (``tailor``, ``blender`` or ``newton``) on the exported scene with the given knob
settings, then measures the quality of its final positions with Tailor's metric functions and
writes timings and metrics as JSON (final positions beside it as ``.npy``). A run whose
stepping passes CAP_S seconds after its first frame stops there: its time per frame still counts, its quality does not. A fresh process per
run keeps the peers' libraries (bpy, Warp) and thread pools apart.
"""

from __future__ import annotations

import json
import sys
import time
import traceback
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import metrics  # noqa: E402
import scenes  # noqa: E402

WARMUP = 5  # frames left out of the median


def main(argv: list[str]) -> int:
    scene_path, peer, knob, out = Path(argv[0]), argv[1], json.loads(argv[2]), Path(argv[3])
    cap = float(argv[4]) if len(argv) > 4 else float("inf")  # seconds of stepping after the first frame
    scene = scenes.load(scene_path)
    rec: dict = dict(scene=scene["name"], peer=peer, knob=knob, particles=len(scene["positions"]),
                     frames=int(scene["frames"]), started=time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()))
    try:
        module = __import__(f"peer_{peer}")
        r = module.run(scene, knob, cap=cap)
    except Exception as exc:  # a peer that cannot run this scene: recorded, not hidden
        rec.update(status="failed", error=f"{type(exc).__name__}: {exc}", traceback=traceback.format_exc())
        out.write_text(json.dumps(rec, indent=1))
        print(f"{peer} {knob}: FAILED {rec['error']}", file=sys.stderr)
        return 0
    wall, cpu = np.array(r["frame_wall_s"]), np.array(r["frame_cpu_s"])
    tail = slice(WARMUP, None) if len(wall) > WARMUP + 2 else slice(0, None)
    rec.update(
        status="ok",
        version=r["version"],
        setup_s=r["setup_s"],
        first_frame_s=float(wall[0]) if len(wall) else None,
        s_per_frame=float(np.median(wall[tail])) if len(wall) else None,
        cpu_s_per_frame=float(np.median(cpu[tail])) if len(cpu) else None,
        frames_run=len(wall),
        capped=len(wall) < int(scene["frames"]) and r["nan_frame"] is None,
        nan_frame=r["nan_frame"],
        frame_wall_s=[float(v) for v in wall],
    )
    rec["quality"] = metrics.quality(scene, r["final"], r.get("vertex_pairs"))
    if r["nan_frame"] is not None:
        rec["quality"]["nan"] = True
    np.save(out.with_suffix(".npy"), np.asarray(r["final"], np.float32))
    out.write_text(json.dumps(rec, indent=1))
    q = rec["quality"]
    print(f"{peer} {json.dumps(knob)}: {rec['s_per_frame'] * 1e3:.1f} ms/frame (cpu {rec['cpu_s_per_frame'] * 1e3:.1f}), "
          f"setup {rec['setup_s']:.2f} s, first frame {rec['first_frame_s']:.2f} s, quality {json.dumps(q)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
