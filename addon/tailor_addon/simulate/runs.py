"""The modal operators' runs (the modal bake, Live on its timer), apart from the operators.

A run holds what its operator started: the window manager's timer, the solver on native
threads, the progress bar and status text (bake), the overlay (Live). Every way a run ends goes
through it: finished, Esc (bake), Stop Live, an error, or Blender cancelling the operator
(`Operator.cancel`: a file is opened, Blender quits, the window closes). Keeping it out of the
operator also lets the headless tests drive it (the bpy wheel has no event loop to run modals).

Blender cancels running modal operators while a file is opened, after the old file's data may
already be replaced, so a cancel touches no scene data: the `load_pre` handler (`handlers.py`)
ends every run first (`abandon_all`), while the old file is still there.
"""

from __future__ import annotations

import bpy

from ..core.simulate_live import LiveSolver
from ..ui_common import redraw_view3d
from . import draw, job as bake_job, live

#: The runs in progress (the load_pre handler ends them).
RUNNING: set = set()

#: Seconds between the modal bake's ticks, and Live's. A finished solve waits for the next tick
#: (half a tick on average) with the solver idle: Live's tick is about as short as Blender's
#: event loop goes (it sleeps 5 ms when idle); a tick that finds the solve running only polls
#: it, and the viewport is redrawn only for a new frame. (It was 1/60 s, a display refresh: 8 ms
#: a frame of idle solver on average, a quarter of the T-shirt's frame.)
BAKE_TICK_S = 0.02
LIVE_TICK_S = 0.005


def status(context, text: str | None) -> None:
    ws = getattr(context, "workspace", None)
    if ws is not None:
        ws.status_text_set(text)


class _TimerRun:
    """A run ticked by a window manager timer."""

    def __init__(self, context, interval: float):
        self.timer = context.window_manager.event_timer_add(interval, window=context.window)
        RUNNING.add(self)

    @property
    def running(self) -> bool:
        return self.timer is not None

    def _release(self, context) -> None:
        """Removes the timer (the window manager's, not scene data): safe in `cancel`."""
        if self.timer is not None:
            context.window_manager.event_timer_remove(self.timer)
            self.timer = None
        RUNNING.discard(self)


class BakeRun(_TimerRun):
    """The modal bake: one collider gather per tick, the solve on native threads."""

    def __init__(self, context, job: bake_job.BakeJob):
        self.job = job
        self.solver = LiveSolver(job.run, keep_frames=True)
        self.total = job.end - job.start + 1
        context.window_manager.progress_begin(0, self.total)
        super().__init__(context, BAKE_TICK_S)

    def tick(self, context) -> bool:
        """Takes a finished frame, starts the next; True once every frame is done. Raises the
        solver's or the colliders' error (the caller ends the run, cancelled)."""
        job, solver = self.job, self.solver
        res = solver.poll()
        if res is not None and res.error is not None:
            raise res.error
        if not solver.busy:
            if job.done:
                return True
            job.checkpoint()  # between frames: the solver thread adds none now
            frame = job.run.next_frame
            solver.submit(frame, job.colliders_at(frame))
        done = len(job.run.frames)
        context.window_manager.progress_update(done)
        what = "assembling" if done == 0 else f"frame {job.run.next_frame}"
        status(context, f"Tailor: baking, {what} ({done}/{self.total} done), Esc cancels keeping the frames done")
        return False

    def end(self, context, cancelled: bool) -> str:
        """Done or Esc: the frame in progress is finished and kept, the caches of every frame
        done are written and played (`job.finish`); returns the report."""
        self.solver.stop(timeout=None)
        self._clear_ui(context)
        return bake_job.finish(context.scene, self.job, cancelled)

    def abandon(self) -> None:
        """The file is closing: the solver stops and the frames are dropped (nothing is written
        or attached, so the scene keeps its previous bake, whole); the timeline goes back to the
        start frame, as a finished bake leaves it."""
        if self.job is None:
            return
        self.solver.stop()
        bake_job.JOBS.pop(self.job.key, None)
        scene = bpy.data.scenes.get(self.job.scene_name)
        if scene is not None:
            scene.frame_set(self.job.start)
        self.job = None

    def cancel(self, context) -> None:
        """Blender cancels the operator (file opened, quit, window closed)."""
        self.abandon()  # if the load_pre handler has not already
        self._clear_ui(context)

    def _clear_ui(self, context) -> None:
        if self.timer is not None:
            context.window_manager.progress_end()
            status(context, None)
        self._release(context)


class LiveRun(_TimerRun):
    """Live on its timer: the session (`live.LiveSession`) is ticked, the overlay drawn."""

    def __init__(self, context):
        self.scene_name = context.scene.name
        live.start(context)
        draw.add()
        super().__init__(context, LIVE_TICK_S)

    @property
    def session(self) -> live.LiveSession | None:
        return live.SESSIONS.get(self.scene_name)

    def end(self, context) -> None:
        """Stops the solver, puts the pieces back, removes the overlay and timer."""
        self.abandon()
        self._release(context)
        redraw_view3d(context)

    def abandon(self) -> None:
        """Stops the session, if it still runs (the pieces put back), and removes the overlay
        (no window needed)."""
        if self.scene_name in live.SESSIONS:
            scene = bpy.data.scenes.get(self.scene_name)
            if scene is not None:
                live.stop(scene)
            else:
                live.SESSIONS.pop(self.scene_name).stop(restore=False)
        draw.remove()

    def cancel(self, context) -> None:
        """Blender cancels the operator: Live stops as with Stop Live (if the load_pre handler
        has not already stopped it)."""
        self.abandon()
        self._release(context)


def abandon_all() -> None:
    """Ends every run while the file they ran on is still loaded (the load_pre handler)."""
    for run in list(RUNNING):
        run.abandon()
