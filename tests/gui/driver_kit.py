"""What every window driver (driver.py, live_driver.py, start_driver.py) shares, inside Blender:
its command line, its result record and checks, and the timer that steps its scenario.

A scenario is a generator that drives the window and yields the seconds to wait before its next
step: Blender's event loop must run between steps (redraws, modal operators, timers), so the
driver cannot simply block. `run` registers a timer that advances it, writes the result JSON when
it ends, fails, or runs past its deadline, and exits Blender without its exit handlers (a clean
quit would run those of a half-driven UI)."""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
import traceback
from pathlib import Path
from typing import Callable, Iterator

import bpy

ROOT = Path(__file__).resolve().parents[2]


def parse_args(result_name: str, add: Callable[[argparse.ArgumentParser], None] | None = None):
    """The driver's arguments after Blender's `--`: `--addon-dir`, `--out`, and the driver's own."""
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("--addon-dir", default=str(ROOT / "addon"), help="folder holding tailor_addon/ (with wheels/)")
    p.add_argument("--out", default=str(ROOT / "out" / "gui"), help=f"screenshots and {result_name}")
    if add is not None:
        add(p)
    return p.parse_args(argv)


class Record:
    """The verdict a driver writes: every check, screenshots, figures, and `ok` once the whole
    scenario ran."""

    def __init__(self, label: str, out: Path, result_name: str):
        self.label, self.out, self.result_name = label, out, result_name
        out.mkdir(parents=True, exist_ok=True)
        self.result: dict = {"checks": [], "screenshots": [], "figures": {}, "ok": False}

    def check(self, what: str, ok: bool, detail="") -> None:
        """Records a check and stops the scenario at the first that fails."""
        self.result["checks"].append({"what": what, "ok": bool(ok), "detail": str(detail)})
        print(f"{self.label} {'PASS' if ok else 'FAIL'}: {what} {detail}", flush=True)
        if not ok:
            raise AssertionError(f"{what}: {detail}")

    def finish(self, code: int, cleanup: Callable[[], None] | None = None) -> None:
        (self.out / self.result_name).write_text(json.dumps(self.result, indent=2))
        if cleanup is not None:
            cleanup()
        print(f"{self.label} RESULT {'OK' if code == 0 else 'FAILED'} ({len(self.result['checks'])} checks) "
              f"-> {self.out}", flush=True)
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)

    def run(self, steps: Iterator[float], deadline_s: float, cleanup: Callable[[], None] | None = None) -> None:
        """Steps `steps` on a Blender timer; at most `deadline_s` seconds in all."""
        deadline = time.monotonic() + deadline_s

        def step():
            try:
                if time.monotonic() > deadline:
                    raise TimeoutError(f"the {self.label} scenario took more than {deadline_s:.0f} s")
                delay = next(steps)
            except StopIteration:
                self.finish(0 if self.result["ok"] else 1, cleanup)
                return None
            except BaseException:
                self.result["error"] = traceback.format_exc()
                print(self.result["error"], flush=True)
                self.finish(1, cleanup)
                return None
            return delay

        bpy.app.timers.register(step, first_interval=0.5)
