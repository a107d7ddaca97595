"""A sample garment file on a body, headless (module only, no bpy): its simulation and quality.

The sample garments (sample_blends/*.json, written by sample_blends/build/garments.py) hold
their fabric per piece, collision levels and solver choices in the garment file's typed setup
(`tailor.Garment.setup`). `dress()` builds the `tailor.Simulation` of such a file with a body
(the vertices of `tailor.motion.ColliderMotion`'s rest pose, say) as a mesh collider, configured
by the garment file's own setup (`tailor.Garment.build_simulation`); `quality()` gives the
figures of its current state.

The body's motion (`tailor.motion`) and the frame loop with its assembly at the rest pose and
blend into the action (`tailor.bake.Bake`'s preroll and transition) are not here: the demo
(`demo/character.py`) drives a dressed garment through those.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

import tailor
from tailor.bake import ColliderPins

GRAVITY_Y = (0.0, -9.81, 0.0)


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
