"""``tailor simulate``: simulate a garment file on a collider mesh, headless.

    python -m tailor simulate GARMENT_FILE --collider MESH [--collider-anim CACHE | --animation NAME]
        [--loop] --frames N [--fps 30] [--backend auto|cpu|gpu] [--up y|z] --report REPORT.json
        [-o CACHE.pc2 [--resume]] [--usd GARMENT.usd] [--obj-dir DIR] [--per-piece] [--maps MAPS.npz]
        [--assemble-at rest|start] [--preroll N] [--transition N] [--assembly-gravity]

MESH is an OBJ, PLY or glTF/GLB file (a glTF's first skin animation plays, or the one
``--animation`` names); CACHE is a PC2 file of the collider's vertex positions per frame (both
read by ``tailor.motion.ColliderMotion``). Past the clip's or cache's end the last pose holds;
``--loop`` starts the motion over instead (a walk cycle walking on).
Gravity points down the up axis: Y for OBJ and glTF files by their convention, Z for PLY,
unless ``--up`` says. A garment file that states its up axis (``setup["up"]``: the add-on's
exports say Z, Blender's) and a collider with the other one agree by turning the collider into
the garment's coordinates (``tailor.motion.turn_up``, as Blender's glTF importer does); gravity
and every output (caches, USD's up axis) are then in the garment's. The garment assembles (its
seams close under the damping ramp) and follows the collider.

The assembly is the add-on's Bake's (``tailor.bake.Bake``'s preroll and transition, with its
defaults): on an animated collider the garment is sewn at the collider's rest pose, the pose its
patterns were placed for, for at least ``--preroll`` frames (60) and on while its seams close (up
to 10 s), without gravity unless ``--assembly-gravity``; then ``--transition`` frames (40) move
the collider into the first frame's pose; frame 1 is the garment as it enters the motion (the
assembly's end, with the collider at the motion's first frame, as the add-on's first baked
frame), and each later frame f one step with the collider at the motion's frame f - 1: the
add-on's Bake and this command give the same frames (tests/addon/test_cli_parity.py).
Sewing on the motion's first pose instead put the sample trousers' back piece through the
calf (29 mm inside the body for good). A still collider has one pose: by default the assembly
runs in the recorded frames (no preroll). ``--assemble-at start`` assembles on the first frame's
pose. The report holds one record per frame
and a summary of the same fields (worst case over the frames, mean time of the frames that
were a step: frame 1's holds the whole assembly).

Every frame is judged by ``tailor.judge`` against the start frame (frame 1): whether it
fell off the body (its centroid moved over 20 cm on the body and its top, where it hangs
from, over 10 cm; or, assembled, under 25 % of its particles lie within 10 cm of the body), a seam is open (over 1 cm once assembled), cloth is
inside the body (deeper than 1 cm, or over 1 % of the particles) or the solve diverged. The
records carry ``on_body_fraction``, ``centroid_shift_m``, ``top_shift_m`` and ``failed``; the summary the worst of
them and its ``verdict``: each failed check with the first frame that failed it and why, printed
as a ``warning:`` line.

Every output is the garment welded along its seams (``tailor.export.WeldedGarment``: one
surface, no crack along a seam), unless ``--per-piece`` asks for the pieces as the solver holds
them (``tailor.export.PieceGarment``: each piece its own mesh, as the add-on's bake plays them).
``-o CACHE.pc2`` writes the positions of every frame and, beside it, ``CACHE.obj``: the mesh
the cache deforms (its vertices in the cache's order, with the pattern's UVs, at frame 1), so a
DCC imports the OBJ and plays the PC2 on it (Blender: a Mesh Cache modifier); per piece, the
cache holds every particle, piece after piece in the garment file's order, and the OBJ all the
pieces. ``--usd`` writes one USD mesh (a mesh per piece under ``/Garment`` with
``--per-piece``) with time-sampled points, normals and the pattern's UVs, and the garment's
thickness as the constant primvar ``tailor_thickness`` (``tailor.usd.UsdCache``; needs PyPI's
``usd-core``), saved every 10 frames and at the end, its up axis the run's. ``--obj-dir``
writes one OBJ a frame (``DIR/GARMENT.0001.obj`` on, with UVs; per piece
``DIR/GARMENT.PIECE.0001.obj``).
``--maps`` writes the fit maps of every frame (``Simulation.fit_maps``: strain, signed distance
to the collider, pressure) as an .npz of frames x particles, and their summary in each frame's
record (``"fit"``); not with ``--resume``; with ``--usd`` too, the maps are also time-sampled
primvars of the USD mesh.

Progress: one line per frame on stdout. ``-o`` is written frame by frame (``tailor.Pc2Stream``:
a valid cache of the frames done after every frame), and the report every 10 frames
(``"complete": false`` until the end): a run that crashes or is killed keeps what it did.
``--resume`` goes on from the frames in ``-o``: it solves them again (the solver's state is not
on disk), checks that each comes out identical (else: the garment, collider or settings
changed, and it stops with an error), and continues to ``--frames``.

Exit status: 0 when the result passes its checks; 1 when the solve diverged (NaN); 3
(``FAILED_CHECKS``) when it ran to the end but fails a check (fell, open, inside); 2 on an error
(one line on stderr) or bad arguments. The report is written in every case but the last.

The garment file's setup (``tailor.Garment.setup``) configures the simulation as it does in the
add-on, in the core (``Garment.build_simulation``): fabric per piece, painted maps (pins,
collision levels, friction, mass and bend scales), thickness, self-collision with its radius and
the cloth's friction, the collider's collision levels, and painted pins, which ride on the
collider once every seam has met. ``--thickness`` and ``--self-collision`` override the file's.
``--fabric NAME`` makes every piece that fabric of the library (``tailor.fabric_library()``).
``--preset`` (default ``final``) gives substeps, iterations and tolerance, as the add-on's
Quality does (``tailor.Settings.preset``); ``--substeps`` and ``--iterations`` override it;
``--two-level`` adds the two-level global step (``Settings.two_level``).
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

from tailor import bake
from tailor.bake import FIELDS  # noqa: F401  (the report fields, kept importable from here)

#: Exit status of a run that finished but whose result fails its own checks (fell, open, inside).
FAILED_CHECKS = 3


def register(sub):
    p = sub.add_parser("simulate", help="simulate a garment file on a (moving) collider mesh")
    p.add_argument("garment", metavar="GARMENT_FILE")
    p.add_argument("--collider", metavar="MESH", required=True, help="OBJ, PLY or glTF/GLB collider")
    p.add_argument("--collider-anim", metavar="CACHE", help="PC2 file of collider positions per frame")
    p.add_argument("--animation", metavar="NAME", help="the glTF collider's animation to play (default: its first)")
    p.add_argument("--loop", action="store_true",
                   help="play the collider's animation or cache over again past its end (default: hold its last pose)")
    p.add_argument("--frames", type=int, required=True)
    p.add_argument("--fps", type=float, default=30.0)
    p.add_argument("--backend", choices=("auto", "cpu", "gpu"), default="auto")
    p.add_argument("--threads", type=int, metavar="N",
                   help="CPU threads of the solver (default: one per core; results do not depend on it)")
    p.add_argument("--up", choices=("y", "z"), help="up axis (default: y for OBJ/glTF, z for PLY)")
    p.add_argument("--report", metavar="REPORT.json", required=True)
    p.add_argument("-o", "--output", metavar="CACHE.pc2",
                   help="write the garment's positions, frame by frame as they are solved, and beside it CACHE.obj, "
                        "the mesh the cache deforms (welded along the seams unless --per-piece)")
    p.add_argument("--usd", metavar="GARMENT.usd",
                   help="also write the garment as USD (.usd, .usda or .usdc; needs usd-core), welded along its seams unless "
                        "--per-piece")
    p.add_argument("--obj-dir", metavar="DIR",
                   help="also write the garment as one OBJ a frame (DIR/NAME.0001.obj, ...), welded along its seams unless "
                        "--per-piece (then DIR/NAME.PIECE.0001.obj)")
    p.add_argument("--per-piece", action="store_true",
                   help="write -o, --usd and --obj-dir piece by piece as the solver holds them (default: the garment "
                        "welded along its seams, one surface)")
    p.add_argument("--maps", metavar="MAPS.npz",
                   help="also write the fit maps of every frame (Simulation.fit_maps: strain, signed distance to the "
                        "collider in metres, pressure in pascals), arrays of frames x particles, frame 1 first")
    p.add_argument("--resume", action="store_true",
                   help="go on from the frames already in -o (solved again and checked, then continued)")
    p.add_argument("--edge", type=float, help="re-triangulate every piece at this edge length first")
    p.add_argument("--assemble-at", choices=("rest", "start"), default=None,
                   help="the collider's pose while the garment assembles: its rest pose (as stored; patterns are "
                        "placed for it), then --transition frames into the first frame's; or the first frame's. "
                        "Default: rest for an animated collider (a glTF clip or --collider-anim), start for a still "
                        "one (its only pose)")
    p.add_argument("--preroll", type=int, default=None,
                   help=f"frames solved at the assembly pose before frame 1 is recorded, more while the seams still "
                        f"close, up to {int(bake.ASSEMBLY_MAX_S)} s (default {bake.DEFAULT_PREROLL} when assembling at "
                        f"rest, as the add-on's Preroll; 0 at the start pose: the assembly is recorded)")
    p.add_argument("--transition", type=int, default=bake.DEFAULT_TRANSITION,
                   help=f"frames moving the collider from the rest pose into the first frame's (default "
                        f"{bake.DEFAULT_TRANSITION}, as the add-on's)")
    p.add_argument("--assembly-gravity", action="store_true",
                   help="keep gravity during the preroll (default: none while the garment assembles at rest, as the "
                        "add-on's Assemble Without Gravity)")
    p.add_argument("--preset", choices=("preview", "final"), default="final",
                   help="quality preset: substeps, iterations and tolerance (default final, as the add-on)")
    p.add_argument("--substeps", type=int, help="solver substeps per frame (default: the preset's)")
    p.add_argument("--iterations", type=int, help="solver iterations per substep (default: the preset's)")
    p.add_argument("--two-level", action="store_true",
                   help="the two-level global step: a coarse-grid correction after each sweep, so that bending and "
                        "large-scale stretch converge (docs/accuracy.md)")
    p.add_argument("--fabric", metavar="NAME",
                   help="every piece of this fabric from the library (tailor.fabric_library(); default: the garment "
                        "file's fabrics)")
    p.add_argument("--thickness", type=float, help="collision thickness, metres (default: the garment file's)")
    p.add_argument("--self-collision", action=argparse.BooleanOptionalAction, default=None,
                   help="cloth self-collision on or off (default: as the garment file says, else off)")
    p.add_argument("--self-contacts", choices=("spheres", "triangles"),
                   help="the self-collision contact model: particle spheres, or particles kept off the cloth's "
                        "triangles on the side they started each substep on (CPU only; default: the garment file's, "
                        "else spheres)")
    p.set_defaults(run=run)


def run(args):
    import tailor
    from tailor import bake
    from tailor import dress as dressing
    from tailor.motion import ColliderMotion

    # Every check before any work: the settings by name, then the files (an output over an
    # input, or in a folder it cannot be written to, is refused now rather than after the run).
    tailor.check_playback(args.fps, args.frames)
    inputs = [("GARMENT_FILE", args.garment), ("GARMENT_FILE's sidecar", tailor.sidecar_path(args.garment)),
              ("--collider", args.collider)] + ([("--collider-anim", args.collider_anim)] if args.collider_anim else [])
    obj_output = bool(args.output) and Path(args.output).suffix.lower() == ".obj"
    mesh_path = str(Path(args.output).with_suffix(".obj")) if args.output and not obj_output else None
    outputs = [("--report", args.report)] + [(flag, path) for flag, path in (("-o", args.output), ("--usd", args.usd),
                                                                            ("--maps", args.maps),
                                                                            ("-o's mesh", mesh_path)) if path]
    tailor.check_outputs(inputs, outputs)
    if obj_output:
        raise tailor.InvalidParameterError(f"-o {args.output}: the cache is a PC2 file (its mesh is written beside it "
                                           "as .obj)")
    if args.maps and Path(args.maps).suffix.lower() != ".npz":
        raise tailor.InvalidParameterError(f"--maps {args.maps}: the maps are written as NumPy's .npz")
    if args.maps and args.resume:
        raise tailor.InvalidParameterError("--maps with --resume: the resumed frames are solved again without their "
                                           "maps; run without --resume to map every frame")
    if args.usd and Path(args.usd).suffix.lower() not in (".usd", ".usda", ".usdc"):
        raise tailor.InvalidParameterError(f"--usd {args.usd}: a USD file ends in .usd, .usda or .usdc")
    up = args.up or ("z" if Path(args.collider).suffix.lower() == ".ply" else "y")
    warnings = []
    garment = tailor.Garment.load(args.garment)
    if args.fabric is not None:  # a library name, resolved (or refused, naming the library) by the setup
        garment.setup = {**garment.setup, "fabrics": [args.fabric] * len(garment.pieces)}
    collider_up, up = up, garment.setup.get("up") or up
    gravity = (0.0, -9.81, 0.0) if up == "y" else (0.0, 0.0, -9.81)
    if args.edge is not None:  # --edge 0 is an error (set_resolution names it), not "keep"
        for i in range(len(garment.pieces)):
            garment.set_resolution(i, args.edge)
    # The preset is the module's defaults with its substeps, iterations and tolerance; the
    # constructor checks what the arguments override, by name.
    preset = tailor.Settings.preset(args.preset)
    settings = tailor.Settings(
        substeps=preset.substeps if args.substeps is None else args.substeps,
        iterations=preset.iterations if args.iterations is None else args.iterations,
        tolerance=preset.tolerance, gravity=gravity, two_level=args.two_level)
    self_on = args.self_collision if args.self_collision is not None else garment.setup.get("self_collision")
    if args.two_level and self_on:
        print("note: the two-level step is not applied while self-collision is on (docs/accuracy.md)")
    if args.resume and not args.output:
        raise tailor.InvalidParameterError("--resume needs -o CACHE.pc2: the frames it goes on from")
    motion = ColliderMotion(args.collider, args.collider_anim, animation=args.animation, fps=args.fps,
                            loop=args.loop)
    if collider_up != up:
        motion.turn(collider_up, up)
        print(f"simulate: the collider is {collider_up.upper()} up and the garment {up.upper()} up: the collider is "
              f"turned into the garment's coordinates", flush=True)
    # The assembly (tailor.bake.Bake's preroll and transition), as the add-on's Bake: at the
    # rest pose the patterns were placed for when the collider moves, then into the first frame.
    at_rest = (args.assemble_at or ("start" if motion.kind == "static" else "rest")) == "rest"
    preroll = args.preroll if args.preroll is not None else (bake.DEFAULT_PREROLL if at_rest else 0)
    for name, v in (("--preroll", preroll), ("--transition", args.transition)):
        if v < 0:
            raise tailor.InvalidParameterError(f"{name} {v}: a number of frames is at least 0")
    pose0 = motion.rest if at_rest else motion.at(0)
    d = dressing.dress(garment, pose0, motion.triangles, settings=settings, backend=args.backend,
                       thickness=args.thickness, self_collision=args.self_collision,
                       self_contacts=args.self_contacts, collider_friction=None,
                       strict=False)
    sim, cid, pins = d.sim, d.collider, d.pins
    # What the outputs hold (tailor.export): made from the garment as dressed, before any step,
    # so a resumed run writes the same vertices in the same order.
    from tailor.export import PieceGarment, WeldedGarment

    name = Path(args.garment).stem
    shape = PieceGarment.of_garment(sim, garment) if args.per_piece else WeldedGarment(sim, name)
    if args.threads is not None:
        sim.set_threads(args.threads)
    warnings += d.info["warnings"]
    setup = {k: v for k, v in d.info.items() if k in dressing.SETUP_KEYS}
    print(f"simulate: {sim.num_particles} particles, {len(garment.seams)} seams, collider {len(motion.rest)} vertices "
          f"/ {len(motion.triangles)} triangles, {args.frames} frames at {args.fps:g} fps, up {up}, "
          f"backend {sim.backend}{f' ({sim.adapter})' if sim.adapter else ''}; thickness "
          f"{setup['thickness_m'] * 1e3:g} mm, self-collision "
          f"{'on (' + setup['self_collision_contacts'] + ')' if setup['self_collision'] else 'off'}, "
          f"{settings.substeps} substeps x {settings.iterations} iterations ({args.preset}), "
          f"{setup['attached']} pinned particles")
    transition = args.transition if at_rest else 0
    gravity0 = None if args.assembly_gravity or preroll == 0 else bake.ASSEMBLY_GRAVITY
    if preroll or transition:
        steps = ([f"at least {preroll} frames{' without gravity' if gravity0 else ''}, more while the seams close"]
                 if preroll else []) + ([f"{transition} frames into the first frame"] if transition else [])
        print(f"simulate: assembly at the {'rest pose' if at_rest else 'first frame'}: {', then '.join(steps)}",
              flush=True)
    else:
        print("simulate: the garment assembles in the recorded frames (no preroll)", flush=True)
    # Frame 1 is the garment as it enters the motion: after the assembly, with the collider at
    # the motion's first frame; each later frame f is one step, the collider at the motion's
    # frame f - 1. The add-on's Bake records its start frame the same way, so the two bakes
    # give the same frames (tests/addon/test_cli_parity.py).
    run = bake.Bake(sim, [bake.Collider(args.collider, cid, len(motion.rest))], fps=args.fps, start=1,
                    preroll=preroll, assembly=[motion.rest] if at_rest else None, transition=transition,
                    assembly_gravity=gravity0, pins=pins if len(pins.particles) else None)
    at = lambda f: [motion.at(f - 1)]  # noqa: E731  (frame f: the collider at the motion's frame f - 1)
    cache = None
    if args.resume and os.path.exists(args.output):
        cache = tailor.Pc2Stream.resume(args.output, shape.num_vertices, keep=args.frames)
        done = tailor.read_pc2(args.output)["frames"]
        print(f"resume: solving the {len(done)} frames of {args.output} again and checking them", flush=True)
        run.replay(done, at, view=shape.points)
    elif args.output:
        cache = tailor.Pc2Stream(args.output, shape.num_vertices, start_frame=1.0, sample_rate=1.0)
    frames = list(run.records)  # the frames a resume solved again
    usd = None
    if args.usd:
        from tailor.usd import UsdCache

        usd = UsdCache(args.usd, sim, start_frame=1.0, fps=args.fps, up=up, name=name,
                       thickness=setup["thickness_m"], garment=shape)
        usd.add_all(run.frames)
    objs = None
    if args.obj_dir:
        from tailor.export import ObjSequence

        objs = ObjSequence(args.obj_dir, shape, name=name)
        for f in run.frames:
            objs.add(f)

    def write_mesh() -> None:
        """`-o`'s mesh (CACHE.obj), the garment at frame 1, once frame 1 is solved."""
        if args.output and run.frames:
            from tailor.export import write_mesh as write

            write(mesh_path, shape, run.frames[0])

    write_mesh()

    maps = FitMapFrames(args.maps) if args.maps else None

    def report(complete: bool) -> dict:
        summary = bake.summarize(frames)
        doc = {"frames": frames, "summary": summary, "warnings": warnings, "backend": sim.backend, "threads": sim.threads,
               "adapter": sim.adapter, "gpu_setup": sim.gpu_setup, **setup, "pins_attached": bool(pins.attached), "up": up,
               "collider_up": collider_up, "two_level": settings.two_level,
               "assembly": {"at": "rest" if at_rest else "start", "preroll_frames": run.preroll_frames,
                            "transition_frames": transition, "gravity": gravity0 is None},
               "outputs": "per piece" if args.per_piece else "welded", "fabric": args.fabric, "complete": complete}
        Path(args.report).parent.mkdir(parents=True, exist_ok=True)
        tmp = args.report + ".tmp"
        with open(tmp, "w") as fh:
            json.dump(doc, fh, indent=1)
        os.replace(tmp, args.report)
        return summary

    while run.next_frame <= args.frames:
        f = run.next_frame
        try:
            rec = run.step(at(f))
        except tailor.SimulationError as exc:
            warnings.append(f"frame {f}: {exc}")
            rec = run.record_failure()
        frames.append(rec)
        if cache is not None:
            cache.push(shape.points(run.frames[-1]))
        if f == 1:
            write_mesh()
        frame_maps = sim.fit_maps(cid) if maps is not None else None
        if usd is not None:
            usd.add(run.frames[-1], frame_maps)
        if objs is not None:
            objs.add(run.frames[-1])
        if maps is not None:
            rec["fit"] = maps.add(frame_maps)
        print(f"frame {f:4d}/{args.frames}: {rec['ms']:7.1f} ms, seam gap {rec['seam_gap_max_m'] * 1e3:.2f} mm, "
              f"penetrations {rec['penetration_count']} (max {rec['penetration_max_m'] * 1e3:.2f} mm), "
              f"self-intersections {rec['self_intersections']}, strain max {rec['strain_max']:.3f}, "
              f"on body {rec['on_body_fraction'] * 100:.0f} %, centroid moved {rec['centroid_shift_m'] * 1e2:.1f} cm "
              f"(top {rec['top_shift_m'] * 1e2:.1f} cm), "
              f"on the {(rec.get('backend') or '-').upper()}", flush=True)
        if f % 10 == 0:
            report(complete=False)
            if maps is not None:
                maps.write()
    summary = report(complete=True)
    if maps is not None:
        maps.write()
    if usd is not None:
        usd.close()
    for w in warnings:
        print(f"warning: {w}")
    for line in bake.verdict_lines(summary):
        print(f"warning: {line}")
    print(f"summary: {json.dumps(summary)}")
    if summary["nan"]:
        return 1
    return FAILED_CHECKS if summary["verdict"] else 0


class FitMapFrames:
    """The fit maps of the recorded frames (``--maps``), written to ``path`` as an .npz of
    ``strain``, ``distance`` and ``pressure`` (float32, frames x particles), rewritten whole
    (through a temporary file) every 10 frames and at the end, as the report is."""

    def __init__(self, path: str):
        self.path = path
        self.frames: dict[str, list] = {"strain": [], "distance": [], "pressure": []}

    def add(self, m: dict) -> dict:
        """Keeps one frame's maps; returns their summary for the frame's record."""
        import numpy as np

        for k in self.frames:
            self.frames[k].append(np.asarray(m[k], np.float32))
        s, p, d = m["strain"], m["pressure"], m["distance"]
        return {"strain_p50": float(np.median(s)), "strain_p99": float(np.percentile(s, 99)),
                "strain_max": float(s.max()), "pressure_max_pa": float(p.max()),
                "pressure_p99_pa": float(np.percentile(p, 99)), "distance_median_m": float(np.median(d))}

    def write(self) -> None:
        import numpy as np

        Path(self.path).parent.mkdir(parents=True, exist_ok=True)
        tmp = self.path + ".tmp.npz"
        np.savez(tmp, **{k: np.stack(v) if v else np.zeros((0, 0), np.float32) for k, v in self.frames.items()})
        os.replace(tmp, self.path)

