"""Plots and tables of the run-time-against-error benchmark (`make bench-error`).

Reads what `cargo run --example accuracy` wrote (DIR/steps.json, DIR/animations.json) and
writes docs/img/accuracy_<scene>_<particles>.png (error against solver time, log-log, one
column per frozen state, one row per error measure), docs/img/presets.png (quality metrics
against frame time for each quality preset), and the tables between the markers of
docs/accuracy.md. Needs matplotlib, which it installs into the running interpreter's
environment (the repository's .venv) when missing.

    python bench/plot_accuracy.py [DIR]
"""

import importlib.util
import json
import math
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
IMG = ROOT / "docs" / "img"
DOC = ROOT / "docs" / "accuracy.md"
LEVELS = (1e-2, 1e-3, 1e-4)
METHODS = ("jacobi", "gauss_seidel", "chebyshev", "two_level", "reference")
LABEL = {"jacobi": "Jacobi", "gauss_seidel": "Gauss-Seidel", "chebyshev": "GS + Chebyshev",
         "two_level": "GS + Chebyshev, two-level", "reference": "reference"}
COLOUR = {"jacobi": "tab:orange", "gauss_seidel": "tab:blue", "chebyshev": "tab:green", "two_level": "tab:purple",
          "reference": "black"}
MEASURES = (("objective_rel", "relative objective error"), ("residual_rel", "relative residual"),
            ("distance_rel", "distance to reference"))


def pyplot():
    if importlib.util.find_spec("matplotlib") is None:
        subprocess.run([sys.executable, "-m", "pip", "install", "-q", "matplotlib"], check=True)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def records(run, columns):
    return [dict(zip(columns, r)) for r in run["records"]]


def time_to(recs, key, level):
    """Solver seconds of the first recorded iteration at or under `level` (recorded iterations are
    sampled at 20 per decade, so this is at most 12 % late), or None."""
    for r in recs:
        if r[key] <= level:
            return r["seconds"]
    return None


def fmt_ms(t):
    if t is None:
        return "—"
    ms = t * 1e3
    return f"{ms:.0f}" if ms >= 100 else f"{ms:.1f}" if ms >= 1 else f"{ms:.2f}"


def plot_steps(plt, steps):
    groups = {}
    for s in steps:
        groups.setdefault((s["scene"], s["particles"]), []).append(s)
    written = []
    for (scene, n), states in groups.items():
        fig, axes = plt.subplots(3, len(states), figsize=(4.2 * len(states), 9), squeeze=False)
        for c, s in enumerate(states):
            for r, (key, label) in enumerate(MEASURES):
                ax = axes[r][c]
                for run in s["runs"]:
                    recs = records(run, s["columns"])
                    xs = [max(x["seconds"], 1e-6) * 1e3 for x in recs]
                    ys = [max(x[key], 1e-9) for x in recs]
                    ax.loglog(xs, ys, color=COLOUR[run["method"]], label=LABEL[run["method"]], lw=1.4)
                for lv in LEVELS:
                    ax.axhline(lv, color="0.8", lw=0.6, zorder=0)
                ax.set_ylim(1e-7, 3)
                ax.grid(True, which="major", color="0.92")
                if r == 0:
                    ax.set_title(f"{s['state']} (frame {s['frame']})")
                if r == 2:
                    ax.set_xlabel("solver time, ms")
                if c == 0:
                    ax.set_ylabel(label)
        axes[0][0].legend(fontsize=8)
        fig.suptitle(f"{scene}, {n} particles: error against time, one substep")
        fig.tight_layout()
        path = IMG / f"accuracy_{scene}_{n}.png"
        fig.savefig(path, dpi=80)
        plt.close(fig)
        written.append(path)
    return written


def steps_tables(steps):
    out = []
    for key, label in MEASURES:
        out.append(f"**Time to reach {', '.join(f'{l:g}' for l in LEVELS)} in {label}** (ms of solver time; "
                   "— = not reached within the iterations run; the reference includes its factorisation)\n")
        out.append("| scene | particles | state | " + " | ".join(LABEL[m] for m in METHODS) + " |")
        out.append("|---|---:|---|" + "---:|" * len(METHODS))
        for s in steps:
            cells = []
            for m in METHODS:
                run = next((r for r in s["runs"] if r["method"] == m), None)
                if run is None:
                    cells.append("")
                    continue
                recs = records(run, s["columns"])
                cells.append(" / ".join(fmt_ms(time_to(recs, key, lv)) for lv in LEVELS))
            out.append(f"| {s['scene']} | {s['particles']} | {s['state']} | " + " | ".join(cells) + " |")
        out.append("")
    out.append("**Iterations run and where each method ended** (last recorded iteration: objective / residual / "
               "distance; the reference's own relative gradient is the floor of the residual column)\n")
    out.append("| scene | particles | state | " + " | ".join(LABEL[m] for m in METHODS) + " |")
    out.append("|---|---:|---|" + "---:|" * len(METHODS))
    for s in steps:
        cells = []
        for m in METHODS:
            run = next((r for r in s["runs"] if r["method"] == m), None)
            last = records(run, s["columns"])[-1]
            cells.append(f"{last['iteration']} its, {fmt_ms(last['seconds'])} ms: {last['objective_rel']:.0e} / "
                         f"{last['residual_rel']:.0e} / {last['distance_rel']:.0e}")
        out.append(f"| {s['scene']} | {s['particles']} | {s['state']} | " + " | ".join(cells) + " |")
    out.append("")
    return out


def plot_presets(plt, anims):
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    keys = (("seam_gap_max_second_half_m", "seam gap, mm (2nd half, max)", 1e3),
            ("penetration_max_second_half_m", "deepest penetration, mm (2nd half)", 1e3),
            ("strain_max_second_half", "max edge strain (2nd half)", 1.0))
    markers = {"preview": "o", "default": "s", "final": "^"}
    scenes = sorted({(a["scene"], a["particles"]) for a in anims})
    colours = dict(zip(scenes, ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple")))
    for ax, (key, label, scale) in zip(axes, keys):
        for sc in scenes:
            rows = [a for a in anims if (a["scene"], a["particles"]) == sc]
            xs = [a["ms_median"] for a in rows]
            ys = [max(a[key] * scale, 1e-3) for a in rows]
            ax.plot(xs, ys, color=colours[sc], lw=0.8)
            for a, x, y in zip(rows, xs, ys):
                ax.plot(x, y, markers[a["preset"]], color=colours[sc],
                        label=f"{sc[0]} {sc[1]}" if a["preset"] == "preview" else None)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("median ms per frame (o preview, □ default, △ final)")
        ax.set_ylabel(label)
        ax.grid(True, color="0.92")
    axes[0].legend(fontsize=8)
    fig.suptitle("Whole animations: quality against frame time per preset")
    fig.tight_layout()
    path = IMG / "presets.png"
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return path


def presets_table(anims):
    out = ["| scene | particles | preset | substeps × iterations, tolerance | it/substep | ms/frame (median) | fps "
           "| seam gap max, mm | penetrations (deepest, mm) | strain max | strain mean | KE at end, J "
           "| self-intersections |",
           "|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for a in anims:
        last = a["last"]
        out.append(
            f"| {a['scene']} | {a['particles']} | {a['preset']} | {a['substeps']} × {a['iterations']}, "
            f"{a['tolerance']:g} | {a['iterations_per_substep']:.1f} | {a['ms_median']:.1f} | "
            f"{1e3 / a['ms_median']:.1f} | {a['seam_gap_max_second_half_m'] * 1e3:.2f} | "
            f"{a['penetration_count_max_second_half']:.0f} ({a['penetration_max_second_half_m'] * 1e3:.2f}) | "
            f"{a['strain_max_second_half']:.3f} | {last['strain_mean']:.4f} | {last['kinetic_energy_j']:.1e} | "
            f"{last['self_intersections']} |")
    out.append("")
    return out


def replace_between(text, name, body):
    begin, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
    pattern = re.compile(re.escape(begin) + ".*?" + re.escape(end), re.S)
    if not pattern.search(text):
        return text + f"\n{begin}\n{body}\n{end}\n"
    return pattern.sub(lambda _: f"{begin}\n{body}\n{end}", text)


def main():
    data = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "out" / "bench"
    plt = pyplot()
    IMG.mkdir(parents=True, exist_ok=True)
    text = DOC.read_text() if DOC.exists() else "# Accuracy\n"
    steps_file, anim_file = data / "steps.json", data / "animations.json"
    if steps_file.exists():
        doc = json.loads(steps_file.read_text())
        h = doc["header"]
        for p in plot_steps(plt, doc["steps"]):
            print(f"wrote {p.relative_to(ROOT)}")
        body = [f"Command: `{h['command']}` ({h['date_utc']} UTC). Machine: {h['machine']}; at the end: "
                f"{doc['machine_after']}.\n", *steps_tables(doc["steps"])]
        text = replace_between(text, "steps", "\n".join(body))
    if anim_file.exists():
        doc = json.loads(anim_file.read_text())
        h = doc["header"]
        print(f"wrote {plot_presets(plt, doc['animations']).relative_to(ROOT)}")
        body = [f"Command: `{h['command']}` ({h['date_utc']} UTC). Machine: {h['machine']}; at the end: "
                f"{doc['machine_after']}.\n", *presets_table(doc["animations"])]
        text = replace_between(text, "presets", "\n".join(body))
    DOC.write_text(text)
    print(f"wrote {DOC.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
