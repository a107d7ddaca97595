"""When and where a bake of the Simulate test scene loses quality (`make diagnose-bake`).

Runs the add-on's own bake job (`simulate.job.BakeJob`: the scene's garment, fabric, seams,
pins and colliders as the Bake operator builds them) on the scene of `simulate_scene.py` (the
GarmentCode shirt on the walking sample character), but steps it one frame at a time through
the three stages `tailor.bake.Bake` runs, printing one line per frame:

1. *pre*: the preroll at the rest pose without gravity (the seams close);
2. *trans*: the colliders moved linearly from the rest pose into the start frame's pose;
3. *walk*: the recorded frames of the walk.

Each line: the largest seam gap, the penetration into the collider (the proxy, what the
bake's report checks) and into the character's own mesh (`Body`, evaluated at the same pose),
the largest edge strain, the garment's lowest and highest point and the seam ramp's phase. On
every `--every`-th frame, on frames failing the issue's thresholds and at the end of each
stage it adds the three widest seams and, for particles more than 2 mm inside the body, which
piece they belong to and which bone the nearest body vertex is weighted to most (`where`: a
nearest-vertex test, an estimate beside the exact counts).

    .venv/bin/python tests/addon/diagnose_bake.py [--lift 0.14] [--edge 0.03] [--seam-stiffness N]
        [--body] [--preroll 60] [--transition 40] [--frames 8]

needs `make addon` first (it installs dist/tailor_addon.zip like the add-on tests do).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
sys.path[:] = [p for p in sys.path if not p.startswith(str(ROOT / "native" / "python"))]
sys.path.insert(0, str(HERE))
os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp(prefix="tailor-diagnose-user-")

import bpy  # noqa: E402
import numpy as np  # noqa: E402

MODULE = "bl_ext.user_default.tailor_addon"
INSIDE_REPORTED = 0.002  # metres: deeper particles are located in the detail lines


def vertex_normals(v: np.ndarray, tris: np.ndarray) -> np.ndarray:
    fn = np.cross(v[tris[:, 1]] - v[tris[:, 0]], v[tris[:, 2]] - v[tris[:, 0]])
    n = np.zeros_like(v)
    for k in range(3):
        np.add.at(n, tris[:, k], fn)
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)


class Where:
    """Piece and body part of particles inside the body (nearest body vertex, its normal)."""

    def __init__(self, body, tris: np.ndarray, piece_names: list[str], offsets: np.ndarray, n: int):
        self.tris = np.asarray(tris, np.int64)
        self.piece_names = piece_names
        self.piece_of = np.searchsorted(np.asarray(offsets), np.arange(n), side="right") - 1
        names = {g.index: g.name for g in body.vertex_groups}
        w = np.zeros((len(body.data.vertices), max(names) + 1), np.float32)
        for v in body.data.vertices:
            for g in v.groups:
                w[v.index, g.group] = g.weight
        self.bone = [names[i] for i in w.argmax(axis=1)]

    def __call__(self, points: np.ndarray, body_v: np.ndarray) -> str:
        v = np.asarray(body_v, np.float64)
        n = vertex_normals(v, self.tris)
        found: dict[tuple[str, str], list[float]] = {}
        for i in range(0, len(points), 128):
            c = np.asarray(points[i:i + 128], np.float64)
            j = ((c[:, None, :] - v[None]) ** 2).sum(-1).argmin(axis=1)
            d = c - v[j]
            depth = -np.sign((d * n[j]).sum(1)) * np.linalg.norm(d, axis=1)
            for k in np.flatnonzero(depth > INSIDE_REPORTED):
                key = (self.piece_names[self.piece_of[i + k]], self.bone[j[k]])
                found.setdefault(key, []).append(float(depth[k]))
        return ", ".join(f"{p} at {b}: {len(d)} (to {max(d) * 1e3:.0f} mm)" for (p, b), d in sorted(found.items()))


def seam_gaps(garment, points: np.ndarray) -> list[tuple[float, str]]:
    out = []
    for k, seam in enumerate(garment.seams):
        av, aw, bv, bw = garment.seam_pairs(k)
        pa = points[av[:, 0]] * aw[:, :1] + points[av[:, 1]] * aw[:, 1:]
        pb = points[bv[:, 0]] * bw[:, :1] + points[bv[:, 1]] * bw[:, 1:]
        out.append((float(np.linalg.norm(pa - pb, axis=1).max()), seam.name))
    return sorted(out, reverse=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lift", type=float, default=None, help="metres (default: simulate_scene.LIFT)")
    ap.add_argument("--edge", type=float, default=0.03)
    ap.add_argument("--body", action="store_true", help="the character's own mesh as collider, no proxy")
    ap.add_argument("--voxel", type=float, default=0.02, help="the collider proxy's voxel size, metres")
    ap.add_argument("--seam-stiffness", type=float, default=None, help="N/m (default: the panel's)")
    ap.add_argument("--preset", default="FINAL")
    ap.add_argument("--preroll", type=int, default=60)
    ap.add_argument("--transition", type=int, default=40)
    ap.add_argument("--frames", type=int, default=8)
    ap.add_argument("--every", type=int, default=10)
    args = ap.parse_args()
    bpy.ops.extensions.package_install_files(filepath=str(ROOT / "dist" / "tailor_addon.zip"), repo="user_default",
                                             enable_on_install=True)
    try:
        run(args)
    finally:
        bpy.ops.preferences.addon_disable(module=MODULE)  # bpy 4.5 hangs at exit otherwise


def run(args) -> None:
    from importlib import import_module

    import tailor
    from simulate_scene import LIFT, shirt_on_character

    job_mod = import_module(MODULE + ".simulate.job")
    gather = import_module(MODULE + ".simulate.gather")
    folder = Path(tempfile.mkdtemp(prefix="tailor-diagnose-"))
    sc = shirt_on_character(folder / "scene.blend", edge=args.edge, proxy_voxel=None if args.body else args.voxel,
                            frames=(1, args.frames), lift=LIFT if args.lift is None else args.lift)
    scene, body = sc["scene"], sc["body"]
    s = scene.tailor_simulate
    s.preset = args.preset
    if args.seam_stiffness is not None:
        s.seam_stiffness = args.seam_stiffness
    s.preroll, s.transition = args.preroll, args.transition
    job = job_mod.BakeJob(scene)
    bake, sim, garment = job.run, job.run.sim, job.garment
    print(f"tailor {tailor.__version__}, Blender {bpy.app.version_string}; {sim.num_particles} particles, "
          f"{len(garment.seams)} seams; {s.substeps} substeps x {s.iterations} iterations, seams {s.seam_stiffness:g} "
          f"N/m, thickness {s.thickness * 1e3:.1f} mm, collider {sc['collider'].name}", flush=True)
    dg = bpy.context.evaluated_depsgraph_get()
    body_tris = gather.evaluated_triangles(body, dg).astype(np.uint32)
    body_rest = gather.rest_pose_positions(scene, [body])[0]
    body_start = gather.colliders_at(scene, [body], job.start)[0]
    where = Where(body, body_tris, job.piece_names, garment.offsets, sim.num_particles)
    thickness = s.thickness

    def line(stage: str, k: int, body_v: np.ndarray, st: dict | None, last: bool = False) -> None:
        p = sim.positions
        m = sim.metrics(bake.metrics_collider)
        pen = tailor.penetration(p, body_v, body_tris)
        bad = m["seam_gap"] >= 1e-3 or m["penetration_max_depth"] >= thickness or pen["max_depth"] >= thickness
        text = (f"{stage:5s} {k:3d}  gap {m['seam_gap'] * 1e3:7.2f} mm  collider {m['penetration_count']:3d} inside, "
                f"{m['penetration_max_depth'] * 1e3:5.1f} mm  body {pen['count']:3d}, {pen['max_depth'] * 1e3:5.1f} mm  "
                f"strain {m['strain_max']:.3f}  z {p[:, 2].min():.2f}-{p[:, 2].max():.2f}"
                + (f"  {st['ramp_phase']}" if st else ""))
        if last or bad or k % args.every == 0:
            text += "\n        widest seams: " + ", ".join(f"{n} {g * 1e3:.1f} mm" for g, n in seam_gaps(garment, p)[:3])
            inside = where(p, body_v)
            if inside:
                text += "\n        inside the body: " + inside
        print(text, flush=True)

    dt = 1.0 / bake.fps

    def step() -> dict:
        """One solver frame; painted pins riding on the character are attached once the seams
        have met, as `tailor.bake.Bake` does."""
        st = sim.step(dt)
        if bake.pins is not None:
            bake.pins.after_frame(sim, st["ramp_phase"])
        return st

    t0 = time.perf_counter()
    rest = bake.assembly
    bake._set_colliders(rest)
    settings = sim.settings
    gravity = settings.gravity
    if bake.assembly_gravity is not None:
        settings.gravity = tuple(bake.assembly_gravity)
        sim.settings = settings
    line("start", 0, body_rest, None, True)
    for k in range(1, args.preroll + 1):
        line("pre", k, body_rest, step(), k == args.preroll)
    settings.gravity = gravity
    sim.settings = settings
    start = job.colliders_at(job.start)
    for k in range(1, args.transition + 1):
        t = k / args.transition
        bake._set_colliders([(1.0 - t) * a + t * b for a, b in zip(rest, start)])
        body_v = ((1.0 - t) * body_rest + t * body_start).astype(np.float32)
        line("trans", k, body_v, step(), k == args.transition)
    for f in range(job.start + 1, job.start + args.frames):
        bake._set_colliders(job.colliders_at(f))
        st = step()
        line("walk", f, gather.colliders_at(scene, [body], f)[0], st, True)
    print(f"{time.perf_counter() - t0:.1f} s", flush=True)


if __name__ == "__main__":
    main()
