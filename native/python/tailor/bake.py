"""The frame loop of a garment-on-collider simulation, shared by every driver.

A bake is: for each frame, the colliders' vertex positions in, one solver frame, the garment's
positions and quality metrics out. The command line (``tailor simulate``), the Blender add-on's
Bake and Live modes, the demo (``demo/`` in the source tree) and pipeline scripts all run this
loop; they differ only in where collider positions come from (a mesh, a PC2 cache or a glTF skin
through ``tailor.motion.ColliderMotion``; Blender's evaluated meshes) and where positions go (a
PC2 file, Blender meshes). The frames a bake solves before its start frame (the assembly at a
rest pose and the move from it) are not recorded; a driver that reports them (the demo's
timings per phase) gets each through ``Bake.on_assembly_frame``.

``Bake`` keeps every frame it has solved, so a cancelled bake keeps its frames and ``run`` can
resume where it stopped: the solver state lives on in the same ``Bake`` object, which makes a
resumed bake bit-for-bit the same as an uninterrupted one (the solver is deterministic). When
that object is gone (a new session), ``Bake.replay`` rebuilds the state by re-solving the
frames already cached and checks that they come out identical before going on.

Painted pins can ride on the character (``ColliderPins``): they are attached to a collider
(``Simulation.attach_to_collider``) after the first frame whose seam-closing ramp is no longer
"closing", not from the start, because pins held from the first frame would hold the seams
open; from then on each rides on its bound point of the collider as the body moves.

No Blender, no threads here. The frame's loop is a generator (``Bake.solves``) that yields each
solve and measurement it needs (``Solve``, ``Measure``) and is sent back the result: ``step``
runs it with ``Simulation.step`` and ``metrics`` on the calling thread; a host whose main thread
must stay free and which must not run Python on a second thread (Blender: see the add-on's
``core/simulate_live.py``) runs the same generator with ``Simulation.step_async`` and
``metrics_async``, which compute on a native thread, and collects each result when it is done.
Either way the Python between the calls runs on the caller's thread and the frames are the same.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field
from typing import Callable, Generator, Sequence

import numpy as np

from tailor._tailor import (VERDICT_THRESHOLDS, CancelledError, InvalidParameterError, SimulationError, Simulation,
                            check_playback, judge, judge_unfinished, write_pc2)

#: Quality fields of a frame record, each worst-case (largest) over frames in a summary.
#: The assembly's defaults, the add-on's and ``tailor simulate``'s alike: at least this many
#: frames at the rest pose before the start frame (more while the seams close), then this many
#: frames moving the colliders from it into the start frame's pose, without gravity while the
#: seams close at rest (open seams have nothing to hang on).
DEFAULT_PREROLL = 60
DEFAULT_TRANSITION = 40
ASSEMBLY_GRAVITY = (0.0, 0.0, 0.0)

#: The longest an assembly at the rest pose may go on while its seams are still closing, seconds
#: (a safety net: the ramp ends its closing phase by itself when the seams meet or stall).
ASSEMBLY_MAX_S = 10.0

FIELDS = ("seam_gap_max_m", "penetration_count", "penetration_max_m", "self_intersections", "strain_max")


def judged_from(reference: dict | None, metrics: dict) -> dict:
    """The frame a run's frames are judged against (`tailor.judge`'s `start`), given the one so
    far (`reference`, None before the first frame) and this frame's `Simulation.metrics`: the
    run's first frame until a frame is assembled, then the first assembled frame (its seams no
    longer closing) for good. While seams close the pieces travel to meet by design (a skirt
    placed 50 cm below the shirt it is sewn to comes up 17 cm with the body holding the shirt):
    that is assembly, not a fall. From the garment as sewn, a fall or a slide off a shoulder
    is measured however late it comes; one that leaves the body while it assembles is caught
    by the on-body share."""
    if reference is None or (reference["seams_closing"] and not metrics["seams_closing"]):
        return metrics
    return reference


def frame_record(sim: Simulation, frame: int, ms: float, nan: bool, collider: int | None = None,
                 start: dict | None = None, metrics: dict | None = None) -> dict:
    """The quality of the simulation's current state as one report record, judged against
    `start` (the `Simulation.metrics` of the run's first frame; this frame itself when None) by
    `tailor.judge`: `on_body_fraction` (share of the particles within 10 cm of `collider`, None
    without one), `centroid_shift_m` and `top_shift_m` (how far the garment's centroid and its
    top, where it hangs from, moved on the body since `start`, which callers keep with
    `judged_from`), `seams_closing` (still assembling) and `failed` (the checks it fails, each
    {"check", "reason"}). `metrics` is `sim.metrics(collider)` when the caller already has it."""
    m = sim.metrics(collider) if metrics is None else metrics
    nan = bool(nan or not np.isfinite(sim.positions).all())
    verdict = judge(m, start, nan)
    return {
        "frame": int(frame),
        "ms": float(ms),
        "seam_gap_max_m": float(m["seam_gap"]),
        "penetration_count": int(m["penetration_count"]),
        "penetration_max_m": float(m["penetration_max_depth"]),
        "self_intersections": int(m["self_intersections"]),
        "strain_max": float(m["strain_max"]),
        "on_body_fraction": None if m["on_body_fraction"] is None else float(m["on_body_fraction"]),
        "centroid_shift_m": float(verdict["centroid_shift_m"]),
        "top_shift_m": float(verdict["top_shift_m"]),
        "seams_closing": bool(m["seams_closing"]),
        "nan": nan,
        "failed": verdict["failed"],
    }


def unmeasured_record(frame: int, ms: float, positions: np.ndarray) -> dict:
    """The record of a frame solved without its quality measured (`Bake.solves(measure=False)`):
    its number, time and whether a position is not finite, `measured` False; no quality
    fields, no verdict."""
    return {"frame": int(frame), "ms": float(ms), "nan": not bool(np.isfinite(positions).all()), "measured": False,
            "failed": []}


def stage_ms(stats: dict) -> dict:
    """Where a solved frame's time went, in ms, from its `Simulation.step` statistics: the
    solver's stages (`prediction`, `local`, `global`, `damping`, `total`) and the collision
    work inside them (`hash`: placing the colliders and filing their hashes, `contacts`: the
    iterations' particle-vs-mesh tests, `self`: self-collision, `resolve`: the end of each
    substep). The quality metrics are outside them (the record's `ms` includes them)."""
    out = {k: 1e3 * float(v) for k, v in stats.get("timings", {}).items()}
    col = stats.get("collision", {})
    for name, key in (("hash", "hash_seconds"), ("contacts", "contact_seconds"),
                      ("self", "self_seconds"), ("resolve", "resolve_seconds")):
        if key in col:
            out[name] = 1e3 * float(col[key])
    return out


def summarize(records: Sequence[dict]) -> dict:
    """Worst case of every quality field over `records` (the largest of `FIELDS`), the mean
    frame time, any NaN, and the garment on the body over the frames `tailor.judge` judges it
    on, the assembled ones (`assembled_frames` of them): the smallest `on_body_fraction` and the
    largest `centroid_shift_m` and `top_shift_m` (None when no frame is assembled or there is no collider); `ms`
    is the mean over the frames that were a step (not the start frame's, which holds the whole
    assembly, unless it is the only record). And the
    `verdict`: each check that some record failed (in `judge`'s order) with the first frame that
    failed it and that frame's reason, [] when every frame passed. `backends`: how many frames
    each backend solved (records of `Bake.step` carry `backend` and `backend_warning`)."""
    if not records:
        return {"frame": 0, "ms": 0.0, "nan": False, **{k: 0 for k in FIELDS}, "assembled_frames": 0,
                "on_body_fraction": None, "centroid_shift_m": None, "top_shift_m": None, "verdict": [],
                "backends": {}}
    s = {k: max(r[k] for r in records) for k in FIELDS}
    # The frame time of the steps: the start frame's time is the whole assembly's (its preroll
    # and transition, tens of frames), not a frame's.
    stepped = [r["ms"] for r in records if not r.get("start")] or [r["ms"] for r in records]
    s.update(frame=len(records), ms=float(np.mean(stepped)), nan=any(r["nan"] for r in records))
    s.update(on_body_worst(records), verdict=verdict_of(records))
    # Frames per backend that solved them ({"cpu": 40, "gpu": 20}), where the records say.
    backends: dict[str, int] = {}
    for r in records:
        if r.get("backend"):
            backends[r["backend"]] = backends.get(r["backend"], 0) + 1
    s["backends"] = backends
    return s


def on_body_worst(records: Sequence[dict]) -> dict:
    """Over the assembled records (`seams_closing` false: those `tailor.judge` judges on the body):
    how many, the smallest `on_body_fraction` and the largest `centroid_shift_m` and `top_shift_m`
    (None when none is assembled or there is no collider; records written before the top was
    measured count by their centroid's)."""
    judged = [r for r in records if not r.get("seams_closing", False)]
    shares = [r["on_body_fraction"] for r in judged if r.get("on_body_fraction") is not None]
    return {"assembled_frames": len(judged), "on_body_fraction": min(shares) if shares else None,
            "centroid_shift_m": max(r["centroid_shift_m"] for r in judged) if judged else None,
            "top_shift_m": max(r.get("top_shift_m", r["centroid_shift_m"]) for r in judged) if judged else None}


def verdict_of(records: Sequence[dict]) -> list[dict]:
    """Each check some record failed (its `failed`, from `tailor.judge`), in `judge`'s order, with
    the first frame that failed it and that frame's reason: {"check", "frame", "reason"}; and
    "open" when the last record still had seams closing (`tailor.judge_unfinished`: the run
    ended before the garment was assembled)."""
    first: dict[str, dict] = {}
    for r in records:
        for f in r.get("failed", ()):
            first.setdefault(f["check"], {"check": f["check"], "frame": r["frame"], "reason": f["reason"]})
    if records:
        last = records[-1]
        gap = last.get("seam_gap_max_m", 0.0)
        f = judge_unfinished(bool(last.get("seams_closing", False)), float(gap))
        if f is not None:
            first.setdefault(f["check"], {"check": f["check"], "frame": last["frame"], "reason": f["reason"]})
    return [first[c] for c in VERDICT_THRESHOLDS["checks"] if c in first]


def verdict_lines(summary: dict) -> list[str]:
    """One line per failed check of a summary's verdict: "fell from frame 12: <reason>"."""
    return [f"{v['check']} from frame {v['frame']}: {v['reason']}" for v in summary.get("verdict", ())]


def summary_text(summary: dict) -> str:
    """A summary in one line for people (the add-on's Last Bake): frames, time, the worst
    quality figures, the garment on the body, and the verdict ("passes its checks", or each
    failed check with its first frame)."""
    s = summary
    share, shift, top = s.get("on_body_fraction"), s.get("centroid_shift_m"), s.get("top_shift_m")
    if not s.get("assembled_frames"):
        on_body = ", still assembling"
    else:
        on_body = (f", on body min {share * 100:.0f} %" if share is not None else "") + \
            f", centroid moved max {shift * 1e2:.1f} cm" + (f", top {top * 1e2:.1f} cm" if top is not None else "")
    failed = [f"{v['check']} (frame {v['frame']})" for v in s.get("verdict", ())]
    return (f"{s['frame']} frames, {s['ms']:.0f} ms/frame, seam gap max {s['seam_gap_max_m'] * 1e3:.2f} mm, "
            f"penetration max {s['penetration_max_m'] * 1e3:.2f} mm, strain max {s['strain_max']:.3f}{on_body}"
            + (", NaN" if s["nan"] else "")
            + (f"; FAILS: {', '.join(failed)}" if failed else "; passes its checks"))


def write_pc2_atomic(path: str | os.PathLike, frames: np.ndarray, start_frame: float, sample_rate: float = 1.0) -> None:
    """Writes a PC2 cache to a temporary file beside `path`, then renames it over `path`: a
    reader (Blender's Mesh Cache modifier, another DCC) sees the old cache or the new one,
    never half a file."""
    path = os.fspath(path)
    tmp = f"{path}.partial{os.getpid()}.pc2"
    try:
        write_pc2(tmp, np.ascontiguousarray(frames, np.float32), start_frame=float(start_frame),
                  sample_rate=float(sample_rate))
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def check_collider_positions(name: str, positions: np.ndarray, count: int) -> np.ndarray:
    """(count, 3) float32 positions of collider `name`, or InvalidParameterError naming the
    collider and its first bad vertex (before anything is handed to the solver)."""
    p = np.ascontiguousarray(positions, np.float32).reshape(-1, 3)
    if len(p) != count:
        raise InvalidParameterError(f"collider '{name}' has {len(p)} vertices now but {count} when the bake started "
                                    "(its topology must not change over the frame range)")
    if np.isfinite(p).all():  # the usual case, 100 times cheaper than finding the rows (0.6 ms on a body)
        return p
    bad = np.flatnonzero(~np.isfinite(p).all(axis=1))
    if len(bad):
        raise InvalidParameterError(f"collider '{name}': vertex {int(bad[0])} is not finite ({p[bad[0]].tolist()}), "
                                    f"{len(bad)} such vertices")
    return p


@dataclass
class Collider:
    """A mesh collider of the bake: its name (for messages), its id in the simulation."""

    name: str
    id: int
    num_vertices: int


@dataclass
class ColliderPins:
    """Pinned particles that ride on mesh collider `collider` once the seams have met: each
    group of particles is attached with its stiffness (N/m per particle) by `attach`, which
    `Bake` calls through `after_frame` once every seam has met (see there)."""

    collider: int
    groups: list[tuple[np.ndarray, float]]
    attached: bool = False

    @property
    def particles(self) -> np.ndarray:
        """Every particle of the groups."""
        if not self.groups:
            return np.zeros(0, np.int64)
        return np.concatenate([np.asarray(p, np.int64) for p, _ in self.groups])

    def attach(self, sim: Simulation) -> None:
        for particles, stiffness in self.groups:
            if len(particles):
                sim.attach_to_collider(np.asarray(particles, np.int64), self.collider, float(stiffness))
        self.attached = True

    def after_frame(self, sim: Simulation, ramp_phase: str) -> bool:
        """Attaches the pins after the first frame at which every seam has met: the ramp phase
        is no longer "closing" (most pairs have met) and the widest pair is within the ramp's
        gap threshold; or, whatever the widest pair, once the ramp's release is over ("done"),
        so that a seam that never closes does not leave the garment unpinned. Returns whether
        they are attached.

        Not at the ramp's release alone: it comes when most pairs (`ramp_closed_fraction`) have
        met, and a short seam still open then (the layered sample's hoody's shoulder seams,
        9 cm apart) would close against pins already holding both its sides to the body: it
        stayed 1.2 mm open for good (0.9 mm when the pins waited for it)."""
        if not self.attached and ramp_phase != "closing":
            if ramp_phase == "done" or sim.seam_gaps()[0] <= sim.settings.ramp_gap_threshold:
                self.attach(sim)
        return self.attached

    def replace(self, sim: Simulation, groups: list[tuple[np.ndarray, float]]) -> None:
        """New groups (the pin map was repainted): attached at once, where the particles are
        now, if the old ones were already attached; else when the seams meet."""
        if self.attached:
            sim.detach_from_collider()
        self.groups = groups
        if self.attached:
            self.attach(sim)


@dataclass(frozen=True)
class Solve:
    """A request of `Bake.solves`: `frames` solver frames of `dt` seconds; it is sent back the
    last frame's `Simulation.step` statistics (with `wall_s`, the seconds the solve took), and
    with `measure` the state's `Simulation.metrics(collider)` after them as `metrics` (so that
    a driver on another thread makes one trip for a frame, not two)."""

    dt: float
    frames: int = 1
    measure: bool = False
    collider: int | None = None


@dataclass(frozen=True)
class Measure:
    """A request of `Bake.solves`: the current state's `Simulation.metrics(collider)`, sent back."""

    collider: int | None


@dataclass(frozen=True)
class MapFit:
    """A request of `Bake.solves` (with `fit_maps`): the current state's
    `Simulation.fit_maps(collider)`, sent back."""

    collider: int | None


#: What `Bake.solves` yields, is sent and returns.
Solves = Generator["Solve | Measure | MapFit", dict, dict]


def run_here(sim: Simulation, request: Solve | Measure | MapFit) -> dict:
    """A request of `Bake.solves` computed on this thread."""
    if isinstance(request, Solve):
        stats = sim.step(request.dt, request.frames)
        if request.measure:
            stats["metrics"] = sim.metrics(request.collider)
        return stats
    if isinstance(request, MapFit):
        return sim.fit_maps(request.collider)
    return sim.metrics(request.collider)


def start_async(sim: Simulation, request: Solve | Measure):
    """A request of `Bake.solves` started on a native thread: a `tailor.Pending`."""
    if isinstance(request, Solve):
        return sim.step_async(request.dt, request.frames, measure=request.measure, collider=request.collider)
    if isinstance(request, MapFit):
        return sim.fit_maps_async(request.collider)
    return sim.metrics_async(request.collider)


def drive(solves: Solves, sim: Simulation,
          run: Callable[[Simulation, Solve | Measure], dict] = run_here) -> dict:
    """Runs a `Bake.solves` generator to its end, each request computed by `run` (on this
    thread: `run_here`); returns its value. An error of a request is raised inside the
    generator (its clean-ups run) and out of here."""
    try:
        request = next(solves)
        while True:
            try:
                result = run(sim, request)
            except Exception as exc:
                request = solves.throw(exc)
            else:
                request = solves.send(result)
    except StopIteration as stop:
        return stop.value


class _Clock:
    """A frame's solve time as `step` measured it, however a driver runs the requests: the
    loop's own work plus each solve's wall time (`wall_s`) and each measurement's time,
    without the time a driver took to send the results back (a timer tick, in Blender)."""

    def __init__(self) -> None:
        self.s = 0.0
        self.mark = time.perf_counter()

    def request(self, request: Solve | Measure) -> Generator[Solve | Measure, dict, dict]:
        self.s += time.perf_counter() - self.mark
        sent = time.perf_counter()
        result = yield request
        back = time.perf_counter()
        # A solve's own wall time; a measurement is counted as the round trip (it is not timed).
        self.s += result.get("wall_s", back - sent) if isinstance(request, Solve) else back - sent
        self.mark = back
        return result

    def ms(self) -> float:
        return (self.s + time.perf_counter() - self.mark) * 1e3


@dataclass
class AssemblyFrame:
    """A solver frame of a bake's assembly, before its start frame (`Bake.on_assembly_frame`):
    `phase` "preroll" (at the assembly pose) or "transition" (moving to the start frame's),
    `index` (1-based within the phase), `ms` (the solve's wall time), `stats` (its
    `Simulation.step` statistics: `ramp_phase`, `seam_gap_max`, `contacts`, ...) and the collider
    positions it was solved with (one array per collider)."""

    phase: str
    index: int
    ms: float
    stats: dict
    colliders: Sequence[np.ndarray]


@dataclass
class Bake:
    """A running bake: `sim` with its mesh `colliders`, one frame per `step`.

    Frame `start` is the garment as given (no step); each following frame is one step of
    `1/fps` seconds with the colliders at that frame. Before frame `start` is recorded, the
    garment assembles: `preroll` steps with the colliders at `assembly` (a pose the pattern is
    placed for, typically the rest pose; the start frame's positions when None), more while the
    seams are still closing (up to `preroll_limit()`), then
    `transition` steps moving them from `assembly` to the start frame's positions along a
    smoothstep (3t² - 2t³: the body starts and ends the move at rest, no jolt at either end for
    the cloth's contacts).
    With `assembly_gravity` set (typically zero) the preroll runs under that gravity: a garment
    whose seams are still open has nothing to hang on and would fall off the body while they
    close. `pins` (optional) are attached to their collider after the first solver frame,
    preroll included, at which every seam has met (`ColliderPins.after_frame`). `frames[i]` and
    `records[i]` are frame `start + i`."""

    sim: Simulation
    colliders: list[Collider]
    fps: float
    start: int
    preroll: int = 0
    assembly: Sequence[np.ndarray] | None = None
    transition: int = 0
    assembly_gravity: tuple[float, float, float] | None = None
    frames: list[np.ndarray] = field(default_factory=list)
    records: list[dict] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    prerolled: bool = False
    pins: ColliderPins | None = None
    #: What every record is judged against (`judged_from`): the `Simulation.metrics` of frame
    #: `start`, or of the first assembled frame after it.
    start_metrics: dict | None = None
    #: The preroll goes on past `preroll` frames while the seams are still closing, up to this
    #: many frames in all (None: `ASSEMBLY_MAX_S` seconds); `preroll_frames` is how many ran.
    preroll_max: int | None = None
    preroll_frames: int = 0
    #: Called after every preroll and transition frame (they are not recorded) with an
    #: `AssemblyFrame`: for drivers that report the assembly (the demo's timings per phase).
    #: The frames solved are the same with it or without.
    on_assembly_frame: Callable[[AssemblyFrame], None] | None = None
    #: Every recorded frame's fit maps too (`Simulation.fit_maps` on the metrics collider, the
    #: add-on's bake with a Fit Map chosen), kept by frame in `fit_maps` (not in the records,
    #: which stay JSON).
    keep_fit_maps: bool = False
    fit_maps: dict[int, dict] = field(default_factory=dict)

    def __post_init__(self) -> None:
        # A NaN or zero rate would reach the solver as a NaN or infinite time step.
        check_playback(self.fps)

    @property
    def next_frame(self) -> int:
        return self.start + len(self.frames)

    @property
    def metrics_collider(self) -> int | None:
        return self.colliders[0].id if self.colliders else None

    def _set_colliders(self, positions: Sequence[np.ndarray]) -> None:
        if len(positions) != len(self.colliders):
            raise InvalidParameterError(f"{len(positions)} collider position arrays for {len(self.colliders)} colliders")
        checked = [check_collider_positions(c.name, p, c.num_vertices) for c, p in zip(self.colliders, positions)]
        for c, p in zip(self.colliders, checked):
            self.sim.set_collider_positions(c.id, p)

    def step(self, collider_positions: Sequence[np.ndarray]) -> dict:
        """Solves frame `next_frame` with the colliders at `collider_positions` (one (n, 3)
        array per collider, world space) and records it. The first call runs the preroll and
        records the start frame. Raises `InvalidParameterError` (bad collider) or
        `SimulationError` (the solve diverged; the simulation is rolled back) and records
        nothing in that case."""
        return drive(self.solves(collider_positions), self.sim)

    def solves(self, collider_positions: Sequence[np.ndarray], measure: bool = True,
               fit_maps: bool = False) -> Solves:
        """`step` as a generator of the solves and measurements it needs (`Solve`, `Measure`),
        each sent back its result (`drive` runs it on this thread); returns the record.

        With `measure` False the frame's quality is not measured (Live, between the frames
        its overlay shows: the measurement costs about half the T-shirt's solve):
        the frame is solved the same, and its record (`unmeasured_record`) has no quality
        fields and judges nothing. The start frame is measured regardless (every later frame
        is judged from it)."""
        clock = _Clock()
        stats = None
        if not self.frames:
            if not self.prerolled:
                yield from self._assemble(collider_positions, clock)
            self._set_colliders(collider_positions)
        else:
            self._set_colliders(collider_positions)
            stats = yield from self._solve(clock, 1.0 / self.fps, measure=measure)
        ms = clock.ms()
        pos = self.sim.positions
        m = None if stats is None else stats.get("metrics")
        if m is None and (measure or stats is None):  # the start frame, or the pins attached after the frame's last solve
            m = yield from clock.request(Measure(self.metrics_collider))
        if m is None:
            rec = unmeasured_record(self.next_frame, ms, pos)
        else:
            self.start_metrics = judged_from(self.start_metrics, m)
            rec = frame_record(self.sim, self.next_frame, ms, False, self.metrics_collider, self.start_metrics, m)
        # Which backend solved the frame, and why the CPU did when the GPU was asked for (None:
        # the start frame, solved by no step of its own).
        rec["start"] = stats is None  # the start frame: the assembly's end, or the garment as given
        rec["backend"] = None if stats is None else stats.get("backend")
        rec["backend_warning"] = None if stats is None else stats.get("warning")
        rec["stages_ms"] = None if stats is None else stage_ms(stats)
        # How far the particles resting on a body moved this frame (median): on a still body,
        # the drape's jitter at rest.
        rec["contact_motion_m"] = None if stats is None else stats.get("contact_motion_m")
        if fit_maps or self.keep_fit_maps:
            self.fit_maps[rec["frame"]] = yield MapFit(self.metrics_collider)
        self.frames.append(pos)
        self.records.append(rec)
        return rec

    def record_failure(self) -> dict:
        """Records frame `next_frame` as failed, after `step` raised `SimulationError` for it (the
        solver rolled back): the positions as they are, a record with `nan` set and no time,
        judged against `start_metrics` (which it does not move on). Returns the record; the next
        `step` goes on from there (``tailor simulate`` keeps every frame this way)."""
        rec = frame_record(self.sim, self.next_frame, 0.0, True, self.metrics_collider, self.start_metrics)
        self.frames.append(self.sim.positions)
        self.records.append(rec)
        return rec

    def _solve(self, clock: _Clock, dt: float, frames: int = 1,
               measure: bool = False) -> Generator[Solve | Measure, dict, dict]:
        """`frames` solver frames; pins waiting for the seams are attached after the first
        frame whose ramp is no longer closing (so frame by frame until then). Returns the
        last frame's `Simulation.step` statistics (its `ramp_phase`: "closing", "releasing"
        or "done"), with `measure` and the metrics after the last frame (`Solve.measure`)."""
        ask = {"measure": True, "collider": self.metrics_collider} if measure else {}
        if self.pins is None or self.pins.attached:
            return (yield from clock.request(Solve(dt, frames, **ask)))
        stats = {"ramp_phase": "done"}
        for k in range(frames):
            stats = yield from clock.request(Solve(dt, 1, **(ask if k == frames - 1 else {})))
            if self.pins.after_frame(self.sim, stats["ramp_phase"]):
                if frames - k - 1 > 0:
                    stats = yield from clock.request(Solve(dt, frames - k - 1, **ask))
                break
        return stats

    def _assembly_frame(self, clock: _Clock, phase: str, index: int, dt: float,
                        colliders: Sequence[np.ndarray]) -> Generator[Solve | Measure, dict, str]:
        """One preroll or transition frame, handed to `on_assembly_frame` when there is one.
        Returns the ramp's phase after it."""
        t0 = clock.ms()
        stats = yield from self._solve(clock, dt)
        if self.on_assembly_frame is not None:
            self.on_assembly_frame(AssemblyFrame(phase, index, clock.ms() - t0, stats, colliders))
        return stats["ramp_phase"]

    def preroll_limit(self) -> int:
        """The most preroll frames `_assemble` runs while the seams are still closing."""
        if self.preroll_max is not None:
            return max(self.preroll, self.preroll_max)
        return max(self.preroll, round(ASSEMBLY_MAX_S * self.fps))

    def _assemble(self, start_positions: Sequence[np.ndarray], clock: _Clock) -> Generator[Solve | Measure, dict, None]:
        dt = 1.0 / self.fps
        pose = self.assembly if self.assembly is not None else start_positions
        if self.preroll > 0:
            self._set_colliders(pose)
            settings = self.sim.settings
            gravity = settings.gravity
            if self.assembly_gravity is not None:
                settings.gravity = tuple(self.assembly_gravity)
                self.sim.settings = settings
            try:
                # At least `preroll` frames, and on while the seams close: the ramp ends its
                # closing phase when they have met (or stalled), by measured gaps, however far
                # apart the pieces were placed; leaving the pose earlier drags open seams
                # through the motion.
                n, cap = self.preroll, self.preroll_limit()
                if self.on_assembly_frame is None:
                    phase = (yield from self._solve(clock, dt, self.preroll))["ramp_phase"]
                else:  # frame by frame, as many solver frames (`Simulation.step` loops the same)
                    for k in range(1, self.preroll + 1):
                        phase = yield from self._assembly_frame(clock, "preroll", k, dt, pose)
                while phase == "closing" and n < cap:
                    phase, n = (yield from self._assembly_frame(clock, "preroll", n + 1, dt, pose)), n + 1
                self.preroll_frames = n
            finally:
                if self.assembly_gravity is not None:
                    settings.gravity = gravity
                    self.sim.settings = settings
        if self.assembly is not None and self.transition > 0:
            a = [np.asarray(p, np.float32) for p in self.assembly]
            b = [np.asarray(p, np.float32) for p in start_positions]
            for k in range(1, self.transition + 1):
                t = k / self.transition
                t = t * t * (3.0 - 2.0 * t)
                blend = [(1.0 - t) * pa + t * pb for pa, pb in zip(a, b)]
                self._set_colliders(blend)
                yield from self._assembly_frame(clock, "transition", k, dt, blend)
        self.prerolled = True

    def run(
        self,
        collider_positions_at: Callable[[int], Sequence[np.ndarray]],
        end: int,
        cancel: Callable[[], bool] | None = None,
        on_frame: Callable[[dict], None] | None = None,
    ) -> bool:
        """Steps up to frame `end` (inclusive) from `next_frame`. `cancel()` is asked before
        every frame: when it says yes the loop stops, keeping the frames done, and returns
        False (call `run` again to resume). Returns True when `end` is reached."""
        while self.next_frame <= end:
            if cancel is not None and cancel():
                return False
            rec = self.step(collider_positions_at(self.next_frame))
            if on_frame is not None:
                on_frame(rec)
        return True

    def replay(self, cached: np.ndarray, collider_positions_at: Callable[[int], Sequence[np.ndarray]],
               cancel: Callable[[], bool] | None = None, atol: float = 0.0,
               view: Callable[[np.ndarray], np.ndarray] | None = None) -> None:
        """Rebuilds the state at the end of `cached` ((k, n, 3): frames start..start+k-1 of an
        earlier bake with the same garment, colliders and settings) by solving them again, and
        checks that every frame comes out identical (within `atol` metres: a cache stored in
        another frame of reference has rounding of its own). `view` turns a frame's particles
        into what the cache holds (the welded garment's points, ``tailor.export``), when it holds
        something else than the particles. Raises `SimulationError` when one differs
        (the scene or settings changed since: bake again from the start), `CancelledError` when
        cancelled."""
        cached = np.asarray(cached, np.float32)
        for k in range(len(cached)):
            if cancel is not None and cancel():
                raise CancelledError(f"resuming stopped while re-solving frame {self.next_frame}")
            self.step(collider_positions_at(self.next_frame))
            solved = self.frames[-1] if view is None else view(self.frames[-1])
            diff = float(np.abs(solved - cached[k]).max()) if solved.shape == cached[k].shape else np.inf
            if not diff <= atol:
                raise SimulationError(
                    f"the cache differs from a new solve at frame {self.start + k} (by {diff:.3g} m): the garment, "
                    "colliders or settings changed since it was baked; bake again from the start"
                )

    def summary(self) -> dict:
        return summarize(self.records)

    def positions(self) -> np.ndarray:
        """(frames, n, 3) float32: every frame solved so far."""
        if not self.frames:
            return np.zeros((0, self.sim.num_particles, 3), np.float32)
        return np.stack(self.frames)
