"""Time to the first GPU frame: three simulations made one after the other in one process
(a 0.6 m cloth of 41 x 41 particles over a sphere collider), each timed from
``tailor.Simulation(..., backend="gpu")`` to the end of its first step. The first makes the
process's shared GPU context (adapter, device, every shader compiled: ``sim.gpu_setup``); the
others reuse it, so their time is their own buffers' upload and the frame.

    python bench/gpu/first_frame.py
"""

from __future__ import annotations

import time

import numpy as np

import tailor


def cloth(n: int = 40, w: float = 0.6):
    u = np.linspace(0.0, w, n + 1, dtype=np.float32)
    xx, yy = np.meshgrid(u, u)
    rest = np.stack([xx.ravel(), yy.ravel()], axis=1).astype(np.float32)
    pos = np.column_stack([rest[:, 0] - w / 2, rest[:, 1] - w / 2, np.full(len(rest), 0.3)]).astype(np.float32)
    q = np.arange(n * (n + 1)).reshape(n, n + 1)[:, :n].ravel()
    tris = np.concatenate([np.stack([q, q + 1, q + n + 2], 1), np.stack([q, q + n + 2, q + n + 1], 1)])
    return pos, tris.astype(np.int64), rest


def main() -> None:
    pos, tris, rest = cloth()
    for k in range(3):
        t0 = time.perf_counter()
        sim = tailor.Simulation(pos, tris, rest, backend="gpu")
        t1 = time.perf_counter()
        sim.add_sphere_collider([0.0, 0.0, 0.0], 0.2)
        st = sim.step(1 / 30)
        t2 = time.perf_counter()
        setup = getattr(sim, "gpu_setup", None)  # None before the shared context (older builds)
        print(f"simulation {k + 1}: {sim.backend} ({sim.adapter}); created in {(t1 - t0) * 1e3:.1f} ms "
              f"(context {'made' if setup and setup['context_made'] else 'reused' if setup else 'of its own'}), first frame "
              f"{(t2 - t1) * 1e3:.1f} ms (on {st['backend']}), {(t2 - t0) * 1e3:.1f} ms in all")


if __name__ == "__main__":
    main()
