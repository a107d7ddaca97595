"""Tailor (the `tailor` module, CPU) on an exported scene. Knobs: substeps, iterations."""

from __future__ import annotations

import time

import numpy as np

import scenes


def run(scene: dict, knob: dict, cap: float = float("inf")) -> dict:
    import tailor

    t0 = time.perf_counter()
    sim, _cid = scenes.build_simulation(scene, knob["substeps"], knob["iterations"])
    setup = time.perf_counter() - t0
    dt = 1.0 / float(scene["fps"])
    wall, cpu, nan_frame = [], [], None
    for f in range(int(scene["frames"])):
        if sum(wall[1:]) > cap:  # the first frame (Warp compiles its kernels there) does not count
            break
        w0, c0 = time.perf_counter(), time.process_time()
        try:
            sim.step(dt)
        except tailor.SimulationError:
            nan_frame = f + 1
            break
        wall.append(time.perf_counter() - w0)
        cpu.append(time.process_time() - c0)
    x = sim.positions
    if nan_frame is not None:
        x = np.full_like(x, np.nan)
    return dict(frame_wall_s=wall, frame_cpu_s=cpu, setup_s=setup, final=x, nan_frame=nan_frame,
                version=f"tailor {tailor.__version__}", vertex_pairs=None)
