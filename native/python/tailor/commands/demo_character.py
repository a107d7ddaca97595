"""``tailor demo`` (scene ``character``): a sample garment on the walking sample character.

Stages: load the garment file and the glTF character; assemble at the rest pose (the seams
close under the damping ramp), blend into the walk, walk (`on_character`); then render every
`--render-every`th frame with Workbench (`demo_render`, the `bpy` wheel) and compose a contact
sheet. Prints per-phase timings (ms/frame, particles), quality figures (seam gap,
penetration, strain, the garment on the body) and the verdict of `tailor.judge` on every
judged frame against the garment as placed (exit status 3 when it fails a check, 1 on NaN or
seams that never met, as ``tailor simulate``); writes into the output folder:

* ``frames/frame_NNNN.png``: the image sequence; ``contact_sheet.png``: a grid of frames;
  ``animation.gif``: the frames as an animated image (played at the simulation's speed);
* ``garment.pc2``: the garment's positions at every simulated frame (Y-up, metres);
* ``report.json``: one record per frame and a summary.
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import numpy as np

MET = 1e-3  # seams count as met below this gap (the sample garments settle at 0.4-1.3 mm at rest)
COLOURS = {"tshirt": (0.10, 0.33, 0.78), "skirt": (0.70, 0.12, 0.22), "trousers": (0.18, 0.22, 0.32),
           "layered": (0.20, 0.45, 0.30)}


def _summary(records: list[dict], phase: str) -> dict:
    rs = [r for r in records if r["phase"] == phase]
    if not rs:
        return {}
    q = [r for r in rs if "seam_gap_m" in r]
    out = {"frames": len(rs), "ms_per_frame_median": float(np.median([r["ms"] for r in rs])),
           "ms_per_frame_max": float(np.max([r["ms"] for r in rs]))}
    if q:
        out.update(
            seam_gap_max_m=max(r["seam_gap_m"] for r in q),
            penetration_count_max=max(r["penetration_count"] for r in q),
            penetration_max_m=max(r["penetration_max_m"] for r in q),
            strain_max=max(r["strain_max"] for r in q),
            strain_mean=float(np.mean([r["strain_mean"] for r in q])),
            nan=any(r["nan"] for r in q),
        )
    return out


def run(args):
    import tailor
    from tailor import bake
    from tailor.commands import on_character

    t_all = time.perf_counter()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    character = on_character.Character(args.character, args.action)
    schedule = on_character.Schedule(args.assemble, args.blend)
    d = on_character.dress(args.garment, character.rest, character.triangles, args.substeps, args.iterations)
    load_s = time.perf_counter() - t0
    sim, info = d.sim, d.info
    total = schedule.assemble + schedule.blend + args.frames
    print(f"Tailor {tailor.__version__} demo: {info['garment']} ({info['pieces']} pieces, {info['seams']} seams, "
          f"{info['particles']} particles, {info['triangles']} triangles) on {Path(args.character).name} "
          f"({len(character.rest)} vertices, '{args.action}'), {args.substeps} substeps x {args.iterations} "
          f"iterations, {os.cpu_count()} CPUs; loaded in {load_s:.1f} s")
    print(f"frames: {schedule.assemble} assemble at rest (more while the seams close) + {schedule.blend} blend into the {args.action} + "
          f"{args.frames} {args.action} = {total} at {schedule.fps:g} fps")
    print(f"{'frame':>5} {'phase':>8} {'ms':>7} {'seam gap mm':>11} {'pen.':>5} {'deepest mm':>10} "
          f"{'strain max':>10} {'ramp':>9}")
    records, cloth_frames, body_frames = [], [], []
    closed_at = None
    start = sim.metrics(d.collider)  # the garment as placed, then as sewn: what frames are judged against
    t_sim = time.perf_counter()
    f = 0
    while f < schedule.assemble + schedule.blend + args.frames:
        phase = schedule.phase(f)
        body = character.at(f, schedule)
        d.move_body(body)
        t0 = time.perf_counter()
        st = d.step(1.0 / schedule.fps)
        ms = (time.perf_counter() - t0) * 1e3
        rec = {"frame": f + 1, "phase": phase, "ms": ms, "ramp": st["ramp_phase"], "contacts": st["contacts"],
               "seam_gap_step_m": float(st["seam_gap_max"])}
        if closed_at is None and st["seam_gap_max"] < MET:
            closed_at = f + 1
        schedule.hold(f, st["ramp_phase"])
        total = schedule.assemble + schedule.blend + args.frames
        last_of_phase = f + 1 == total or schedule.phase(f + 1) != phase
        # Every frame until one is assembled: the first assembled frame is what the rest are
        # judged against (`bake.judged_from`).
        if phase != "assemble" or (f + 1) % 5 == 0 or last_of_phase or start["seams_closing"]:
            m = sim.metrics(d.collider)
            start = bake.judged_from(start, m)
            rec.update(on_character.quality(d, start, m))
        if (f + 1) % 10 == 0 or f == 0 or last_of_phase:
            q = rec if "seam_gap_m" in rec else None
            print(f"{f + 1:5d} {phase:>8} {ms:7.1f} "
                  + (f"{q['seam_gap_m'] * 1e3:11.3f} {q['penetration_count']:5d} {q['penetration_max_m'] * 1e3:10.2f} "
                     f"{q['strain_max']:10.3f}" if q else f"{rec['seam_gap_step_m'] * 1e3:11.3f} {'':>5} {'':>10} {'':>10}")
                  + f" {st['ramp_phase']:>9}", flush=True)
        records.append(rec)
        cloth_frames.append(sim.positions.copy())
        body_frames.append(body)
        f += 1
    sim_s = time.perf_counter() - t_sim
    tailor.write_pc2(out / "garment.pc2", np.stack(cloth_frames), start_frame=1.0, sample_rate=1.0)

    phases = {p: _summary(records, p) for p in ("assemble", "blend", "animate")}
    judged = [r for r in records if "failed" in r]
    summary = {**info, "frames": total, "simulate_s": sim_s, "ms_per_frame_median": float(np.median(
        [r["ms"] for r in records])), "seams_met_at_frame": closed_at, "seams_met_below_m": MET, "phases": phases,
        **bake.on_body_worst(judged), "verdict": bake.verdict_of(judged)}
    a, w = phases["assemble"], phases.get("animate") or {}
    print()
    print(f"timing:   {summary['ms_per_frame_median']:.0f} ms/frame median for {info['particles']} particles "
          f"(assemble {a['ms_per_frame_median']:.0f}, {args.action} {w.get('ms_per_frame_median', float('nan')):.0f}); "
          f"{total} frames simulated in {sim_s:.1f} s ({total / 30.0 / sim_s:.2f}x real time)")
    print(f"assembly: seams met (< {MET * 1e3:g} mm) at frame {closed_at}; at rest after {schedule.assemble} frames: "
          f"seam gap {a['seam_gap_max_m'] * 1e3 if records[schedule.assemble - 1].get('seam_gap_m') is None else records[schedule.assemble - 1]['seam_gap_m'] * 1e3:.3f} mm, "
          f"penetrations {records[schedule.assemble - 1]['penetration_count']} "
          f"(deepest {records[schedule.assemble - 1]['penetration_max_m'] * 1e3:.2f} mm, thickness "
          f"{info['thickness_m'] * 1e3:.1f} mm), strain max {records[schedule.assemble - 1]['strain_max']:.3f}")
    if w:
        print(f"{args.action}:     worst over {w['frames']} frames: seam gap {w['seam_gap_max_m'] * 1e3:.3f} mm, "
              f"penetrations {w['penetration_count_max']} (deepest {w['penetration_max_m'] * 1e3:.2f} mm), "
              f"strain max {w['strain_max']:.3f} (mean {w['strain_mean']:.4f}), NaN: {w['nan']}")
    share, shift = summary["on_body_fraction"], summary["centroid_shift_m"]
    print("on body:  " + (f"at least {share * 100:.0f} % within {tailor.VERDICT_THRESHOLDS['on_body_distance_m'] * 1e2:g} "
                           f"cm of the body, centroid moved at most {shift * 1e2:.1f} cm on it over "
                           f"{summary['assembled_frames']} assembled frames" if share is not None else "never assembled"))
    print("verdict:  " + ("passes its checks" if not summary["verdict"] else
                          "FAILS: " + "; ".join(bake.verdict_lines(summary))))

    if not args.no_render:
        t_r = time.perf_counter()
        summary["render"] = render(args, out, d, character, body_frames, cloth_frames, info)
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
        json.dump({"summary": summary, "frames": records}, fh, indent=1)
    os.replace(out / "report.json.tmp", out / "report.json")
    print(f"total:    {summary['total_s']:.1f} s; wrote {out / 'report.json'}, {out / 'garment.pc2'}")
    last = records[-1]
    ok = not any(r.get("nan", False) for r in records) and closed_at is not None
    return (1 if not ok else 3 if summary["verdict"] else 0)


def render(args, out: Path, d, character, body_frames, cloth_frames, info) -> dict:
    from tailor.commands import demo_render

    w, h = (int(x) for x in args.size.lower().split("x"))
    colour = COLOURS.get(info["garment"], COLOURS["tshirt"])
    r = demo_render.Renderer(character.triangles, d.triangles, colour, size=(w, h))
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
    anim = demo_render.animation(paths, out / "animation.gif", fps=30.0 / args.render_every,
                                 width=min(w, args.gif_width) if args.gif_width else None)
    return {"images": len(paths), "size": f"{w}x{h}", "frames": [p.name for p in paths],
            "contact_sheet": [p.name for p in chosen], "animation": anim}
