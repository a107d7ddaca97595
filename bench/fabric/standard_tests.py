"""The textile laboratory's two standard tests, simulated (issue 28): how far the solver is from
the fabric parameters it is given.

* **Cantilever** (ASTM D1388, option A): a strip 2.5 cm wide held flat on a platform, its free
  end overhanging by `l` and bending down under its own weight. The bending length `c` follows
  from the chord's angle `θ` below the horizontal (Peirce 1930, the standard's formula):
  `c = l · (cos(θ/2) / (8 tan θ))^(1/3)`; an inextensible elastic strip of flexural rigidity
  `B` (N·m) and weight `w = ρ g` per area has `c = (B / w)^(1/3)` (Euler's beam; the standard's
  41.5° is where `l = 2c`). `B` is the rigidity the fabric's hinge stiffness `bend` stands for,
  `tailor.HINGE_ENERGY_PER_RIGIDITY` × bend (the hinge model's energy, calibrated in
  `tailor_core::fabrics`; for a library fabric, its measured rigidity). The overhang is `2c` of
  the fabric, so an exact solver would show 41.5°.
* **Cusick drape** (ISO 9073-9, BS 5058): a 30 cm disc on an 18 cm support, draped under its own
  weight; the drape coefficient is `DC = (A_s − A_d) / (A_D − A_d)`, the shadow area `A_s`
  between the support's `A_d` and the flat disc's `A_D` (1: stiff as a board, 0: hanging
  straight down). The support is modelled as clamped (the test sandwiches the specimen between
  two 18 cm discs): its particles are pinned. No closed form exists, so the reference is the same
  scene solved with many more iterations.

Each is run at the Final preset (8 substeps × 15 iterations), at Final with the two-level global
step (`Settings.two_level`), and with 8 × `--reference-iterations` (default 400) as the nearest
to a converged reference the plain solver gets, through the module (`tailor.Simulation`), for
every fabric of the library (`tailor.fabric_library()`: measured fabrics, their sources in
`tailor_core::fabrics`) and Tailor's default fabric. The source measured stretch and bending, not
these tests: the cantilever's beam length is the one the measured rigidity gives; no measured
drape coefficient exists for these fabrics, so the Cusick table compares with the reference solve.

    python bench/fabric/standard_tests.py [--frames 150] [--reference-iterations 400] [--only cantilever|cusick]

Prints one Markdown table per test.
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np

import tailor

G = 9.81


def fabrics() -> list[tuple[str, "tailor.Fabric"]]:
    """Every library fabric, lightest first, then Tailor's default fabric. A library fabric is
    taken isotropic, its measured directions' geometric means (the library's solver fabric is
    anisotropic, `f["fabric"]`; a specimen cut along each direction is not run yet), so that the
    beam length compares with the one rigidity the strip bends with."""
    def mean(f: dict) -> "tailor.Fabric":
        return tailor.Fabric(f["density"], math.sqrt(f["stretch_u"] * f["stretch_v"]), f["shear"],
                             f["rigidity"] / tailor.HINGE_ENERGY_PER_RIGIDITY)

    return [(f["name"], mean(f)) for f in tailor.fabric_library()] + [("default (Tailor's)", tailor.Fabric())]


def rigidity(fabric) -> float:
    """The flexural rigidity (N·m) a fabric's hinge stiffness stands for."""
    return fabric.bend * tailor.HINGE_ENERGY_PER_RIGIDITY


def piece_mesh(outline: np.ndarray, edge: float, name: str):
    piece = tailor.Piece.from_json(json.dumps({"name": name, "outline": np.asarray(outline).tolist(),
                                               "fixed_vertices": [], "edges": [], "holes": [],
                                               "internal_lines": [], "notches": []}))
    return tailor.triangulate(piece, edge=edge)


def bending_length_from_angle(overhang: float, theta: float) -> float:
    """Peirce's formula: the bending length of a strip overhanging by `overhang` whose chord
    drops `theta` radians below the horizontal."""
    return overhang * (math.cos(theta / 2.0) / (8.0 * math.tan(theta))) ** (1.0 / 3.0)


def beam_bending_length(rigidity: float, density: float) -> float:
    """`c = (B / (ρ g))^(1/3)`, metres, for a flexural rigidity `B` (N·m)."""
    return (rigidity / (density * G)) ** (1.0 / 3.0)


def flat_simulation(mesh, fabric, iterations: int, two_level: bool):
    """`mesh` lying flat at z = 0, of `fabric`, 8 substeps x `iterations`, air damping 2."""
    rest = np.asarray(mesh.rest, np.float32)
    pos = np.column_stack([rest, np.zeros(len(rest), np.float32)])
    settings = tailor.Settings(substeps=8, iterations=iterations, air_damping=2.0, two_level=two_level)
    return tailor.Simulation(pos, mesh.triangles, rest, fabric, settings), rest


def settle(sim, frames: int) -> float:
    t0 = time.perf_counter()
    for _ in range(frames):
        sim.step(1.0 / 30.0)
    return time.perf_counter() - t0


def cantilever(fabric, iterations: int, frames: int, two_level: bool = False) -> dict:
    c = beam_bending_length(rigidity(fabric), fabric.density)
    overhang, clamp, width = 2.0 * c, 0.02, 0.025
    edge = min(overhang / 24.0, 0.005)
    outline = np.array([[-clamp, 0.0], [overhang, 0.0], [overhang, width], [-clamp, width]])
    sim, rest = flat_simulation(piece_mesh(outline, edge, "strip"), fabric, iterations, two_level)
    sim.pin(np.flatnonzero(rest[:, 0] <= 1e-6).astype(np.uint32))
    seconds = settle(sim, frames)
    x = np.asarray(sim.positions)
    tip = x[rest[:, 0] >= overhang - 1e-6].mean(axis=0)
    theta = math.atan2(-tip[2], tip[0])
    return {"c_beam": c, "overhang": overhang, "theta_deg": math.degrees(theta),
            "c": bending_length_from_angle(overhang, theta) if 0 < theta < math.pi / 2 else float("nan"),
            "particles": len(rest), "seconds": seconds}


def shadow_area(x: np.ndarray, triangles: np.ndarray, half: float, cell: float = 1e-3) -> float:
    """Area of the union of the triangles projected onto the horizontal (z) plane, rasterised
    on a grid of `cell` over the square of half-width `half` round the origin."""
    n = int(round(2 * half / cell))
    centres = (np.arange(n) + 0.5) * cell - half
    covered = np.zeros((n, n), bool)
    p = x[:, :2]
    for a, b, c in p[triangles]:
        lo = np.floor((np.minimum(np.minimum(a, b), c) + half) / cell).astype(int).clip(0, n - 1)
        hi = np.ceil((np.maximum(np.maximum(a, b), c) + half) / cell).astype(int).clip(0, n - 1)
        gx, gy = np.meshgrid(centres[lo[0]:hi[0] + 1], centres[lo[1]:hi[1] + 1], indexing="ij")
        q = np.stack([gx, gy], -1)
        d1 = np.cross(b - a, q - a)
        d2 = np.cross(c - b, q - b)
        d3 = np.cross(a - c, q - c)
        inside = ((d1 >= 0) & (d2 >= 0) & (d3 >= 0)) | ((d1 <= 0) & (d2 <= 0) & (d3 <= 0))
        covered[lo[0]:hi[0] + 1, lo[1]:hi[1] + 1] |= inside
    return float(covered.sum()) * cell * cell


def drape_coefficient(shadow: float, specimen_radius: float = 0.15, support_radius: float = 0.09) -> float:
    a_disc, a_support = math.pi * specimen_radius ** 2, math.pi * support_radius ** 2
    return (shadow - a_support) / (a_disc - a_support)


def cusick(fabric, iterations: int, frames: int, edge: float = 0.01, two_level: bool = False) -> dict:
    t = np.linspace(0.0, 2 * math.pi, 189, endpoint=False)
    mesh = piece_mesh(np.column_stack([0.15 * np.cos(t), 0.15 * np.sin(t)]), edge, "disc")
    sim, rest = flat_simulation(mesh, fabric, iterations, two_level)
    sim.pin(np.flatnonzero(np.linalg.norm(rest, axis=1) <= 0.09).astype(np.uint32))
    seconds = settle(sim, frames)
    x = np.asarray(sim.positions)
    dc = drape_coefficient(shadow_area(x, np.asarray(mesh.triangles), 0.16))
    return {"dc": dc, "particles": len(rest), "seconds": seconds}


def three_runs(test, fabric, final: int, args) -> tuple[dict, dict, dict]:
    """`test` at Final, at Final with the two-level step, and with the reference's iterations."""
    return (test(fabric, final, args.frames), test(fabric, final, args.frames, two_level=True),
            test(fabric, args.reference_iterations, args.frames))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--frames", type=int, default=150, help="frames of 1/30 s to settle (default 150: 5 s)")
    ap.add_argument("--reference-iterations", type=int, default=400)
    ap.add_argument("--only", choices=("cantilever", "cusick"))
    args = ap.parse_args(argv)
    final = tailor.Settings.preset("final").iterations
    if args.only != "cusick":
        print("Cantilever (ASTM D1388): bending length c, beam theory against the simulation at Final "
              f"(8 x {final}) and with 8 x {args.reference_iterations} iterations\n")
        print("| fabric | density kg/m² | rigidity µN·m | c, beam | Final: θ, c, error | Final two-level: θ, c, error | "
              f"8 x {args.reference_iterations}: θ, c, error | particles |")
        print("|---|---:|---:|---:|---|---|---|---:|")

        def cell(r: dict) -> str:
            if not r["c"] == r["c"]:  # past the vertical: no bending length
                return f"{r['theta_deg']:.1f}° (past vertical)"
            return f"{r['theta_deg']:.1f}°, {r['c'] * 100:.2f} cm, {100 * (r['c'] / r['c_beam'] - 1):+.0f} %"

        for name, fabric in fabrics():
            f, t, r = three_runs(cantilever, fabric, final, args)
            print(f"| {name} | {fabric.density:.3f} | {rigidity(fabric) * 1e6:.1f} | {f['c_beam'] * 100:.2f} cm | "
                  f"{cell(f)} | {cell(t)} | {cell(r)} | {f['particles']} |", flush=True)
        print()
    if args.only != "cantilever":
        print("Cusick drape (30 cm disc, 18 cm support): drape coefficient at Final "
              f"(8 x {final}) against 8 x {args.reference_iterations} iterations\n")
        print(f"| fabric | density kg/m² | rigidity µN·m | DC Final | DC Final two-level | DC 8 x {args.reference_iterations} | "
              "particles | s Final / two-level / reference |")
        print("|---|---:|---:|---:|---:|---:|---:|---|")
        for name, fabric in fabrics():
            f, t, r = three_runs(cusick, fabric, final, args)
            print(f"| {name} | {fabric.density:.3f} | {rigidity(fabric) * 1e6:.1f} | {f['dc']:.3f} | {t['dc']:.3f} | "
                  f"{r['dc']:.3f} | {f['particles']} | "
                  f"{f['seconds']:.1f} / {t['seconds']:.1f} / {r['seconds']:.1f} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
