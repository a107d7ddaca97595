"""``tailor demo``: the headless main job (`make demo`).

Two scenes:

* ``--scene character`` (the default, `demo_character`): a sample garment file
  (sample_blends/skirt.json) assembles on the sample character (sample_blends/character.glb)
  at rest and follows its walk; Workbench renders (the `bpy` wheel) of every frame, a contact
  sheet, timings and quality figures go to the output folder. ``--no-render`` skips Blender.
* ``--scene sleeve`` (`demo_sleeve`): the module-only demo, a sleeve sewn around a capsule arm.
"""

from __future__ import annotations

from pathlib import Path

# The repository when running from a checkout (native/python/tailor/commands/demo.py).
REPO = Path(__file__).resolve().parents[4]
SAMPLES = REPO / "sample_blends"


def register(sub):
    p = sub.add_parser("demo", help="sew a sample garment on the walking character headless, render and report")
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
    p.add_argument("--assemble", type=int, default=36, help="character: frames to assemble at the rest pose")
    p.add_argument("--blend", type=int, default=10, help="character: frames from the rest pose into the action")
    p.add_argument("--no-render", action="store_true", help="character: simulate and report only (no Blender)")
    p.add_argument("--render-every", type=int, default=2, help="character: render every Nth frame (default 2)")
    p.add_argument("--size", default="480x360", help="character: rendered image size, WxH")
    p.add_argument("--gif-width", type=int, default=360,
                   help="character: width of animation.gif in pixels (0: the rendered size; default 360)")
    p.set_defaults(run=run)


def run(args):
    if args.scene == "sleeve":
        from tailor.commands import demo_sleeve

        if args.frames is None:
            args.frames = 90
        return demo_sleeve.run(args)
    from tailor.commands import demo_character

    if args.frames is None:
        args.frames = 32
    return demo_character.run(args)
