"""The ``tailor`` command line. Each sub-command lives in its own module under ``tailor.commands``
(``import``, ``info``, ``simulate``, ``batch``). The demo of ``make demo`` is not one of them: it lives in the
source tree's ``demo/`` folder, outside the package that ships in the add-on.

Every error ends the same way: one line on standard error, ``tailor COMMAND: error: ...``, and
a non-zero exit status (2; 130 after Ctrl-C), never a traceback. Tailor's own errors say what
and where; an operating-system error (a read-only folder, a full disk) names the path; anything
else is a bug and says so, still on one line.
"""

from __future__ import annotations

import argparse
import sys

#: Exit status of an error (a bad argument, an unreadable file, a failed write).
ERROR = 2
#: Exit status after Ctrl-C (128 + SIGINT), as shells report it.
INTERRUPTED = 130


class _Parser(argparse.ArgumentParser):
    """argparse, but its errors are one line (argparse prints the usage block first)."""

    def error(self, message):
        self.exit(ERROR, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="tailor", description="Tailor garment tools (headless).")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    from tailor.commands import batch, import_, info, simulate

    import_.register(sub)
    info.register(sub)
    simulate.register(sub)
    batch.register(sub)
    return parser


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or type(exc).__name__


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    import tailor

    where = f"tailor {args.command}"
    try:
        return int(args.run(args) or 0)
    except tailor.TailorError as exc:
        print(f"{where}: error: {_one_line(exc)}", file=sys.stderr)
    except OSError as exc:
        print(f"{where}: error: {_one_line(exc)}", file=sys.stderr)
    except KeyboardInterrupt:
        print(f"{where}: interrupted", file=sys.stderr)
        return INTERRUPTED
    except Exception as exc:  # noqa: BLE001 - the command line never shows a traceback
        print(f"{where}: error: internal error (a bug in Tailor, please report it): "
              f"{type(exc).__name__}: {_one_line(exc)}", file=sys.stderr)
    return ERROR


if __name__ == "__main__":
    sys.exit(main())
