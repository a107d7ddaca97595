"""The ``tailor`` command line. Each sub-command lives in its own module under ``tailor.commands``."""

from __future__ import annotations

import argparse
import sys


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="tailor", description="Tailor garment tools (headless).")
    sub = parser.add_subparsers(dest="command", required=True)
    from tailor.commands import demo, import_, info, simulate

    demo.register(sub)
    import_.register(sub)
    info.register(sub)
    simulate.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    import tailor

    try:
        return int(args.run(args) or 0)
    except tailor.TailorError as exc:
        print(f"tailor {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
