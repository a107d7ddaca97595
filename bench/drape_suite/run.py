"""Assembly on patterns nobody tuned (``make drape-suite``): random GarmentCode designs, imported
and simulated with default settings exactly as a user would, and judged by Tailor's own checks.

    python bench/drape_suite/run.py [--seed 18] [--count 30] [--frames 90] [--edge 0.02]
        [--no-walk] [--arrange] [--out out/drape-suite] [--sampler ../shared/tools/garmentcode/run]
        [--data ../shared/data] [--designs FOLDER]

For each design the sampler writes (shirts, skirts of many kinds, trousers, waistbands and their
combinations, fitted to the GarmentCode mean body), the suite runs
``python -m tailor import SPEC --edge EDGE`` and ``python -m tailor simulate GARMENT --collider
BODY --frames N`` (the body with its legs apart for designs with trousers, as GarmentCode's own
draping does), one fresh process each, and reads the verdict ``tailor simulate`` wrote into its
report (on the body, seams closed, nothing inside the body, no NaN). Then, unless ``--no-walk``,
the walk: ``python demo/run.py --garment GARMENT --no-render`` on the walking sample character
(the same body, rigged): assembled at its rest pose, blended into the walk, one cycle
(`tailor.bake.Bake`'s preroll, transition and frames), judged by the same checks. It prints one line per design and the shares that succeed, and writes
``OUT/summary.json``, ``OUT/table.md`` and a picture of every failure (``OUT/failures/NAME.png``:
the last frame at rest; ``NAME-walk.png``: the walk's first failing frame; front and side).

With ``--arrange`` the designs' own placements are dropped and each is imported with
``--arrange BODY`` (`tailor.arrange`: every piece placed round the body by its name and shape):
the arrangement judged on designs nobody tuned it to.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(HERE))

import picture  # noqa: E402


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--seed", type=int, default=18)
    p.add_argument("--count", type=int, default=30)
    p.add_argument("--frames", type=int, default=90, help="frames at rest on the body (30 fps)")
    p.add_argument("--no-walk", dest="walk", action="store_false", help="skip the walk on the sample character")
    p.add_argument("--arrange", action="store_true",
                   help="drop the designs' placements: import each with --arrange BODY (tailor.arrange)")
    p.add_argument("--edge", type=float, default=0.02)
    p.add_argument("--out", default=str(REPO / "out" / "drape-suite"))
    p.add_argument("--sampler", default=str(REPO.parent / "shared" / "tools" / "garmentcode" / "run"))
    p.add_argument("--data", default=str(REPO.parent / "shared" / "data"))
    p.add_argument("--designs", help="a folder of specifications already sampled (skips the sampler)")
    return p.parse_args(argv)


def sample(args, out: Path) -> tuple[Path, dict]:
    """The designs' folder and their descriptions ({name: {upper, bottom, wb}})."""
    if args.designs:
        folder = Path(args.designs)
    else:
        folder = out / f"designs-{args.seed}-{args.count}"
        if not (folder / "designs.json").exists():
            if not Path(args.sampler).exists():
                sys.exit(f"drape-suite: no sampler at {args.sampler} (the GarmentCode sampler of ../shared/tools)")
            subprocess.run([args.sampler, str(args.seed), str(args.count), str(folder)], check=True,
                           stdout=subprocess.DEVNULL)
    meta = folder / "designs.json"
    kinds = json.loads(meta.read_text()) if meta.exists() else {}
    return folder, kinds


def run_one(name: str, spec: Path, kind: dict, body: Path, args, work: Path) -> dict:
    py = sys.executable
    garment, report, cache = work / f"{name}.json", work / f"{name}.report.json", work / f"{name}.pc2"
    row = {"design": name, "kind": "+".join(v for v in (kind.get("upper"), kind.get("bottom"), kind.get("wb")) if v),
           "body": body.name}
    t0 = time.perf_counter()
    arrange = ["--arrange", str(body)] if args.arrange else []
    imp = subprocess.run([py, "-m", "tailor", "import", str(spec), "--edge", str(args.edge), *arrange, "-o",
                          str(garment)], capture_output=True, text=True)
    if imp.returncode != 0:
        return {**row, "ok": False, "failed": ["import"], "walk_ok": False, "walk_failed": ["import"],
                "error": (imp.stderr or imp.stdout).strip()[-300:]}
    sim = subprocess.run([py, "-m", "tailor", "simulate", str(garment), "--collider", str(body), "--frames",
                          str(args.frames), "--report", str(report), "-o", str(cache)], capture_output=True, text=True)
    row["seconds"] = round(time.perf_counter() - t0, 1)
    row["exit"] = sim.returncode
    if not report.exists():
        return {**row, "ok": False, "failed": ["simulate"], "walk_ok": False, "walk_failed": ["simulate"],
                "error": (sim.stderr or sim.stdout).strip()[-300:]}
    rep = json.loads(report.read_text())
    last = rep["frames"][-1]
    verdict = rep["summary"]["verdict"]  # each failed check with its first frame: [] passes
    row.update(
        ok=not verdict,
        failed=[f"{v['check']}@{v['frame']}" for v in verdict],
        on_body=round(float(last["on_body_fraction"]), 3),
        shift_m=round(float(last["centroid_shift_m"]), 3),
        top_m=round(float(last["top_shift_m"]), 3),
        seam_gap_mm=round(float(last["seam_gap_max_m"]) * 1e3, 2),
        penetration=int(last["penetration_count"]),
    )
    if args.walk:
        demo = work / f"{name}-walk"
        w = subprocess.run([py, str(REPO / "demo" / "run.py"), "--garment", str(garment), "--no-render", "--frames",
                            "32", "--out", str(demo)], capture_output=True, text=True)
        report = demo / "report.json"
        if report.exists():
            ws = json.loads(report.read_text())["summary"]
            row.update(walk_ok=not ws["verdict"], walk_failed=[f"{v['check']}@{v['frame']}" for v in ws["verdict"]],
                       walk_shift_m=round(float(ws["centroid_shift_m"] or 0.0), 3),
                       walk_seam_gap_mm=round(float(ws["phases"]["animate"]["seam_gap_max_m"]) * 1e3, 2))
        else:
            row.update(walk_ok=False, walk_failed=["demo"], walk_error=(w.stderr or w.stdout).strip()[-300:])
        row["seconds"] = round(time.perf_counter() - t0, 1)
    return row


def walk_picture(name: str, row: dict, out: Path) -> None:
    """`failures/NAME-walk.png`: the walk's first failing frame, on the character posed as the
    demo posed it then (frame f of the walk is the demo's cache's step `action_start_step` + f)."""
    import tailor
    from tailor.motion import ColliderMotion

    demo = out / "work" / f"{name}-walk"
    summary = json.loads((demo / "report.json").read_text())["summary"]
    first = min(v["frame"] for v in summary["verdict"])
    walk = ColliderMotion(REPO / "sample_blends" / "character.glb", animation="walk", loop=True)
    cloth = tailor.read_pc2(str(demo / "garment.pc2"))["frames"][summary["action_start_step"] + first]
    picture.garment_on_body(walk.at(first), cloth,
                            f"{name} {row['kind']} walk: {', '.join(row['walk_failed'])}",
                            str(out / "failures" / f"{name}-walk.png"))


def main(argv=None) -> int:
    args = parse_args(argv)
    out = Path(args.out)
    (out / "work").mkdir(parents=True, exist_ok=True)
    (out / "failures").mkdir(exist_ok=True)
    folder, kinds = sample(args, out)
    specs = sorted(folder.glob("*/*_specification.json")) or sorted(folder.glob("*_specification.json"))
    bodies = Path(args.data) / "bodies" / "garmentcode-mean-all"
    import tailor

    rows = []
    for spec in specs:
        name = spec.name.removesuffix("_specification.json")
        kind = kinds.get(name, {})
        body = bodies / ("mean_all_apart.obj" if kind.get("bottom") == "Pants" else "mean_all.obj")
        row = run_one(name, spec, kind, body, args, out / "work")
        rows.append(row)
        cache = out / "work" / f"{name}.pc2"
        if not row["ok"] and cache.exists():
            bv, _ = tailor.read_mesh(str(body))
            last = tailor.read_pc2(str(cache))["frames"][-1]
            picture.garment_on_body(bv, last, f"{name} {row['kind']}: {', '.join(row['failed'])}",
                                    str(out / "failures" / f"{name}.png"))
        if args.walk and not row.get("walk_ok") and row.get("walk_failed") != ["demo"]:
            walk_picture(name, row, out)
        walk = ("" if not args.walk else
                f" | walk {'ok  ' if row.get('walk_ok') else 'FAIL'} {','.join(row.get('walk_failed', [])):12s} "
                f"shift {row.get('walk_shift_m', float('nan')):5.2f} m gap {row.get('walk_seam_gap_mm', float('nan')):6.2f} mm")
        print(f"{name:12s} {row['kind']:34s} rest {'ok  ' if row['ok'] else 'FAIL'} {','.join(row['failed']):12s} "
              f"on body {row.get('on_body', float('nan')):.2f} shift {row.get('shift_m', float('nan')):5.2f} m "
              f"(top {row.get('top_m', float('nan')):5.2f} m) "
              f"gap {row.get('seam_gap_mm', float('nan')):6.2f} mm{walk}  {row.get('seconds', 0):6.1f} s", flush=True)
    ok = sum(r["ok"] for r in rows)
    walk_ok = sum(bool(r.get("walk_ok")) for r in rows) if args.walk else None
    secs = [r["seconds"] for r in rows if "seconds" in r]
    summary = {"seed": args.seed, "count": len(rows), "frames": args.frames, "edge_m": args.edge,
               "arranged": args.arrange,
               "succeeded": ok, "share": ok / max(len(rows), 1), "walk_succeeded": walk_ok,
               "walk_share": None if walk_ok is None else walk_ok / max(len(rows), 1),
               "median_seconds_per_design": float(np.median(secs)) if secs else None, "designs": rows}
    (out / "summary.json").write_text(json.dumps(summary, indent=1))
    lines = ["| design | kind | at rest | on body | centroid shift (m) | top shift (m) | seam gap (mm) | walk | "
             "walk: shift (m), seam gap (mm) | s |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    verdict = lambda ok, failed: "ok" if ok else "fails: " + ", ".join(failed)  # noqa: E731
    for r in rows:
        lines.append(f"| {r['design']} | {r['kind']} | {verdict(r['ok'], r['failed'])} | {r.get('on_body', '')} | "
                     f"{r.get('shift_m', '')} | {r.get('top_m', '')} | {r.get('seam_gap_mm', '')} | "
                     f"{verdict(r.get('walk_ok'), r.get('walk_failed', [])) if args.walk else ''} | "
                     f"{r.get('walk_shift_m', '')}, {r.get('walk_seam_gap_mm', '')} | {r.get('seconds', '')} |")
    (out / "table.md").write_text("\n".join(lines) + "\n")
    walked = "" if walk_ok is None else f"; through the walk {walk_ok} ({100 * summary['walk_share']:.0f} %)"
    how = ", arranged round the body" if args.arrange else ""
    print(f"drape-suite: seed {args.seed}, {len(rows)} designs{how}, {args.frames} frames at rest: {ok} succeed "
          f"({100 * summary['share']:.0f} %){walked}; median {summary['median_seconds_per_design'] or 0:.1f} s per design; "
          f"{out / 'table.md'}, failures' pictures in {out / 'failures'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
