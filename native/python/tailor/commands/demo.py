"""``tailor demo``: the headless main job (filled in with the solver)."""


def register(sub):
    p = sub.add_parser("demo", help="drape a sewn two-panel garment headless and print figures")
    p.add_argument("--out", default="out/demo")
    p.set_defaults(run=run)


def run(args):
    print("demo: solver not built yet")
    return 0
