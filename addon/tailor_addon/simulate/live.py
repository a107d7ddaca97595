"""Live mode's Blender half: one `LiveSession` per scene, ticked on the main thread.

A tick (from the modal timer in the UI, or `tailor.live_step` in scripts and tests) does only
main-thread work: take the solver's finished frame (`core.simulate_live.LiveSolver.poll`) and
write it into the piece meshes, then, if the solver is idle, gather the colliders at the
current frame (the timeline plays or the artist scrubs: the garment follows) plus any edits
and submit them. The solve itself runs on a native thread, so the viewport waits for at most
one frame's gathering and writing.

Edits apply without a restart: every tick compares the pieces' fabric and the panel's
settings with what the solver has, and every `MAPS_EVERY` ticks re-reads the painted maps
(pins, friction, mass); a change becomes an edit applied before the next frame starts.
Stopping restores the pieces' meshes as they were before Live started, and so does saving the
file during Live, for the save only (`hold_for_save`, from the save_pre handler): the .blend
keeps the pattern's placement, not a frame of the drape.
"""

from __future__ import annotations

import bpy
import numpy as np

from tailor import bake

from ..core import simulate as core_sim
from ..core.simulate_live import LiveResult, LiveSolver
from ..paint.maps import painted_maps
from . import fit_map_attrs, gather

SESSIONS: dict[str, "LiveSession"] = {}
MAPS_EVERY = 15


class LiveSession:
    def __init__(self, context):
        scene = context.scene
        self.scene_name = scene.name
        self.settings = gather.sim_settings(scene)
        garment, self.objects, self.fabrics, self.maps, self.collider_objects = gather.read_scene(scene)
        self.garment = garment
        dg = context.evaluated_depsgraph_get()
        colliders = gather.collider_data(self.collider_objects, dg)
        built = core_sim.build(garment, self.settings, self.fabrics, self.maps, colliders)
        self.warnings, self.adapter = built.warnings, built.adapter
        # The module's garment the solver was built from: edits change it and re-apply the
        # changed part in the core (`Garment.apply_fabric`, ...), as the build applied it.
        self.tgarment = built.garment
        self.hard_pins = _hard_pins(self.tgarment)
        self.piece_names = [o.name for o in self.objects]
        # What Live overwrites, restored by `stop`.
        self.original = [_local_co(o) for o in self.objects]
        self.solver = LiveSolver(bake.Bake(built.sim, built.colliders, self.settings.fps, scene.frame_current,
                                           pins=built.pins))
        self.fit_map = scene.tailor_simulate.fit_map
        self.ticks = 0
        self.frames_applied = 0
        self.last: LiveResult | None = None
        self.error: BaseException | None = None

    # ---- main thread ----------------------------------------------------------------------------

    def tick(self, context, block: bool = False, timeout: float = 60.0) -> LiveResult | None:
        """One main-thread turn: take a finished frame, submit the next, then write the finished
        one into the pieces while the next solves. With `block`, submit first if idle and wait
        for that frame (scripts, tests)."""
        self.ticks += 1
        if block and not self.solver.busy:
            self.submit(context)
        res = self.solver.wait(timeout) if block else self.solver.poll()
        if res is not None and res.error is not None:
            self.error = res.error
            return res
        if self.error is None and not self.solver.busy and not block:
            self.submit(context)
        if res is not None:
            self.apply(res)
        return res

    def submit(self, context) -> bool:
        scene = context.scene
        dg = context.evaluated_depsgraph_get()
        positions = [gather.evaluated_positions(o, dg) for o in self.collider_objects]
        self.fit_map = scene.tailor_simulate.fit_map
        self.solver.fit_maps = self.fit_map != "NONE"
        return self.solver.submit(scene.frame_current, positions, self.pending_edits(scene))

    def apply(self, res: LiveResult) -> None:
        if res.error is not None:
            self.error = res.error
            return
        self.last = res
        self.frames_applied += 1
        for part, o in zip(core_sim.split_pieces(res.positions, self.garment.offsets, self.garment.num_particles),
                           self.objects):
            inv = np.linalg.inv(np.array(o.matrix_world, np.float64))
            local = (part.astype(np.float64) @ inv[:3, :3].T + inv[:3, 3]).astype(np.float32)
            gather.write_positions(o.data, local.reshape(-1))
            o.data.update()
        if res.fit_maps is not None and self.fit_map != "NONE":
            self._write_fit_maps(res.fit_maps)

    def _write_fit_maps(self, maps: dict) -> None:
        """A measured frame's fit maps onto the pieces (`fit_map_attrs.write`)."""
        fit_map_attrs.write(self.objects, self.garment.offsets, self.garment.num_particles, maps, self.fit_map)

    def pending_edits(self, scene) -> list:
        """Edits of fabric, settings and painted maps since the solver last saw them. Each edit
        is applied to the module's garment here and to the solver when the next frame starts."""
        edits = []
        fabrics = gather.fabrics(self.objects)
        maps = self.maps
        if self.ticks % MAPS_EVERY == 0:
            maps = [painted_maps(o) for o in self.objects]
        settings = gather.sim_settings(scene)
        if settings.substeps < 1:  # keep going with the last good settings; the panel shows the value
            settings = self.settings
        changed = {k for k in ("mass_scale", "bend_scale", "friction_static", "friction_kinetic", "pin")
                   if not _same_maps(maps, self.maps, k)}
        if fabrics != self.fabrics or settings != self.settings or changed:
            g = core_sim.garment_of(self.tgarment, "", settings, fabrics, maps)
        if fabrics != self.fabrics or changed & {"mass_scale", "bend_scale"}:
            edits.append(lambda sim: _reapply(g, sim, "fabric"))
        if changed & {"friction_static", "friction_kinetic"} or (
                settings.friction_static, settings.friction_kinetic) != (self.settings.friction_static,
                                                                       self.settings.friction_kinetic):
            edits.append(lambda sim: _reapply(g, sim, "friction"))
        pins = self.solver.run.pins
        if "pin" in changed and pins is not None:
            # Riding on the collider (pin mode ATTACH): the new groups replace the old ones.
            groups = g.attach_groups()
            edits.append(lambda sim, groups=groups: pins.replace(sim, groups))
        elif "pin" in changed:
            hard = _hard_pins(g)
            old, pos = self.hard_pins, self.garment.positions

            def repin(sim, old=old, hard=hard, pos=pos):
                if len(old):
                    sim.unpin(old.astype(np.int64))
                if len(hard):
                    sim.pin(hard.astype(np.int64), pos[hard])

            edits.append(repin)
            self.hard_pins = hard
        if settings != self.settings:
            edits.append(lambda sim, s=settings: _apply_settings(sim, g, s))
        self.settings = settings
        self.fabrics, self.maps = fabrics, maps
        return edits

    def stats(self) -> dict:
        # The quality of the latest measured frame (Live measures a few times a second).
        m = self.solver.measured
        r = m.record if m is not None else {}
        return {
            "fps": self.solver.fps(),
            "seam_gap_mm": r.get("seam_gap_max_m", 0.0) * 1e3,
            "penetrations": r.get("penetration_count", 0),
            "penetration_mm": r.get("penetration_max_m", 0.0) * 1e3,
            "strain": r.get("strain_max", 0.0),
            "frame": self.last.frame if self.last is not None else None,
            "solve_ms": self.last.solve_ms if self.last is not None else 0.0,
        }

    def stop(self, restore: bool = True) -> None:
        self.solver.stop()
        if restore:
            self._write(self.original)

    def hold_for_save(self) -> None:
        """Before the file is saved: the pieces as they were before Live (a save keeps the
        pattern's placement, not a frame of the drape), the drape kept for `resume_after_save`."""
        self._draped = [None if o is None else _local_co(o) for o in map(bpy.data.objects.get, self.piece_names)]
        self._write(self.original)

    def resume_after_save(self) -> None:
        """After the save: the drape back on the pieces, Live going on where it was."""
        self._write(getattr(self, "_draped", None) or [])
        self._draped = None

    def _write(self, positions: list) -> None:
        """Flat local positions onto the pieces (by name; a piece gone or re-meshed is left)."""
        for name, co in zip(self.piece_names, positions):
            o = bpy.data.objects.get(name)
            if co is not None and o is not None and len(o.data.vertices) * 3 == len(co):
                gather.write_positions(o.data, co)
                o.data.update()


def _local_co(obj) -> np.ndarray:
    """A mesh object's local vertex positions, flat."""
    return gather.read_positions(obj.data)


def hold_all_for_save() -> None:
    for session in SESSIONS.values():
        session.hold_for_save()


def resume_all_after_save() -> None:
    for session in SESSIONS.values():
        session.resume_after_save()


def _same_maps(a: list[dict], b: list[dict], key: str) -> bool:
    for ma, mb in zip(a, b):
        va, vb = ma.get(key), mb.get(key)
        if (va is None) != (vb is None):
            return False
        if va is not None and not (np.array_equal(va[0], vb[0]) and np.array_equal(va[1], vb[1])):
            return False
    return True


def _hard_pins(g) -> np.ndarray:
    """The weight-1 pins of the module's garment (`Garment.pin_weights`), as particle indices."""
    return next((np.asarray(p, np.int64) for w, p in g.pin_weights() if w >= 1.0), np.zeros(0, np.int64))


def _reapply(g, sim, part: str) -> None:
    """Re-applies one part of the module garment's setup ("fabric", "friction" or "collision")
    to the running solver, as its build applied it (`Garment.apply_fabric`, ...)."""
    getattr(g, f"apply_{part}")(sim)


def _apply_settings(sim, g, s: core_sim.SimSettings) -> None:
    sim.settings = s.to_tailor()
    _reapply(g, sim, "collision")


def start(context) -> LiveSession:
    stop(context.scene)
    session = LiveSession(context)
    SESSIONS[context.scene.name] = session
    context.scene.tailor_simulate.live_running = True
    context.scene.tailor_simulate.adapter = session.adapter
    return session


def stop(scene, restore: bool = True) -> None:
    session = SESSIONS.pop(scene.name, None)
    if session is not None:
        session.stop(restore)
    scene.tailor_simulate.live_running = False


def stop_all() -> None:
    for name in list(SESSIONS):
        session = SESSIONS.pop(name)
        session.stop(restore=bpy.data.scenes.get(name) is not None)

