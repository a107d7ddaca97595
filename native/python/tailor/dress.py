"""A sample garment file on a body, headless (module only, no bpy): its simulation and quality.

The sample garments (sample_blends/*.json, written by sample_blends/build/garments.py) hold
their fabric per piece, collision levels and solver choices in the garment file's typed setup
(`tailor.Garment.setup`). `dress()` builds the `tailor.Simulation` of such a file with a body
(the vertices of `tailor.motion.ColliderMotion`'s rest pose, say) as a mesh collider, configured
by the garment file's own setup (`tailor.Garment.build_simulation`); `Dressed.record()` gives
the figures of its current state as every run records them (`tailor.bake.frame_record`).

The body's motion (`tailor.motion`) and the frame loop with its assembly at the rest pose and
blend into the action (`tailor.bake.Bake`'s preroll and transition) are not here: the demo
(`demo/character.py`) drives a dressed garment through those.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

import tailor
from tailor.bake import ColliderPins, frame_record

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

    def record(self, frame: int = 0, ms: float = 0.0, start: dict | None = None) -> dict:
        """The quality of the current state as `tailor.bake.frame_record` gives it (the one
        record every run writes), judged against `start` (a `Simulation.metrics`)."""
        return frame_record(self.sim, frame, ms, False, self.collider, start)

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


def dress(garment, body: np.ndarray, triangles: np.ndarray, substeps: int = 8, iterations: int = 15,
          thickness: float | None = None, *, settings=None, backend: str = "auto",
          self_collision: bool | None = None, self_contacts: str | None = None, collider_friction: tuple[float, float] | None = (0.6, 0.4),
          strict: bool = True, name: str | None = None) -> Dressed:
    """A simulation of `garment` (a `tailor.Garment`, or the path of a garment file) on a body
    (vertices `body`, triangles `triangles`), configured by the garment's own setup
    (`tailor.Garment.build_simulation`: fabric per piece, painted maps, thickness,
    self-collision) and the collider levels it records; its pins ride on the body once the
    seams have met (`tailor.bake.ColliderPins`). `settings` (a `tailor.Settings`; default
    `substeps` x `iterations`, Y-up gravity), `backend`, `thickness`, `self_collision`
    and `self_contacts` ("spheres" or "triangles") (override the garment's) and the body's `collider_friction` (None: the module's default)
    are the caller's. `strict`: what the build left out (a painted map for another mesh,
    collider levels for another body) is an error; else it is in `info["warnings"]`."""
    import tailor

    path = None
    if not isinstance(garment, tailor.Garment):
        path = str(garment)
        garment = tailor.Garment.load(path)
    overrides = {k: v for k, v in (("thickness", thickness), ("self_collision", self_collision),
                                   ("self_collision_contacts", self_contacts)) if v is not None}
    if overrides:
        garment.setup = {**garment.setup, **overrides}
    if settings is None:
        settings = tailor.Settings(substeps=substeps, iterations=iterations, gravity=GRAVITY_Y)
    sim, offsets = garment.build_simulation(settings=settings, backend=backend)
    friction = {} if collider_friction is None else dict(zip(("static_friction", "kinetic_friction"), collider_friction))
    cid = sim.add_mesh_collider(np.asarray(body, np.float32), triangles, **friction)
    levels, warnings = garment.collider_levels(len(body))
    if levels is not None:
        sim.set_collider_levels(cid, levels)
    warnings = garment.build_warnings + warnings
    if warnings and strict:
        raise tailor.InvalidParameterError(f"{path or 'garment'}: " + "; ".join(warnings))
    pins = ColliderPins(cid, garment.attach_groups())
    meshes = garment.meshes()
    tris = np.concatenate([np.asarray(m.triangles, np.int64) + o for m, o in zip(meshes, offsets)]).astype(np.uint32)
    info = {
        "garment": name or garment.setup["name"] or (Path(path).stem if path else "garment"),
        "pieces": len(garment.pieces),
        "seams": len(garment.seams),
        "particles": sim.num_particles,
        "triangles": int(sim.num_triangles),
        **setup_info(sim, garment, pins),
        "warnings": warnings,
    }
    return Dressed(sim, cid, list(offsets), tris, info, body=np.asarray(body, np.float32), pins=pins)


#: The keys `setup_info` gives (what a report says of the setup in effect).
SETUP_KEYS = ("levels", "self_collision", "self_collision_contacts", "self_collision_radius_m", "self_collision_friction", "thickness_m",
              "attached")


def setup_info(sim, garment, pins: ColliderPins) -> dict:
    """What a report says of the garment's setup as applied to `sim`."""
    return {
        "levels": sorted(set(int(x) for x in np.unique(sim.particle_levels))),
        "self_collision": bool(sim.self_collision["enabled"]),
        "self_collision_contacts": str(sim.self_collision["contacts"]),
        "self_collision_radius_m": float(sim.self_collision["radius"]),
        "self_collision_friction": [float(sim.self_collision["static_friction"]),
                                    float(sim.self_collision["kinetic_friction"])],
        "thickness_m": float(garment.setup["thickness"]),
        "attached": int(len(pins.particles)),
    }
