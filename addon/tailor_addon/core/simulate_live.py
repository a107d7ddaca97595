"""Live mode's and the modal bake's solver: the solve off Blender's main thread, with no
Python thread of ours.

Bpy-free. The main thread (the modal timer, or `tailor.live_step` in scripts and tests)
`submit`s a frame's collider positions plus any pending edits and goes back to drawing; the
frame's loop (`tailor.bake.Bake.solves`) runs on the main thread up to each solve or
measurement, which is started on a native thread (`Simulation.step_async`, `metrics_async`);
`poll` picks the result up without waiting once it is done and runs the loop on to its next
request or its end, leaving positions and metrics in a one-slot mailbox. So the main thread's
share of a frame is gathering collider arrays, a little bookkeeping and writing positions,
never the solve itself.

Why no worker thread in Python (as this was until 2026-11): in Blender, a second Python thread
holding the GIL while one of Blender's operators runs makes Blender call the C API without the
GIL (with Python 3.11 it reads the *global* current thread state to decide whether it holds
it), and both threads then allocate Python objects at once: Blender crashed, now and then, in
the Live window test (gdb: `PyDict_GetItemString` under `screen.screenshot_area` on the main
thread, `PyUnicode_New` in the worker's `Simulation.step`). Native threads never take the GIL.

Edits are callables `f(sim)` run at the next submission, between frames (the solver is idle
then), which is how stiffness and pin changes apply without a restart.

Live measures a frame's quality (seam gap, penetration, strain: the overlay's figures) at most
every `MEASURE_EVERY_S` seconds, not every frame: the measurement runs on the solver's thread
after the solve and costs about half the T-shirt's solve (17-26 against 33-49 ms at load 4-6:
the body's 47,500 triangles filed again for the penetration test), which every frame paid
though the overlay shows a few a second. The frames solved are the same either way; the modal
bake measures every frame.
"""

from __future__ import annotations

import time
from collections import deque
from dataclasses import dataclass
from functools import partial
from typing import Callable, Sequence

import numpy as np

from tailor import bake

#: Live measures a frame's quality at most this often (seconds); the overlay shows the latest.
MEASURE_EVERY_S = 0.25


@dataclass
class LiveResult:
    frame: int  # the scene frame the colliders were at
    positions: np.ndarray  # (n, 3) world space
    record: dict  # tailor.bake.frame_record fields (unmeasured_record's between Live's measurements)
    solve_ms: float
    error: BaseException | None = None
    fit_maps: dict | None = None  # Simulation.fit_maps of the frame, when asked for (measured frames)


class LiveSolver:
    """Steps `run` (a `tailor.bake.Bake`) one frame per submission, its solves and measurements
    on native threads, everything else on the caller's (main) thread.

    Live keeps only the latest frame and measures a frame's quality every `measure_every_s`
    seconds (`measured` is the latest measured frame's result); with `keep_frames` (the modal
    bake) every frame is measured and stays in `run.frames`, to be read on the main thread once
    the solver is idle or stopped."""

    def __init__(self, run: bake.Bake, keep_frames: bool = False, measure_every_s: float = MEASURE_EVERY_S):
        self.run = run
        self.keep_frames = keep_frames
        self.measure_every_s = 0.0 if keep_frames else measure_every_s
        self._measured_at: float | None = None  # when the latest measured frame was submitted
        self.measured: LiveResult | None = None
        self._frame = 0  # the scene frame in progress
        self._t0 = 0.0
        self._solves: bake.Solves | None = None  # its loop, while in progress
        self._pending = None  # the loop's request running on a native thread (a tailor.Pending)
        self._result: LiveResult | None = None
        self._stopped = False
        self._stamps: deque[float] = deque(maxlen=32)
        #: Live's measured frames also carry their fit maps (the add-on's Fit Map overlay).
        self.fit_maps = False

    @property
    def stopped(self) -> bool:
        """`stop` was called: nothing more is submitted."""
        return self._stopped

    @property
    def busy(self) -> bool:
        """A frame is in progress."""
        return self._solves is not None

    def submit(self, frame: int, collider_positions: Sequence[np.ndarray], edits: Sequence[Callable] = ()) -> bool:
        """Applies `edits` and starts frame `frame`; False (nothing done) while the last one is
        still in progress: the caller tries again on its next tick."""
        if self._stopped:
            raise RuntimeError("the live solver was stopped")
        if self.busy:
            return False
        self._frame, self._t0 = int(frame), time.perf_counter()
        measure = self._measured_at is None or self._t0 - self._measured_at >= self.measure_every_s
        if measure:
            self._measured_at = self._t0
        colliders = [np.array(p, np.float32, copy=True) for p in collider_positions]
        try:
            for edit in edits:
                edit(self.run.sim)
            self._solves = self.run.solves(colliders, measure=measure, fit_maps=measure and self.fit_maps)
        except Exception as exc:  # handed over by the next poll, which reports it and stops
            self._fail(exc)
            return True
        self._advance(partial(next, self._solves))
        return True

    def poll(self) -> LiveResult | None:
        """The latest finished frame, once (None if none finished since the last poll). Never
        waits: a request still running stays so; a finished one moves the frame's loop on."""
        if self._pending is not None and self._pending.done():
            self._collect()
        r, self._result = self._result, None
        return r

    def wait(self, timeout: float | None = None) -> LiveResult | None:
        """Blocks until the submitted frame is solved (scripts and tests; the modal path polls)."""
        self._run_until(timeout)
        r, self._result = self._result, None
        return r

    def fps(self) -> float:
        """Solved frames per wall-clock second over the last 32 frames."""
        s = list(self._stamps)
        if len(s) < 2 or s[-1] <= s[0]:
            return 0.0
        return (len(s) - 1) / (s[-1] - s[0])

    def stop(self, timeout: float | None = 10.0) -> None:
        """No more submissions. A frame in progress is finished (and kept in `run`) if it ends
        within `timeout` seconds (None: however long); else it is left to its native thread,
        which drops the simulation when it ends."""
        self._stopped = True
        self._run_until(timeout)
        if self._pending is not None:
            self._pending = None
            solves, self._solves = self._solves, None
            try:
                # Its clean-ups (the assembly's gravity put back) find the simulation busy on
                # the native thread: said here, not as "Exception ignored" when it is collected.
                solves.close()
            except Exception:
                pass

    # ---- the frame's loop ---------------------------------------------------------------------

    def _run_until(self, timeout: float | None) -> None:
        deadline = None if timeout is None else time.perf_counter() + timeout
        while self._pending is not None:
            left = None if deadline is None else max(0.0, deadline - time.perf_counter())
            if not self._pending.wait(left):
                return
            self._collect()

    def _collect(self) -> None:
        """Hands the finished request's result (or its error) to the frame's loop."""
        pending, self._pending = self._pending, None
        try:
            result = pending.finish()
        except Exception as exc:
            self._advance(partial(self._solves.throw, exc))
        else:
            self._advance(partial(self._solves.send, result))

    def _advance(self, resume: Callable[[], object]) -> None:
        """Runs the frame's loop to its next request, started on a native thread, or its end."""
        try:
            request = resume()
            self._pending = bake.start_async(self.run.sim, request)
        except StopIteration as stop:
            self._done(stop.value)
        except Exception as exc:
            self._fail(exc)

    def _done(self, rec: dict) -> None:
        pos = self.run.frames[-1]
        if not self.keep_frames:  # Live keeps no history: only the latest frame matters
            self.run.frames.clear()
            self.run.records.clear()
            self.run.frames.append(pos)
        self._solves = None
        maps = self.run.fit_maps.get(rec["frame"])
        if not self.keep_frames:
            self.run.fit_maps.clear()
        self._result = LiveResult(self._frame, pos, rec, float(rec["ms"]), fit_maps=maps)
        if rec.get("measured", True):
            self.measured = self._result
        self._stamps.append(time.perf_counter())

    def _fail(self, exc: BaseException) -> None:
        if self._solves is not None:
            try:
                self._solves.close()  # its clean-ups (the assembly's gravity put back)
            except Exception:
                pass  # the error reported is the first one
        self._solves = None
        self._result = LiveResult(self._frame, np.empty((0, 3), np.float32), {},
                                  (time.perf_counter() - self._t0) * 1e3, exc)
