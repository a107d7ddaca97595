"""A sample garment file on the animated sample character, headless (module only, no bpy).

The sample garments (sample_blends/*.json, written by sample_blends/build/garments.py) hold
their fabric per piece, collision levels and solver choices in the garment file's typed setup
(`tailor.Garment.setup`); the character is `sample_blends/character.glb` read by
`tailor.AnimatedMesh`, Y-up like the garment files. The stages of a run, in order:

1. **assemble** at the rest pose (the A-pose GarmentCode places its panels for): the seams close
   under the damping ramp and the garment settles;
2. **blend** from the rest pose into the first frame of the action, vertex by vertex, so the
   arms come down from the A-pose over a few frames instead of teleporting through the cloth;
3. **animate**: the action plays (looping) at the frame rate.

`Character.at(frame)` gives the body's vertices for any frame of that schedule; `dress()`
builds the `tailor.Simulation` with the body as a mesh collider, configured by the garment
file's own setup (`tailor.Garment.build_simulation`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

import tailor
from tailor.bake import ASSEMBLY_MAX_S, ColliderPins

GRAVITY_Y = (0.0, -9.81, 0.0)


@dataclass
class Schedule:
    assemble: int  # frames at the rest pose (at least: `hold` adds more while the seams close)
    blend: int  # frames from the rest pose into the action's first frame
    fps: float = 30.0
    assemble_max: int | None = None  # the most frames at rest (None: `bake.ASSEMBLY_MAX_S`)

    def hold(self, frame: int, ramp_phase: str) -> None:
        """After solving `frame`: when it was the last frame at rest and the seams are still
        closing (`ramp_phase`, as `Simulation.step` reports it), the rest pose is held one
        frame more, up to `assemble_max`; as `bake.Bake`'s preroll, so the garment leaves the
        rest pose assembled however far apart its pieces were placed."""
        cap = self.assemble_max if self.assemble_max is not None else round(ASSEMBLY_MAX_S * self.fps)
        if frame == self.assemble - 1 and ramp_phase == "closing" and self.assemble < cap:
            self.assemble += 1

    def phase(self, frame: int) -> str:
        if frame < self.assemble:
            return "assemble"
        return "blend" if frame < self.assemble + self.blend else "animate"


class Character:
    """The skinned body of a glTF file: its rest pose and one action, on a `Schedule`."""

    def __init__(self, path: str | Path, action: str = "walk"):
        import tailor

        self.path = str(path)
        self.mesh = tailor.AnimatedMesh(self.path)
        self.triangles = np.asarray(self.mesh.triangles, np.uint32)
        names = [n for n, _ in self.mesh.animations]
        if action not in names:
            raise tailor.InvalidParameterError(f"{self.path}: no action '{action}' (it has {', '.join(names)})")
        self.action = names.index(action)
        self.duration = float(self.mesh.animations[self.action][1])
        self.rest = self.mesh.positions_at(0.0, None)

    def pose(self, t: float) -> np.ndarray:
        """Vertices at time `t` seconds of the action (looping)."""
        return self.mesh.positions_at(t % self.duration if self.duration > 0 else 0.0, self.action)

    def at(self, frame: int, schedule: Schedule) -> np.ndarray:
        """Vertices at simulation frame `frame` (0-based) of `schedule`."""
        if frame < schedule.assemble:
            return self.rest
        k = frame - schedule.assemble
        if k < schedule.blend:
            w = (k + 1) / schedule.blend
            # Smoothstep: the body starts and ends the blend at rest, no jolt for the cloth.
            w = w * w * (3.0 - 2.0 * w)
            return ((1.0 - w) * self.rest + w * self.pose(0.0)).astype(np.float32)
        return self.pose((k - schedule.blend) / schedule.fps)


@dataclass
class Dressed:
    sim: object  # tailor.Simulation
    collider: int
    offsets: list[int]
    triangles: np.ndarray
    info: dict
    body: np.ndarray | None = None  # the collider's current vertices
    pins: ColliderPins | None = None  # the particles painted with the pin map

    def move_body(self, body: np.ndarray) -> None:
        """The collider to new body vertices (the attached pins ride on it in the solver)."""
        self.body = body
        self.sim.set_collider_positions(self.collider, body)

    def step(self, dt: float) -> dict:
        """One frame. The solver holds gravity while the seams close (`ramp_closing_gravity`,
        0 by default); once they have met, the pinned particles are attached to the body where
        the assembled garment put them (`Simulation.attach_to_collider`: each rides on its
        nearest body triangle from then on; attached from the start, they would hold the seams
        open). The rule is `tailor.bake.ColliderPins.after_frame`, the add-on's bakes' too."""
        st = self.sim.step(dt)
        if self.pins is not None:
            self.pins.after_frame(self.sim, st["ramp_phase"])
        return st


def dress(garment_path: str | Path, body: np.ndarray, triangles: np.ndarray, substeps: int = 8,
          iterations: int = 15, thickness: float | None = None) -> Dressed:
    """A simulation of the garment file on the body (vertices `body`, Y-up), configured by the
    garment's own setup (`tailor.Garment.build_simulation`: fabric per piece, painted maps,
    thickness, self-collision) and the collider levels it records; its pins ride on the body
    once the seams have met (`tailor.bake.ColliderPins`)."""
    import tailor

    garment_path = str(garment_path)
    g = tailor.Garment.load(garment_path)
    if thickness is not None:
        g.setup = {**g.setup, "thickness": float(thickness)}
    settings = tailor.Settings(substeps=substeps, iterations=iterations, gravity=GRAVITY_Y)
    sim, offsets = g.build_simulation(settings=settings)
    cid = sim.add_mesh_collider(np.asarray(body, np.float32), triangles, static_friction=0.6, kinetic_friction=0.4)
    levels, warnings = g.collider_levels(len(body))
    if levels is not None:
        sim.set_collider_levels(cid, levels)
    warnings = g.build_warnings + warnings
    if warnings:
        raise tailor.InvalidParameterError(f"{garment_path}: " + "; ".join(warnings))
    pins = ColliderPins(cid, g.attach_groups())
    meshes = g.meshes()
    tris = np.concatenate([np.asarray(m.triangles, np.int64) + o for m, o in zip(meshes, offsets)]).astype(np.uint32)
    info = {
        "garment": g.setup["name"] or Path(garment_path).stem,
        "pieces": len(g.pieces),
        "seams": len(g.seams),
        "particles": sim.num_particles,
        "triangles": int(sim.num_triangles),
        **setup_info(sim, g, pins),
    }
    return Dressed(sim, cid, list(offsets), tris, info, body=np.asarray(body, np.float32), pins=pins)


def setup_info(sim, garment, pins: ColliderPins) -> dict:
    """What a report says of the garment's setup as applied to `sim`."""
    return {
        "levels": sorted(set(int(x) for x in np.unique(sim.particle_levels))),
        "self_collision": bool(sim.self_collision["enabled"]),
        "self_collision_radius_m": float(sim.self_collision["radius"]),
        "self_collision_friction": [float(sim.self_collision["static_friction"]),
                                    float(sim.self_collision["kinetic_friction"])],
        "thickness_m": float(garment.setup["thickness"]),
        "attached": int(len(pins.particles)),
    }


def quality(d: Dressed, start: dict | None = None, metrics: dict | None = None) -> dict:
    """The quality figures of the current state (seam gap, penetration, strain), SI units, and
    the garment on the body judged against `start` (as `tailor.bake.judged_from` keeps it: the
    `Simulation.metrics` of the first frame, then of the first assembled one) as
    `tailor.bake.frame_record` judges it: `on_body_fraction`, `centroid_shift_m`,
    `seams_closing`, `failed`. `metrics` is `d.sim.metrics(d.collider)` when the caller has it."""
    m = d.sim.metrics(d.collider) if metrics is None else metrics
    nan = not bool(np.isfinite(d.sim.positions).all())
    verdict = tailor.judge(m, start, nan)
    return {
        "seam_gap_m": float(m["seam_gap"]),
        "penetration_count": int(m["penetration_count"]),
        "penetration_max_m": float(m["penetration_max_depth"]),
        "strain_max": float(m["strain_max"]),
        "strain_mean": float(m["strain_mean"]),
        "self_intersections": int(m["self_intersections"]),
        "on_body_fraction": None if m["on_body_fraction"] is None else float(m["on_body_fraction"]),
        "centroid_shift_m": float(verdict["centroid_shift_m"]),
        "seams_closing": bool(m["seams_closing"]),
        "nan": nan,
        "failed": verdict["failed"],
    }
