"""The demo's character scene: a sample garment file on the walking sample character.

The body is `tailor.motion.ColliderMotion` (the glTF's rest pose, its action looping); the
garment is built from its file as the samples are (`tailor.dress.dress`); the
frames run through `tailor.bake.Bake`, the add-on's and ``tailor simulate``'s loop, so the demo
assembles and judges a garment as they do:

1. **assemble** (Bake's preroll): at least ``--assemble`` frames at the rest pose (the A-pose
   GarmentCode places its panels for), more while the seams are still closing;
2. **blend** (Bake's transition): ``--blend`` frames from the rest pose into the action's
   first frame along a smoothstep, so the arms come down through the cloth gently;
3. **animate** (Bake's recorded frames): frame 0 is the garment as it enters the action, then
   ``--frames`` frames of the action, each judged by `tailor.judge` (`tailor.bake.frame_record`)
   against the garment as it started the action.

Bake does not record the assembly; the demo reports it through `Bake.on_assembly_frame` (time,
ramp phase, seam gap per solver frame, the quality every 5th frame and at the end of each
phase). Then every ``--render-every``th frame is rendered with Workbench (`demo.render`, the
`bpy` wheel) with a contact sheet and an animated GIF. Exit status: 3 when the verdict fails a
check, 1 on NaN or seams that never met (< 1 mm), as ``tailor simulate``. Written into
``--out``:

* ``frames/frame_NNNN.png`` (NNNN: the solver step), ``contact_sheet.png``, ``animation.gif``
  (the frames at the simulation's speed), ``body_only.png`` (the body alone at the last frame);
* ``garment.pc2``: the garment after every solver step, frame k after k steps (frame 0 as
  placed; the action's frame f is step ``action_start_step`` + f), Y-up, metres;
* ``report.json``: ``assembly`` (one record per assembly step), ``frames`` (Bake's records of
  the action; frame 0's ``ms`` is the whole assembly's) and ``summary`` (per phase, Bake's
  summary of the action as ``action``, and its verdict).
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import numpy as np

FPS = 30.0
MET = 1e-3  # seams count as met below this gap (the sample garments settle at 0.4-1.3 mm at rest)
COLOURS = {"tshirt": (0.10, 0.33, 0.78), "skirt": (0.70, 0.12, 0.22), "trousers": (0.18, 0.22, 0.32),
           "layered": (0.20, 0.45, 0.30)}
PHASES = {"preroll": "assemble", "transition": "blend"}  # Bake's names -> the demo's


def phase_summary(records: list[dict]) -> dict:
    """Frames, ms/frame (median, max) and the worst quality over the records that have it."""
    if not records:
        return {}
    from tailor.bake import FIELDS

    q = [r for r in records if "strain_max" in r]
    out = {"frames": len(records), "ms_per_frame_median": float(np.median([r["ms"] for r in records])),
           "ms_per_frame_max": float(np.max([r["ms"] for r in records]))}
    if q:
        out.update({k: max(r[k] for r in q) for k in FIELDS}, nan=any(r["nan"] for r in q))
    return out


def row(step: int, phase: str, r: dict, ramp: str) -> str:
    q = "strain_max" in r
    return (f"{step:5d} {phase:>8} {r['ms']:7.1f} {r['seam_gap_max_m'] * 1e3:11.3f} "
            + (f"{r['penetration_count']:5d} {r['penetration_max_m'] * 1e3:10.2f} {r['strain_max']:10.3f}" if q
               else f"{'':>5} {'':>10} {'':>10}") + f" {ramp:>9}")


def run(args) -> int:
    import tailor
    from tailor import bake
    from tailor import dress as dressing
    from tailor.motion import ColliderMotion

    t_all = time.perf_counter()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    body = ColliderMotion(args.character, animation=args.action, fps=FPS, loop=True)
    d = dressing.dress(args.garment, body.rest, body.triangles, args.substeps, args.iterations)
    load_s = time.perf_counter() - t0
    sim, info = d.sim, d.info
    print(f"Tailor {tailor.__version__} demo: {info['garment']} ({info['pieces']} pieces, {info['seams']} seams, "
          f"{info['particles']} particles, {info['triangles']} triangles) on {Path(args.character).name} "
          f"({body.num_vertices} vertices, '{args.action}'), {args.substeps} substeps x {args.iterations} "
          f"iterations, {os.cpu_count()} CPUs; loaded in {load_s:.1f} s")

    states, bodies = [sim.positions.copy()], [body.rest]  # after 0, 1, 2, ... solver steps
    assembly: list[dict] = []
    closed_at = None

    def keep(gap: float) -> int:
        """The state after the step just solved; returns the step's number."""
        nonlocal closed_at
        states.append(sim.positions.copy())
        bodies.append(sim.collider_positions(d.collider))
        if closed_at is None and gap < MET:
            closed_at = len(states) - 1
        return len(states) - 1

    def on_assembly_frame(f: bake.AssemblyFrame) -> None:
        phase, st = PHASES[f.phase], f.stats
        step = keep(float(st["seam_gap_max"]))
        rec = {"step": step, "phase": phase, "ms": f.ms, "ramp": st["ramp_phase"], "contacts": int(st["contacts"]),
               "seam_gap_max_m": float(st["seam_gap_max"])}
        # The last frame at rest: past the minimum, the seams met (or the cap reached).
        last = (f.index == args.blend if phase == "blend" else
                f.index >= args.assemble and (st["ramp_phase"] != "closing" or f.index >= job.preroll_limit()))
        if f.index % 5 == 0 or last or phase == "blend":
            q = bake.frame_record(sim, step, f.ms, False, d.collider)
            rec.update({k: q[k] for k in (*bake.FIELDS, "on_body_fraction", "seams_closing", "nan")})
        if step == 1 or step % 10 == 0 or last:
            print(row(step, phase, rec, st["ramp_phase"]), flush=True)
        assembly.append(rec)

    def on_frame(rec: dict) -> None:
        nonlocal closed_at
        if rec["frame"] > 0:
            step = keep(rec["seam_gap_max_m"])
        else:  # frame 0 is the state after the last assembly step (without one: as placed)
            step = len(states) - 1
            if closed_at is None and rec["seam_gap_max_m"] < MET:
                closed_at = step
        if rec["frame"] in (1, args.frames) or rec["frame"] % 10 == 0 and rec["frame"] > 0:
            print(row(step, "animate", rec, "closing" if rec["seams_closing"] else ""), flush=True)

    job = bake.Bake(sim, [bake.Collider(Path(args.character).name, d.collider, body.num_vertices)], fps=FPS,
                    start=0, preroll=args.assemble, assembly=[body.rest], transition=args.blend, pins=d.pins,
                    on_assembly_frame=on_assembly_frame)
    print(f"frames: {args.assemble} assemble at rest (more while the seams close, up to {job.preroll_limit()}) + "
          f"{args.blend} blend into the {args.action} + {args.frames} {args.action} at {FPS:g} fps")
    print(f"{'step':>5} {'phase':>8} {'ms':>7} {'seam gap mm':>11} {'pen.':>5} {'deepest mm':>10} "
          f"{'strain max':>10} {'ramp':>9}")
    t_sim = time.perf_counter()
    job.run(lambda f: [body.at(f)], args.frames, on_frame=on_frame)
    sim_s = time.perf_counter() - t_sim
    steps = len(states) - 1
    start_step = len(assembly)
    bake.write_pc2_atomic(out / "garment.pc2", np.stack(states), start_frame=0.0)

    action = job.summary()
    rest = [r for r in assembly if r["phase"] == "assemble"]
    phases = {"assemble": phase_summary(rest), "blend": phase_summary([r for r in assembly if r["phase"] == "blend"]),
              "animate": phase_summary(job.records[1:])}  # frame 0's time is the whole assembly's
    solved_ms = [r["ms"] for r in assembly] + [r["ms"] for r in job.records[1:]]
    summary = {**info, "frames": steps, "action_start_step": start_step, "preroll_frames": job.preroll_frames,
               "simulate_s": sim_s, "ms_per_frame_median": float(np.median(solved_ms)) if solved_ms else 0.0,
               "seams_met_at_step": closed_at, "seams_met_below_m": MET, "phases": phases, "action": action,
               **{k: action[k] for k in ("assembled_frames", "on_body_fraction", "centroid_shift_m", "top_shift_m",
                                         "verdict")}}
    report(summary, phases, rest, args, sim_s, steps)

    if not args.no_render:
        t_r = time.perf_counter()
        summary["render"] = render(args, out, d, body, bodies[1:], states[1:], info)
        summary["render"]["seconds"] = time.perf_counter() - t_r
        r = summary["render"]
        print(f"render:   {r['images']} frames {r['size']} (Workbench) in {r['seconds']:.1f} s "
              f"({r['seconds'] / max(r['images'], 1) * 1e3:.0f} ms/frame) -> {out / 'frames'}, "
              f"{out / 'contact_sheet.png'}")
        a = r["animation"]
        print(f"animation: {a['frames']} frames {a['size']}, {a['ms_per_frame']} ms each, "
              f"{a['bytes'] / 1e3:.0f} kB -> {out / a['file']}")
    summary["total_s"] = time.perf_counter() - t_all
    with open(out / "report.json.tmp", "w") as fh:
        json.dump({"summary": summary, "assembly": assembly, "frames": job.records}, fh, indent=1)
    os.replace(out / "report.json.tmp", out / "report.json")
    print(f"total:    {summary['total_s']:.1f} s; wrote {out / 'report.json'}, {out / 'garment.pc2'}")
    nan = any(r.get("nan", False) for r in assembly) or action["nan"]
    return 1 if nan or closed_at is None else 3 if summary["verdict"] else 0


def report(summary: dict, phases: dict, rest: list[dict], args, sim_s: float, steps: int) -> None:
    """The figures in the terminal: timing, assembly, the action, the garment on the body, verdict."""
    import tailor
    from tailor import bake

    a, w = phases["assemble"], phases["animate"]
    print()
    print(f"timing:   {summary['ms_per_frame_median']:.0f} ms/frame median for {summary['particles']} particles "
          f"(assemble {a.get('ms_per_frame_median', float('nan')):.0f}, {args.action} "
          f"{w.get('ms_per_frame_median', float('nan')):.0f}); {steps} frames simulated in {sim_s:.1f} s "
          f"({steps / FPS / sim_s:.2f}x real time)")
    if rest:
        last = rest[-1]  # sampled: the last frame at rest always is
        print(f"assembly: seams met (< {MET * 1e3:g} mm) at step {summary['seams_met_at_step']}; at rest after "
              f"{len(rest)} frames: seam gap {last['seam_gap_max_m'] * 1e3:.3f} mm, penetrations "
              f"{last['penetration_count']} (deepest {last['penetration_max_m'] * 1e3:.2f} mm, thickness "
              f"{summary['thickness_m'] * 1e3:.1f} mm), strain max {last['strain_max']:.3f}")
    else:
        print(f"assembly: none at rest; seams met (< {MET * 1e3:g} mm) at step {summary['seams_met_at_step']}")
    if w:
        print(f"{args.action}:     worst over {w['frames']} frames: seam gap {w['seam_gap_max_m'] * 1e3:.3f} mm, "
              f"penetrations {w['penetration_count']} (deepest {w['penetration_max_m'] * 1e3:.2f} mm), "
              f"strain max {w['strain_max']:.3f}, self-intersections {w['self_intersections']}, NaN: {w['nan']}")
    share, shift = summary["on_body_fraction"], summary["centroid_shift_m"]
    print("on body:  " + (f"at least {share * 100:.0f} % within {tailor.VERDICT_THRESHOLDS['on_body_distance_m'] * 1e2:g} "
                           f"cm of the body, centroid moved at most {shift * 1e2:.1f} cm on it "
                           f"(top {summary['top_shift_m'] * 1e2:.1f} cm) over "
                           f"{summary['assembled_frames']} assembled frames of the {args.action}" if share is not None
                           else "never assembled"))
    print("verdict:  " + ("passes its checks" if not summary["verdict"] else
                          "FAILS: " + "; ".join(bake.verdict_lines(summary))))


def render(args, out: Path, d, body, body_frames, cloth_frames, info) -> dict:
    from demo import render as demo_render

    w, h = (int(x) for x in args.size.lower().split("x"))
    colour = COLOURS.get(info["garment"], COLOURS["tshirt"])
    r = demo_render.Renderer(body.triangles, d.triangles, colour, size=(w, h))
    frames_dir = out / "frames"
    frames_dir.mkdir(exist_ok=True)
    for old in frames_dir.glob("frame_*.png"):
        old.unlink()
    total = len(cloth_frames)
    picked = list(range(args.render_every - 1 if args.render_every > 1 else 0, total, args.render_every))
    if total - 1 not in picked:
        picked.append(total - 1)
    paths = []
    for f in picked:
        r.set(body_frames[f], cloth_frames[f])
        p = frames_dir / f"frame_{f + 1:04d}.png"
        r.render(p)
        paths.append(p)
    # The body alone at the last frame: compared with the last frame, it shows which pixels the
    # garment covers (the test tells an image of the garment from an empty one this way).
    r.set(body_frames[-1], None)
    r.render(out / "body_only.png")
    # Contact sheet: 12 frames spread over the run, assembly included.
    k = min(12, len(paths))
    chosen = [paths[int(round(i * (len(paths) - 1) / max(k - 1, 1)))] for i in range(k)]
    sheet = demo_render.contact_sheet([r.read_png(p) for p in chosen], columns=4 if k >= 4 else k)
    r.write_png(out / "contact_sheet.png", sheet)
    anim = demo_render.animation(paths, out / "animation.gif", fps=FPS / args.render_every,
                                 width=min(w, args.gif_width) if args.gif_width else None)
    return {"images": len(paths), "size": f"{w}x{h}", "frames": [p.name for p in paths],
            "contact_sheet": [p.name for p in chosen], "animation": anim}
