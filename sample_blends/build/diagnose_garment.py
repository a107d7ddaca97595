"""Where a sample garment fails to assemble: per-frame and per-seam figures (module only).

    .venv/bin/python sample_blends/build/diagnose_garment.py layered [--frames 60] [--self on|off|file]

Runs the garment file on the character at rest as check_garments.py does and prints, every 5
frames, the ramp phase, the widest seam gap, the penetrations, the strain and the three seams
with the widest gaps (their widest gap and how many of their pairs are over 1 mm). At the end:
the particles inside the body (piece, depth, where), the most strained edges, and for each sewn
pair still over 1 mm open every particle within a self-collision sphere diameter of its ends
(the candidates that may hold it open). `--self` overrides the file's self-collision choice.
Used for the figures in sample_blends/README.md.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

SAMPLES = Path(__file__).resolve().parent.parent


def seam_gaps(x: np.ndarray, seams: list[dict]) -> list[np.ndarray]:
    out = []
    for s in seams:
        av, aw = np.asarray(s["a_vertices"]), np.asarray(s["a_weights"])
        bv, bw = np.asarray(s["b_vertices"]), np.asarray(s["b_weights"])
        pa, pb = (x[av] * aw[..., None]).sum(1), (x[bv] * bw[..., None]).sum(1)
        out.append(np.linalg.norm(pa - pb, axis=1))
    return out


def penetrating(tailor, x, body, tris, ids) -> list[tuple[int, float]]:
    """(particle, depth) of every particle of `ids` inside the body, by bisection of the set."""
    if len(ids) == 0:
        return []
    p = tailor.penetration(x[ids], body, tris)
    if p["count"] == 0:
        return []
    if len(ids) == 1:
        return [(int(ids[0]), float(p["max_depth"]))]
    h = len(ids) // 2
    return penetrating(tailor, x, body, tris, ids[:h]) + penetrating(tailor, x, body, tris, ids[h:])


def main(argv=None) -> int:
    import tailor
    from tailor import dress as dressing
    from tailor.motion import ColliderMotion

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("name")
    ap.add_argument("--frames", type=int, default=60)
    ap.add_argument("--self", dest="self_collision", choices=("on", "off", "file"), default="file")
    args = ap.parse_args(argv)
    path = SAMPLES / f"{args.name}.json"
    ch = ColliderMotion(SAMPLES / "character.glb")  # its rest pose
    d = dressing.dress(path, ch.rest, ch.triangles)
    if args.self_collision != "file":
        d.sim.set_self_collision(enabled=args.self_collision == "on", radius=d.sim.self_collision["radius_setting"])
    names = [p.name for p in tailor.Garment.load(str(path)).pieces]
    seams = d.sim.seam_pairs()
    for f in range(args.frames):
        st = d.step(1.0 / 30.0)
        if f % 5 == 4 or f == args.frames - 1:
            x = d.sim.positions
            g = seam_gaps(x, seams)
            m = d.sim.metrics(d.collider)
            worst = sorted(range(len(g)), key=lambda k: -g[k].max())[:3]
            print(f"frame {f + 1:3d} {st['ramp_phase']:9s} gap {st['seam_gap_max'] * 1e3:7.2f} mm  "
                  f"penetrations {m['penetration_count']} ({m['penetration_max_depth'] * 1e3:.1f} mm)  "
                  f"strain {m['strain_max']:.2f}/{m['strain_mean']:.3f}  widest: "
                  + ", ".join(f"[{k}] {seams[k]['name']} {g[k].max() * 1e3:.1f} mm ({int((g[k] > 1e-3).sum())}"
                              f"/{len(g[k])} over 1 mm)" for k in worst), flush=True)
    x = d.sim.positions
    offsets = np.array(list(d.offsets) + [len(x)])
    piece = np.searchsorted(offsets, np.arange(len(x)), side="right") - 1
    label = lambda i: f"{i} ({names[piece[i]]}, piece {piece[i]})"  # noqa: E731
    inside = penetrating(tailor, x, ch.rest, ch.triangles, np.arange(len(x)))
    print(f"\n{len(inside)} particles inside the body:")
    for i, depth in inside:
        print(f"  {label(i)} {depth * 1e3:.1f} mm deep at {np.round(x[i], 3)}")
    tris = d.triangles.astype(np.int64)
    edges = np.unique(np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), 1), axis=0)
    rest = d.sim.rest
    length = np.linalg.norm(x[edges[:, 0]] - x[edges[:, 1]], axis=1)
    rest_length = np.linalg.norm(rest[edges[:, 0]] - rest[edges[:, 1]], axis=1)
    strain = np.abs(length / rest_length - 1.0)
    print(f"\n{int((strain > 0.5).sum())} of {len(edges)} edges strained over 0.5; the most:")
    for k in np.argsort(-strain)[:8]:
        print(f"  {label(edges[k][0])} - {edges[k][1]}: {strain[k]:.2f} ({length[k] * 1e3:.1f} mm, rest "
              f"{rest_length[k] * 1e3:.1f} mm)")
    diameter = 2.0 * d.sim.self_collision["radius"]
    print(f"\nsewn pairs over 1 mm open, with the particles within {diameter * 1e3:.1f} mm of their ends:")
    for si, (s, gap) in enumerate(zip(seams, seam_gaps(x, seams))):
        for k in np.flatnonzero(gap > 1e-3):
            ends = [int(v) for side in "ab" for v, w in zip(s[f"{side}_vertices"][k], s[f"{side}_weights"][k])
                    if w > 0]
            near = sorted({(v, int(j), round(float(np.linalg.norm(x[j] - x[v])) * 1e3, 1))
                           for v in ends for j in np.flatnonzero(np.linalg.norm(x - x[v], axis=1) < diameter)
                           if j != v})
            print(f"  [{si}] {s['name']} pair {k}: {gap[k] * 1e3:.1f} mm, ends {[label(v) for v in ends]}")
            print("      near: " + ", ".join(f"{v}-{label(j)} {dist} mm" for v, j, dist in near))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
