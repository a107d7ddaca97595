"""The headless main job of ``make demo``: a sample garment sewn on the walking character.

    .venv/bin/python demo/run.py [--scene character|sleeve] [--out out/demo] [options]
    .venv/bin/python -m demo ...        (the same, from the repository's root)

Two scenes:

* ``--scene character`` (the default, `demo.character`): a sample garment file
  (sample_blends/skirt.json) assembles on the sample character (sample_blends/character.glb)
  at rest and follows its walk, through `tailor.bake.Bake`; Workbench renders (the `bpy` wheel)
  of every frame, a contact sheet, timings and quality figures go to the output folder.
  ``--no-render`` skips Blender.
* ``--scene sleeve`` (`demo.sleeve`): the module-only demo, a sleeve sewn around a capsule arm.

Why here and not in ``tailor``: the package ``native/python/tailor`` is the wheel that ships
inside the Blender add-on; the demo reads the source checkout's samples and renders with the
`bpy` wheel, neither of which belongs in it. The demo uses only the package's public API
(``tailor.bake``, ``tailor.motion``, and ``tailor.dress.dress`` for the garment
file's setup until that moves into the core).

Errors end as the command line's do: one line on stderr and exit status 2.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SAMPLES = REPO / "sample_blends"


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="demo", description="Sew a sample garment on the walking character headless, "
                                                         "render and report.")
    p.add_argument("--scene", choices=("character", "sleeve"), default="character",
                   help="character: a sample garment on the walking character (default); sleeve: the module-only "
                        "sleeve on a capsule arm")
    p.add_argument("--out", default="out/demo", help="output folder (default out/demo)")
    p.add_argument("--frames", type=int, help="frames of the action (character, default 32: one walk cycle) or in "
                                              "all (sleeve, default 90), at 30 fps")
    p.add_argument("--substeps", type=int, default=8)
    p.add_argument("--iterations", type=int, default=15)
    p.add_argument("--edge", type=float, default=0.015, help="sleeve: mesh edge length, metres")
    p.add_argument("--garment", default=str(SAMPLES / "skirt.json"), help="character: the garment file (default the skirt)")
    p.add_argument("--character", default=str(SAMPLES / "character.glb"), help="character: the glTF character")
    p.add_argument("--action", default="walk", help="character: the animation to play (walk, run)")
    p.add_argument("--assemble", type=int, default=36,
                   help="character: frames to assemble at the rest pose, at least (more while the seams close)")
    p.add_argument("--blend", type=int, default=10, help="character: frames from the rest pose into the action")
    p.add_argument("--no-render", action="store_true", help="character: simulate and report only (no Blender)")
    p.add_argument("--render-every", type=int, default=2, help="character: render every Nth frame (default 2)")
    p.add_argument("--size", default="480x360", help="character: rendered image size, WxH")
    p.add_argument("--gif-width", type=int, default=360,
                   help="character: width of animation.gif in pixels (0: the rendered size; default 360)")
    return p


def run(args) -> int:
    if args.scene == "sleeve":
        from demo import sleeve

        if args.frames is None:
            args.frames = 90
        return sleeve.run(args)
    from demo import character

    if args.frames is None:
        args.frames = 32
    return character.run(args)


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    import tailor

    try:
        return int(run(args) or 0)
    except (tailor.TailorError, OSError) as exc:
        print(f"demo: error: {' '.join(str(exc).split()) or type(exc).__name__}", file=sys.stderr)
    except KeyboardInterrupt:
        print("demo: interrupted", file=sys.stderr)
        return 130
    return 2


if __name__ == "__main__":
    # Run as a script (python demo/run.py): the repository's root, not this folder, goes on the
    # path, so that `demo.render` cannot be shadowed nor shadow anything as plain `render`.
    sys.path[0] = str(REPO)
    sys.exit(main())
