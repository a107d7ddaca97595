"""Tailor against its peers on the same scenes, side by side in one run (``make bench-peers``).

    python bench/peers/run.py [--scenes sheet-1k,shirt-10k] [--cap 90] [--out out/peers]
        [--peers tailor,blender,newton] [--blender-quality 5,10,20] [--plot docs/img/peers.png]

For each scene (``scenes.py``) the runs of all peers are interleaved (Tailor preview, Blender at
its lowest quality, Newton XPBD, Newton Style3D, Tailor final, Blender at the next quality, ...),
one fresh process each (``run_one.py``), so that the load of the shared machine falls on all of
them alike. Each run reports the median seconds per frame after 5 warm-up frames (wall and CPU
time of the process) and the quality of its last frame by Tailor's metric functions
(``metrics.py``). Then, per scene and peer, the cheapest setting whose quality is equal to or
better than Tailor's preview (``meets``) gives the frame-time ratio. Writes
``OUT/results.json``, ``OUT/results.csv``, ``OUT/table.md`` and ``docs/img/peers.png``.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import platform
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(HERE))

import scenes  # noqa: E402

COMPILED = re.compile(r"took ([0-9.]+) ms\s+\(compiled\)")
PREVIEW = dict(substeps=4, iterations=10)
FINAL = dict(substeps=8, iterations=15)  # `tailor simulate`'s defaults
PEERS = {"tailor", "blender", "newton"}


def plan(scene: str, peers: set[str], blender_quality: list[int] | None = None) -> list[tuple[str, dict]]:
    """The runs of one scene, interleaved across peers (cheapest settings first)."""
    big = scene.endswith("10k")
    sewn = scene.startswith("shirt")
    quality = blender_quality or ((5, 10, 20) if big else (5, 10, 20, 40))
    columns = [
        [("tailor", PREVIEW), ("tailor", FINAL)],
        [("blender", dict(quality=q)) for q in quality],
        [("newton", dict(solver="xpbd", substeps=s, iterations=2)) for s in ((40, 160) if big else (40, 80, 160))],
        [("newton", dict(solver="style3d", substeps=s, iterations=10)) for s in ((4,) if sewn else (4, 8))],
    ]
    columns = [[r for r in c if r[0] in peers] for c in columns]
    out = []
    for i in range(max(map(len, columns))):
        out += [c[i] for c in columns if i < len(c)]
    return out


def label(peer: str, knob: dict) -> str:
    if peer == "tailor":
        name = "preview" if knob == PREVIEW else "final" if knob == FINAL else ""
        return f"Tailor {name} ({knob['substeps']}x{knob['iterations']})".replace(" ()", "")
    if peer == "blender":
        return f"Blender Cloth q{knob['quality']}"
    return f"Newton {knob['solver'].upper() if knob['solver'] == 'xpbd' else 'Style3D'} {knob['substeps']}x{knob['iterations']}"


def meets(q: dict, bar: dict, thickness: float) -> tuple[bool, list[str]]:
    """Whether quality `q` is equal to or better than `bar` (Tailor's preview), and what fails.

    Each metric may be up to 10 % worse than the bar (run-to-run noise of a moving state);
    the seam gap and the penetration depth pass anyway under the issue's own limits (1 mm,
    the thickness)."""
    if q.get("nan", True):
        return False, ["NaN"]
    fails = []
    for key, floor in (("seam_gap_m", 1e-3), ("penetration_max_m", thickness), ("strain_max", 0.0),
                       ("self_intersections", 0)):
        if key in bar and q[key] > max(1.1 * bar[key], floor):
            fails.append(key)
    if "drop_m" in bar and q["drop_m"] < 0.8 * bar["drop_m"]:
        fails.append("drop_m")
    return not fails, fails


def machine() -> dict:
    lscpu = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
    keep = ("Model name", "CPU(s)", "Thread(s) per core", "L2 cache", "L3 cache")
    return dict(lscpu={k.strip(): v.strip() for k, v in (line.split(":", 1) for line in lscpu.splitlines() if ":" in line)
                       if k.strip() in keep},
                python=platform.python_version(), platform=platform.platform())


def loadavg() -> float:
    return float(Path("/proc/loadavg").read_text().split()[0])


def drop(scene: dict, x) -> float:
    """How far the centroid moved along gravity (m): a cloth that did not fall shows here."""
    import numpy as np

    g = scene["gravity"]
    if not np.any(g):
        return 0.0
    d = g / np.linalg.norm(g)
    return float((np.asarray(x, float).mean(0) - scene["positions"].mean(0)) @ d)


def run_scene(name: str, out: Path, cap: float, env: dict, peers: set[str], blender_quality) -> list[dict]:
    import numpy as np

    path = out / "scenes" / f"{name}.npz"
    scene = scenes.build(name)
    scenes.save(scene, path)
    print(f"== {name}: {len(scene['positions'])} particles, {len(scene['triangles'])} triangles, "
          f"{len(scene['seam_a_vertices'])} sewn pairs, body {len(scene['body_triangles'])} triangles, "
          f"{scene['frames']} frames", flush=True)
    records = []
    for i, (peer, knob) in enumerate(plan(name, peers, blender_quality)):
        res = out / "runs" / f"{name}-{i:02d}-{peer}.json"
        res.parent.mkdir(parents=True, exist_ok=True)
        load0 = loadavg()
        p = subprocess.run([sys.executable, str(HERE / "run_one.py"), str(path), peer, json.dumps(knob), str(res),
                            str(cap)], env=env, check=True, stdout=subprocess.PIPE, text=True,
                           stderr=subprocess.DEVNULL if peer == "newton" else None)
        print("\n".join(line for line in p.stdout.splitlines() if not line.startswith(" ")), flush=True)
        rec = json.loads(res.read_text())
        rec.update(label=label(peer, knob), load_before=load0, load_after=loadavg())
        # Warp prints one line per kernel module it compiles (cold cache) or loads (warm).
        rec["warp_compile_s"] = sum(float(m) for m in COMPILED.findall(p.stdout)) / 1e3
        if rec["status"] == "ok" and not rec["quality"].get("nan"):
            rec["quality"]["drop_m"] = drop(scene, np.load(res.with_suffix(".npy")))
        records.append(rec)
    return records


def summarise(name: str, records: list[dict], thickness: float) -> dict:
    """The bar (Tailor preview), each run's verdict and the cheapest passing run per peer."""
    by = {r["label"]: r for r in records}
    pre = next(r for r in records if r["peer"] == "tailor" and r["knob"] == PREVIEW)
    fin = next(r for r in records if r["peer"] == "tailor" and r["knob"] == FINAL)
    bar = {k: v for k, v in pre["quality"].items() if k in ("seam_gap_m", "penetration_max_m", "strain_max",
                                                           "self_intersections")}
    if fin["quality"].get("drop_m", 0) > 0:
        bar["drop_m"] = fin["quality"]["drop_m"]
    for r in records:
        if r["status"] != "ok":
            r["meets"], r["fails"] = False, ["did not run"]
        elif r.get("capped"):
            r["meets"], r["fails"] = False, [f"stopped at the time cap after {r['frames_run']} frames"]
        else:
            r["meets"], r["fails"] = meets(r["quality"], bar, thickness)
    best = {}
    for peer in ("blender", "newton-xpbd", "newton-style3d"):  # (those that ran)
        runs = [r for r in records if (r["peer"] if r["peer"] != "newton" else f"newton-{r['knob']['solver']}") == peer]
        ok = sorted((r for r in runs if r["meets"]), key=lambda r: r["s_per_frame"])
        if not runs:
            continue
        if ok:
            b = ok[0]
            best[peer] = dict(label=b["label"], ratio_wall=b["s_per_frame"] / pre["s_per_frame"],
                              ratio_cpu=b["cpu_s_per_frame"] / pre["cpu_s_per_frame"])
        else:
            best[peer] = dict(label=None, why=sorted({f for r in runs for f in r["fails"]}))
    return dict(scene=name, bar=bar, best=best, labels=list(by))


def write_csv(records: list[dict], path: Path) -> None:
    keys = ["scene", "label", "peer", "particles", "frames_run", "s_per_frame", "cpu_s_per_frame", "setup_s",
            "first_frame_s", "seam_gap_m", "seam_gap_vertex_pairs_m", "penetration_count", "penetration_max_m",
            "strain_max", "strain_mean", "self_intersections", "drop_m", "nan", "meets", "fails", "load_before",
            "version", "status", "error"]
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, keys, extrasaction="ignore")
        w.writeheader()
        for r in records:
            row = {**r, **r.get("quality", {})}
            row["fails"] = ";".join(r.get("fails", []))
            w.writerow(row)


def fmt(v, scale=1.0, digits=1):
    return "–" if v is None else f"{v * scale:.{digits}f}"


def table(records: list[dict], summaries: list[dict]) -> str:
    lines = ["| scene | run | s/frame (wall) | CPU s/frame | × Tailor preview (wall / CPU) | seam gap mm | "
             "penetration mm | strain max | self-int. | drop m | meets preview |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    pre = {}
    for r in records:
        if r["peer"] == "tailor" and r["knob"] == PREVIEW:
            pre[r["scene"]] = r
    for r in records:
        q = r.get("quality", {})
        p = pre[r["scene"]]
        if r["status"] != "ok":
            lines.append(f"| {r['scene']} | {r['label']} | did not run: {r['error'][:90]} |||||||||")
            continue
        ratio = f"{r['s_per_frame'] / p['s_per_frame']:.1f} / {r['cpu_s_per_frame'] / p['cpu_s_per_frame']:.1f}"
        verdict = "yes" if r["meets"] else "no: " + ", ".join(r["fails"])
        if q.get("nan"):
            lines.append(f"| {r['scene']} | {r['label']} | {r['s_per_frame']:.3f} | {r['cpu_s_per_frame']:.3f} | {ratio} "
                         f"| NaN |||||| {verdict} |")
            continue
        gap = q.get("seam_gap_m")
        gap_s = fmt(gap, 1e3, 2) if r["scene"].startswith("shirt") else "–"
        if q.get("seam_gap_vertex_pairs_m") is not None:
            gap_s += f" ({q['seam_gap_vertex_pairs_m'] * 1e3:.2f})"
        lines.append(f"| {r['scene']} | {r['label']} | {r['s_per_frame']:.4f} | {r['cpu_s_per_frame']:.4f} | {ratio} | "
                     f"{gap_s} | {fmt(q.get('penetration_max_m'), 1e3, 1)} | {q['strain_max']:.4f} | "
                     f"{q['self_intersections']} | {q.get('drop_m', 0):.3f} | {verdict} |")
    lines += ["", "| scene | peer | cheapest setting at Tailor preview's quality | frame time ÷ Tailor preview (wall / CPU) |",
              "|---|---|---|---:|"]
    for s in summaries:
        for peer, b in s["best"].items():
            if b["label"]:
                lines.append(f"| {s['scene']} | {peer} | {b['label']} | {b['ratio_wall']:.1f} / {b['ratio_cpu']:.1f} |")
            else:
                lines.append(f"| {s['scene']} | {peer} | none reaches it ({', '.join(b['why'])}) | – |")
    return "\n".join(lines) + "\n"


def plot(records: list[dict], path: Path) -> None:
    """One panel per scene: CPU ms per frame of each run (bars; the wall time as a black tick),
    hatched where the run's quality is worse than Tailor preview's."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    names = list(dict.fromkeys(r["scene"] for r in records))
    fig, axes = plt.subplots(1, len(names), figsize=(4.2 * len(names), 4.8), squeeze=False)
    colours = {"tailor": "tab:blue", "blender": "tab:orange", "xpbd": "tab:green", "style3d": "tab:purple"}
    for ax, name in zip(axes[0], names):
        rs = [r for r in records if r["scene"] == name and r["status"] == "ok" and r.get("s_per_frame")]
        for j, r in enumerate(rs):
            c = colours[r["peer"] if r["peer"] != "newton" else r["knob"]["solver"]]
            ax.bar(j, r["cpu_s_per_frame"] * 1e3, color=c, hatch=None if r["meets"] else "//", edgecolor="black",
                   alpha=1.0 if r["meets"] else 0.55)
            ax.plot(j, r["s_per_frame"] * 1e3, marker="_", color="black", markersize=14)
        ax.set_yscale("log")
        ax.set_xticks(range(len(rs)), [r["label"].replace("Blender Cloth ", "Blender ").replace("Newton ", "")
                                       for r in rs], rotation=70, fontsize=7)
        ax.set_title(f"{name} ({rs[0]['particles']} particles)", fontsize=9)
        ax.set_ylabel("ms per frame (median; bar CPU, tick wall)")
        ax.grid(axis="y", which="both", alpha=0.3)
    handles = [Patch(color=c, label=n) for n, c in (("Tailor", "tab:blue"), ("Blender Cloth", "tab:orange"),
                                                   ("Newton XPBD", "tab:green"), ("Newton Style3D", "tab:purple"))]
    handles.append(Patch(facecolor="white", edgecolor="black", hatch="//", label="worse than Tailor preview"))
    fig.legend(handles=handles, loc="upper right", fontsize=8, ncol=5)
    fig.suptitle("Seconds per frame of each peer and setting, same scenes, one interleaved run", fontsize=10, x=0.25)
    fig.tight_layout(rect=(0, 0, 1, 0.93))
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", default=",".join(scenes.SCENES))
    ap.add_argument("--cap", type=float, default=90.0, help="seconds of stepping per run before it stops")
    ap.add_argument("--peers", default="tailor,blender,newton", help="which peers run (Tailor always sets the bar)")
    ap.add_argument("--blender-quality", type=lambda v: [int(q) for q in v.split(",")],
                    help="Blender's quality steps to run (default 5,10,20 at 10k, 5,10,20,40 at 1k)")
    ap.add_argument("--out", type=Path, default=REPO / "out" / "peers")
    ap.add_argument("--plot", type=Path, default=REPO / "docs" / "img" / "peers.png")
    ap.add_argument("--replot", type=Path, metavar="RESULTS.json", help="only redraw the plot of an earlier run")
    args = ap.parse_args()
    if args.replot:
        plot(json.loads(args.replot.read_text())["runs"], args.plot)
        return 0
    # Tailor's preview run is the bar every other run is judged against: it runs whatever --peers
    # names (leaving it out used to fail in `summarise` after the other peers' runs).
    peers = set(args.peers.split(",")) | {"tailor"}
    unknown = peers - PEERS
    if unknown:
        ap.error(f"--peers: unknown {', '.join(sorted(unknown))} (known: {', '.join(sorted(PEERS))})")
    out = args.out
    out.mkdir(parents=True, exist_ok=True)
    cache = out / "warp-cache"
    shutil.rmtree(cache, ignore_errors=True)  # Newton's first run compiles its kernels: timed as such
    env = dict(os.environ, WARP_CACHE_PATH=str(cache), PYTHONUNBUFFERED="1")
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    info = dict(started=started, command=" ".join([Path(sys.executable).name, *sys.argv]), machine=machine(),
                load_start=Path("/proc/loadavg").read_text().strip(), skipped={})
    records, summaries = [], []
    for name in args.scenes.split(","):
        why = scenes.available(name)
        if why:
            print(f"== {name}: skipped ({why})")
            info["skipped"][name] = why
            continue
        rs = run_scene(name, out, args.cap, env, peers, args.blender_quality)
        s = summarise(name, rs, float(scenes.THICKNESS))
        records += rs
        summaries.append(s)
        (out / "results.json").write_text(json.dumps(dict(info=info, summaries=summaries, runs=records), indent=1))
    info.update(finished=time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
                load_end=Path("/proc/loadavg").read_text().strip())
    (out / "results.json").write_text(json.dumps(dict(info=info, summaries=summaries, runs=records), indent=1))
    write_csv(records, out / "results.csv")
    md = table(records, summaries)
    (out / "table.md").write_text(md)
    if records:
        plot(records, args.plot)
    print(md)
    print(f"machine: {info['machine']['lscpu']}, load {info['load_start']} -> {info['load_end']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
