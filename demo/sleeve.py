"""The demo's sleeve scene (``demo/run.py --scene sleeve``): module only, no character, no rendering.

A sleeve (two rectangular panels, 50 × 60 cm) is placed on either side of an arm (a horizontal
capsule), sewn along both long sides, and simulated: the seams close under the damping ramp and
the sleeve drapes over the arm. Prints timings and quality figures, and writes the final garment
as an OBJ and a JSON report.
"""

from __future__ import annotations

import json
import math
import os
import time

import numpy as np

ARM_A = np.array([-0.45, 0.0, 0.5])
ARM_B = np.array([0.45, 0.0, 0.5])
ARM_RADIUS = 0.08


def sleeve_scene(edge: float):
    """The sewn tube of ``tailor.sewn_tube`` turned so its axis runs along the arm (x)."""
    import tailor

    t = tailor.sewn_tube(width=0.5, height=0.6, edge=edge, gap=0.3, bottom=-0.3)
    p = t["positions"]
    t["positions"] = np.stack([p[:, 2], p[:, 1], p[:, 0] + ARM_A[2]], axis=1).astype(np.float32)
    return t


def unique_edges(triangles: np.ndarray) -> np.ndarray:
    e = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    return np.unique(np.sort(e, axis=1), axis=0)


def arm_distance(p: np.ndarray) -> np.ndarray:
    """Signed distance of points to the arm capsule."""
    ab = ARM_B - ARM_A
    t = np.clip(((p - ARM_A) @ ab) / (ab @ ab), 0.0, 1.0)
    return np.linalg.norm(p - (ARM_A + t[:, None] * ab), axis=1) - ARM_RADIUS


def quality(sim, edges, rest_len, thickness):
    p = sim.positions
    strain = np.linalg.norm(p[edges[:, 0]] - p[edges[:, 1]], axis=1) / rest_len - 1.0
    d = arm_distance(p.astype(np.float64))
    gap, _ = sim.seam_gaps()
    inside = d < -1e-3
    return {
        "seam_gap_max_m": float(gap),
        "strain_max": float(strain.max()),
        "strain_mean": float(np.abs(strain).mean()),
        "penetration_count": int(inside.sum()),
        "penetration_max_m": float(max(0.0, -d.min())),
        "clearance_min_m": float(d.min()),
        "nan": bool(not np.isfinite(p).all()),
        "thickness_m": thickness,
    }


def write_obj(path, positions, triangles):
    with open(path + ".tmp", "w") as f:
        f.write("# Tailor demo: sleeve draped on an arm\n")
        for v in positions:
            f.write(f"v {v[0]:.6f} {v[1]:.6f} {v[2]:.6f}\n")
        for t in triangles:
            f.write(f"f {t[0] + 1} {t[1] + 1} {t[2] + 1}\n")
    os.replace(path + ".tmp", path)


def run(args):
    import tailor

    os.makedirs(args.out, exist_ok=True)
    scene = sleeve_scene(args.edge)
    settings = tailor.Settings(substeps=args.substeps, iterations=args.iterations)
    fabric = tailor.Fabric(density=0.15, stretch=600.0, shear=60.0, bend=2e-5)
    sim = tailor.Simulation(scene["positions"], scene["triangles"], scene["rest"], fabric, settings)
    for name, a, b in scene["seams"]:
        sim.add_seam(a, b, stiffness=3000.0, bend_stiffness=1e-5, name=name)
    thickness = 0.003
    sim.thickness = thickness
    sim.add_capsule_collider(ARM_A, ARM_B, ARM_RADIUS, static_friction=0.6, kinetic_friction=0.4)
    edges = unique_edges(scene["triangles"])
    rest = scene["rest"]
    rest_len = np.linalg.norm(rest[edges[:, 0]] - rest[edges[:, 1]], axis=1)

    n = sim.num_particles
    print(f"Tailor {tailor.__version__} demo: sleeve on an arm, {n} particles, {sim.num_triangles} triangles, "
          f"{settings.substeps} substeps x {settings.iterations} iterations ({settings.method}), {os.cpu_count()} CPUs")
    print(f"{'frame':>5} {'ms':>7} {'seam gap mm':>11} {'strain max':>10} {'ramp':>9} {'contacts':>8}")
    frames = []
    wall = time.perf_counter()
    for f in range(args.frames):
        t0 = time.perf_counter()
        st = sim.step(1.0 / 30.0)
        ms = (time.perf_counter() - t0) * 1e3
        rec = {"frame": f + 1, "ms": ms, "solver_ms": st["timings"]["total"] * 1e3,
               "local_ms": st["timings"]["local"] * 1e3, "global_ms": st["timings"]["global"] * 1e3,
               "iterations": st["iterations"], "colours": st["colours"], "ramp": st["ramp_phase"],
               "seam_gap_max_m": st["seam_gap_max"], "contacts": st["contacts"]}
        if (f + 1) % 15 == 0 or f == 0:
            q = quality(sim, edges, rest_len, thickness)
            rec.update(q)
            print(f"{f + 1:5d} {ms:7.1f} {st['seam_gap_max'] * 1e3:11.3f} {q['strain_max']:10.3f} "
                  f"{st['ramp_phase']:>9} {st['contacts']:8d}")
        frames.append(rec)
    wall = time.perf_counter() - wall
    final = quality(sim, edges, rest_len, thickness)
    ms = np.array([r["ms"] for r in frames])
    solve = np.array([r["local_ms"] + r["global_ms"] for r in frames])
    iters = np.array([r["iterations"] for r in frames])
    ns_pi = float(np.median(solve * 1e6 / (n * iters)))
    summary = {
        "particles": n,
        "triangles": sim.num_triangles,
        "frames": args.frames,
        "substeps": settings.substeps,
        "iterations": settings.iterations,
        "colours": frames[-1]["colours"],
        "ms_per_frame_median": float(np.median(ms)),
        "ms_per_frame_p90": float(np.percentile(ms, 90)),
        "ns_per_particle_iteration_median": ns_pi,
        "realtime_factor": (args.frames / 30.0) / wall,
        **final,
    }
    print()
    print(f"timing:  {summary['ms_per_frame_median']:.1f} ms/frame median ({summary['ms_per_frame_p90']:.1f} p90), "
          f"{ns_pi:.1f} ns per particle-iteration, {summary['realtime_factor']:.2f}x real time")
    print(f"quality: seam gap {final['seam_gap_max_m'] * 1e3:.3f} mm, strain max {final['strain_max']:.3f} "
          f"mean {final['strain_mean']:.4f}, penetrations {final['penetration_count']} "
          f"(deepest {final['penetration_max_m'] * 1e3:.2f} mm), min clearance {final['clearance_min_m'] * 1e3:.2f} mm, "
          f"NaN: {final['nan']}")
    write_obj(os.path.join(args.out, "sleeve.obj"), sim.positions, scene["triangles"])
    with open(os.path.join(args.out, "report.json"), "w") as fh:
        json.dump({"summary": summary, "frames": frames}, fh, indent=1)
    print(f"wrote {os.path.join(args.out, 'sleeve.obj')} and {os.path.join(args.out, 'report.json')}")
    ok = final["seam_gap_max_m"] < 2e-3 and not final["nan"] and math.isfinite(summary["ms_per_frame_median"])
    return 0 if ok else 1
