"""Live mode's solver thread: the solve off Blender's main thread, results picked up later.

Bpy-free. The main thread (the modal timer, or `tailor.live_step` in scripts and tests)
`submit`s a frame's collider positions plus any pending edits and goes back to drawing; a
worker thread applies the edits, steps the `tailor.bake.Bake` (`Simulation.step` releases the
GIL, so Blender's UI keeps running while it solves) and leaves positions and metrics in a
one-slot mailbox that `poll` takes without waiting. So the main thread's share of a frame is
gathering collider arrays and writing positions, never the solve itself.

The simulation is owned by the worker while a job runs: edits are callables `f(sim)` queued
with the next submission and run on the worker between frames, which is how stiffness and
pin changes apply without a restart.
"""

from __future__ import annotations

import threading
import time
from collections import deque
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from tailor import bake


@dataclass
class LiveResult:
    frame: int  # the scene frame the colliders were at
    positions: np.ndarray  # (n, 3) world space
    record: dict  # tailor.bake.frame_record fields
    solve_ms: float
    error: BaseException | None = None


class LiveSolver:
    """One worker thread stepping `run` (a `tailor.bake.Bake`) one frame per submission.

    Live keeps only the latest frame; with `keep_frames` (the modal bake) every frame stays in
    `run.frames`, to be read on the main thread once the worker is idle or stopped."""

    def __init__(self, run: bake.Bake, keep_frames: bool = False):
        self.run = run
        self.keep_frames = keep_frames
        self._lock = threading.Condition()
        self._job: tuple[int, Sequence[np.ndarray], list[Callable]] | None = None
        self._result: LiveResult | None = None
        self._busy = False
        self._stop = False
        self._stamps: deque[float] = deque(maxlen=32)
        self._thread = threading.Thread(target=self._work, name="tailor-live", daemon=True)
        self._thread.start()

    # ---- main thread ------------------------------------------------------------------------

    @property
    def busy(self) -> bool:
        with self._lock:
            return self._busy or self._job is not None

    def submit(self, frame: int, collider_positions: Sequence[np.ndarray], edits: Sequence[Callable] = ()) -> bool:
        """Hands a frame to the worker; False (nothing queued) while it is still solving the
        last one: the caller tries again on its next tick."""
        with self._lock:
            if self._stop:
                raise RuntimeError("the live solver was stopped")
            if self._busy or self._job is not None:
                return False
            self._job = (int(frame), [np.array(p, np.float32, copy=True) for p in collider_positions], list(edits))
            self._lock.notify_all()
            return True

    def poll(self) -> LiveResult | None:
        """The latest finished frame, once (None if none finished since the last poll)."""
        with self._lock:
            r, self._result = self._result, None
            return r

    def wait(self, timeout: float | None = None) -> LiveResult | None:
        """Blocks until the submitted frame is solved (scripts and tests; the modal path polls)."""
        with self._lock:
            self._lock.wait_for(lambda: self._result is not None or self._stop, timeout)
            r, self._result = self._result, None
            return r

    def fps(self) -> float:
        """Solved frames per wall-clock second over the last 32 frames."""
        s = list(self._stamps)
        if len(s) < 2 or s[-1] <= s[0]:
            return 0.0
        return (len(s) - 1) / (s[-1] - s[0])

    def stop(self, timeout: float = 10.0) -> None:
        with self._lock:
            self._stop = True
            self._lock.notify_all()
        self._thread.join(timeout)

    # ---- worker thread ----------------------------------------------------------------------

    def _work(self) -> None:
        while True:
            with self._lock:
                self._lock.wait_for(lambda: self._job is not None or self._stop)
                if self._stop:
                    return
                frame, colliders, edits = self._job
                self._job, self._busy = None, True
            result = self._solve(frame, colliders, edits)
            with self._lock:
                self._busy = False
                self._result = result
                self._stamps.append(time.perf_counter())
                self._lock.notify_all()

    def _solve(self, frame: int, colliders: Sequence[np.ndarray], edits: list[Callable]) -> LiveResult:
        t0 = time.perf_counter()
        try:
            for edit in edits:
                edit(self.run.sim)
            rec = self.run.step(colliders)
            pos = self.run.frames[-1]
            if not self.keep_frames:  # Live keeps no history: only the latest frame matters
                self.run.frames.clear()
                self.run.records.clear()
                self.run.frames.append(pos)
            return LiveResult(frame, pos, rec, (time.perf_counter() - t0) * 1e3)
        except Exception as exc:  # handed to the main thread, which reports it and stops
            return LiveResult(frame, np.empty((0, 3), np.float32), {}, (time.perf_counter() - t0) * 1e3, exc)
