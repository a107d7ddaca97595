"""``tailor import``: a pattern file (DXF, SVG, GarmentCode JSON) becomes a garment file.

Every piece is triangulated at ``--edge`` metres; GarmentCode placements are kept and its
stitches become seams (equal-count when both sides have the same number of vertices,
arc-length otherwise). The garment file is ``GARMENT_FILE`` plus a ``.bin`` sidecar. A piece
whose internal lines stop it from triangulating is imported without them, with a warning on
standard error.

With ``--arrange BODY`` every piece is arranged round that body instead
(``tailor.arrange.arrange_garment``: each piece on the place its name and shape suggest,
facing the body ``--clearance`` metres off it and rolled round it; the file's own placements
are dropped), and the plan is printed, one line per piece: what a DXF, which has none, needs
before it can be simulated.
"""

from __future__ import annotations

import sys
from pathlib import Path


def register(sub):
    p = sub.add_parser("import", help="triangulate a pattern file into a garment file")
    p.add_argument("pattern", metavar="PATTERN_FILE", help="DXF, SVG or GarmentCode JSON pattern")
    p.add_argument("--edge", type=float, default=0.01, metavar="METRES", help="target edge length (default 0.01)")
    p.add_argument("--size", default=None, help="size to import from a graded pattern (default: the sample size)")
    p.add_argument("--units", default=None, help="override the file's units (mm, cm, m, inch, ...)")
    p.add_argument("--no-unfold", dest="unfold", action="store_false",
                   help="keep a DXF piece drawn as a half cut on the fold (a mirror line along its edge) as drawn "
                        "(default: mirrored into the whole piece)")
    p.add_argument("--no-quantities", dest="quantities", action="store_false",
                   help="read every DXF piece once, as drawn (default: as many times as its Quantity says: a pair "
                        "as the piece and its mirror image, named R and L; a piece cut 0 times left out)")
    p.add_argument("--arrange", metavar="BODY_MESH",
                   help="arrange every piece round this body (OBJ, PLY or glTF; the file's placements dropped)")
    p.add_argument("--up", choices=("y", "z"), help="the body's up axis (default: y for OBJ/glTF, z for PLY)")
    p.add_argument("--clearance", type=float, default=0.03, metavar="METRES",
                   help="how far off the body an arranged piece starts (default 0.03)")
    p.add_argument("-o", "--output", required=True, metavar="GARMENT_FILE", help="garment file to write (.json)")
    p.set_defaults(run=run)


def run(args) -> int:
    import tailor

    # Before the work, not after it: the garment file and its sidecar must not be the pattern,
    # and their folder must take them (Garment.save also refuses to replace a .bin it did not write).
    inputs = [("PATTERN_FILE", args.pattern)] + ([("--arrange", args.arrange)] if args.arrange else [])
    tailor.check_outputs(inputs, [("-o", args.output), ("-o's sidecar", tailor.sidecar_path(args.output))])
    if not (args.clearance >= 0.0):
        raise tailor.InvalidParameterError(f"--clearance: {args.clearance} must be a distance of 0 or more")
    body = None
    if args.arrange:
        # Read before the pattern's work: a body that cannot be read loses nothing.
        body = tailor.read_mesh(args.arrange)
    garment = tailor.Garment.from_pattern(args.pattern, edge=args.edge, size=args.size, units=args.units,
                                          unfold=args.unfold, quantities=args.quantities)
    if body is not None:
        from tailor.arrange import arrange_garment

        up = args.up or ("z" if Path(args.arrange).suffix.lower() == ".ply" else "y")
        garment, plan = arrange_garment(garment, *body, up=up, clearance=args.clearance)
        for entry in plan:
            print(f"  {entry['name']}: {entry['place']}, {entry.get('side', 'centre')}, "
                  f"turned {entry.get('around_deg', 0.0):.0f} degrees round it, radius {entry['radius']:.3f} m")
    garment.save(args.output)
    for warning in garment.warnings:
        print(f"tailor import: warning: {warning}", file=sys.stderr)
    meshes = garment.meshes()
    vertices = sum(len(m.rest) for m in meshes)
    triangles = sum(len(m.triangles) for m in meshes)
    arranged = f", arranged round {args.arrange}" if args.arrange else ""
    print(
        f"{args.output}: {len(meshes)} pieces, {vertices} vertices, {triangles} triangles, "
        f"{len(garment.seams)} seams (edge {args.edge} m){arranged}"
    )
    return 0
