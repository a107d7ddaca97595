"""``tailor info``: what a garment file holds, or the sizes a pattern file offers.

``tailor info GARMENT_FILE [--json]`` lists pieces (vertices, triangles, outline length,
smallest triangle angle) and seams (the two pieces, sewn pairs, mode). ``tailor info
PATTERN_FILE --sizes`` lists a graded pattern's sizes (none for an ungraded one).
"""

from __future__ import annotations

import json

import numpy as np


def register(sub):
    p = sub.add_parser("info", help="describe a garment file, or list a pattern's sizes")
    p.add_argument("file", metavar="FILE", help="garment file (.json), or a pattern file with --sizes")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--sizes", action="store_true", help="FILE is a pattern: list its sizes")
    p.set_defaults(run=run)


def outline_length(outline: np.ndarray) -> float:
    return float(np.linalg.norm(np.roll(outline, -1, axis=0) - outline, axis=1).sum())


def garment_info(path: str) -> dict:
    import tailor

    garment = tailor.Garment.load(path)
    pieces, meshes = garment.pieces, garment.meshes()
    out = {"file": path, "pieces": [], "seams": []}
    for piece, mesh in zip(pieces, meshes):
        q = mesh.quality
        out["pieces"].append(
            {
                "name": piece.name,
                "edge_m": mesh.edge_length,
                "vertices": q["vertices"],
                "triangles": q["triangles"],
                "outline_length_m": outline_length(piece.outline),
                "min_angle_deg": q["min_angle_deg"],
            }
        )
    for seam in garment.seams:
        r = seam.resolve(meshes)
        out["seams"].append(
            {
                "name": seam.name,
                "a": pieces[seam.a["piece"]].name,
                "b": pieces[seam.b["piece"]].name,
                "a_vertices": len(r["a_vertices"]),
                "b_vertices": len(r["b_vertices"]),
                "pairs": len(r["pair_a_vertices"]),
                "mode": r["mode"],
            }
        )
    return out


def run(args) -> int:
    import tailor

    if args.sizes:
        sizes = tailor.list_sizes(args.file)
        if args.json:
            print(json.dumps({"file": args.file, "sizes": sizes}))
        else:
            print("\n".join(sizes) if sizes else f"{args.file}: not graded (no sizes)")
        return 0
    info = garment_info(args.file)
    if args.json:
        print(json.dumps(info))
        return 0
    print(f"{info['file']}: {len(info['pieces'])} pieces, {len(info['seams'])} seams")
    for p in info["pieces"]:
        print(
            f"  piece {p['name']}: {p['vertices']} vertices, {p['triangles']} triangles, "
            f"outline {p['outline_length_m']:.3f} m, min angle {p['min_angle_deg']:.1f} deg"
        )
    for s in info["seams"]:
        print(f"  seam {s['name']}: {s['a']} - {s['b']}, {s['pairs']} pairs, {s['mode']}")
    return 0
