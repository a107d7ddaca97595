"""A sample garment file on the animated sample character, headless (module only, no bpy).

The sample garments (sample_blends/*.json, written by sample_blends/build/garments.py) hold
their fabric per piece, collision levels and solver choices in the garment file's extras
(`garment_extras`); the character is `sample_blends/character.glb` read by
`tailor.AnimatedMesh`, Y-up like the garment files. The stages of a run, in order:

1. **assemble** at the rest pose (the A-pose GarmentCode places its panels for): the seams close
   under the damping ramp and the garment settles;
2. **blend** from the rest pose into the first frame of the action, vertex by vertex, so the
   arms come down from the A-pose over a few frames instead of teleporting through the cloth;
3. **animate**: the action plays (looping) at the frame rate.

`Character.at(frame)` gives the body's vertices for any frame of that schedule; `dress()`
builds the `tailor.Simulation` with the body as a mesh collider. `file_setup()` applies what a
garment file records besides its pieces and seams to a simulation (the command line's
`simulate` uses it too, on any collider).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

import tailor
from tailor.bake import ASSEMBLY_MAX_S, ColliderPins
from tailor.commands import garment_extras

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


ATTACH_STIFFNESS = 100.0  # N/m per pinned particle: holds a waistband against its ~1e-3 N weight


def base_fabric(extras: dict):
    """The fabric a garment file's simulation is built with: its first piece's (the rest are
    set per triangle by `file_setup`), or the module's default when the file records none."""
    import tailor

    fabrics = extras.get("tailor_sample", {}).get("fabric_per_piece")
    return tailor.Fabric(**fabrics[0]) if fabrics else tailor.Fabric()


def file_setup(sim, garment, offsets, extras: dict, params: dict, collider: int, collider_vertices: int,
               thickness: float | None = None, self_collision: bool | None = None) -> tuple[dict, ColliderPins, list]:
    """Applies to `sim` (built from `garment` with `base_fabric(extras)`, pieces starting at
    `offsets`) what a garment file records besides its pieces and seams (`garment_extras`):
    fabric per piece, particles' collision levels, thickness, self-collision with its radius
    and the cloth's friction against itself, the collider's levels (mesh collider `collider`,
    of `collider_vertices` vertices), and the painted pins, returned as `ColliderPins` riding on the collider once every seam has met
    (weight w at w x `ATTACH_STIFFNESS`, as the add-on's pin mode *Ride on Character*).
    `thickness` and `self_collision` override the file's when given. Per-particle values whose
    piece has another vertex count (the garment re-triangulated since) and collider levels for
    another mesh are left out with a warning. Returns (info, pins, warnings)."""
    sample = extras.get("tailor_sample", {})
    meshes = garment.meshes()
    n, counts = sim.num_particles, [len(m.rest) for m in meshes]
    tri_counts = [len(m.triangles) for m in meshes]
    warnings: list[str] = []
    fabrics = sample.get("fabric_per_piece")
    if fabrics and len(fabrics) != len(meshes):
        warnings.append(f"the file records fabric for {len(fabrics)} pieces, the garment has {len(meshes)}: not used")
        fabrics = None
    base = fabrics[0] if fabrics else None
    if fabrics and any(f != base for f in fabrics):
        # Per-piece fabric: stiffness and bending per triangle, density as a mass scale per particle.
        def per_tri(key: str) -> np.ndarray:
            return np.repeat([f.get(key, base.get(key)) for f in fabrics], tri_counts).astype(np.float32)

        sim.set_triangle_stiffness(per_tri("stretch"), per_tri("shear"))
        sim.set_triangle_bending(per_tri("bend"))
        dens = np.repeat([f.get("density", base.get("density")) / base.get("density") for f in fabrics], counts)
        sim.set_mass_scale(dens.astype(np.float32))

    def per_particle(name: str, dtype) -> np.ndarray:
        out = np.zeros(n, dtype)
        for piece, values in params.get(name, {}).items():
            if piece >= len(counts) or len(values) != counts[piece]:
                warnings.append(f"painted '{name}' of piece {piece} does not fit the garment's piece (re-triangulated?):"
                                " left out")
                continue
            out[offsets[piece]:offsets[piece] + len(values)] = values
        return out

    levels = per_particle("collision_level", np.int32)
    if levels.any():
        sim.set_particle_levels(levels)
    thickness = float(thickness if thickness is not None else sample.get("thickness", 0.004))
    sim.thickness = thickness  # write-only on the module's Simulation
    enabled = bool(self_collision if self_collision is not None else sample.get("self_collision", False))
    radius = float(sample.get("self_collision_radius", 0.0))  # 0: the solver's default
    # The cloth's friction against itself (files from before it was recorded: the solver's).
    friction = {k: float(sample[f]) for k, f in (("static_friction", "friction_static"),
                                                  ("kinetic_friction", "friction_kinetic")) if f in sample}
    sim.set_self_collision(enabled=enabled, radius=radius if radius > 0 else None, **friction)
    body_levels = sample.get("collider_levels")
    if body_levels and int(body_levels["vertices"]) != collider_vertices:
        warnings.append(f"the file's collider levels are for a mesh of {body_levels['vertices']} vertices, the "
                        f"collider has {collider_vertices}: left out")
    elif body_levels:
        sim.set_collider_levels(collider, garment_extras.decode_runs(body_levels["runs"], collider_vertices))
    pins = per_particle("pin", np.float32)
    info = {
        "levels": sorted(set(int(x) for x in np.unique(levels))),
        "self_collision": enabled,
        "self_collision_radius_m": float(sim.self_collision["radius"]),
        "self_collision_friction": [float(sim.self_collision["static_friction"]),
                                    float(sim.self_collision["kinetic_friction"])],
        "thickness_m": thickness,
        "attached": int((pins > 0).sum()),
    }
    # A painted weight w attaches at w times the stiffness, as the add-on's Ride on Character does.
    weights = np.round(np.clip(pins, 0.0, 1.0), 2)
    groups = [(np.flatnonzero(weights == w), ATTACH_STIFFNESS * float(w)) for w in np.unique(weights) if w > 0]
    return info, ColliderPins(collider, groups), warnings


def dress(garment_path: str | Path, body: np.ndarray, triangles: np.ndarray, substeps: int = 8,
          iterations: int = 15, thickness: float | None = None) -> Dressed:
    """A simulation of the garment file on the body (vertices `body`, Y-up), with the garment's
    own fabric per piece, collision levels, thickness and self-collision choice."""
    import tailor

    garment_path = str(garment_path)
    g = tailor.Garment.load(garment_path)
    extras, params = garment_extras.read_extras(garment_path)
    settings = tailor.Settings(substeps=substeps, iterations=iterations, gravity=GRAVITY_Y)
    sim, offsets = g.build_simulation(base_fabric(extras), settings)
    cid = sim.add_mesh_collider(np.asarray(body, np.float32), triangles, static_friction=0.6, kinetic_friction=0.4)
    setup, pins, warnings = file_setup(sim, g, offsets, extras, params, cid, len(body), thickness=thickness)
    if warnings:
        raise tailor.InvalidParameterError(f"{garment_path}: " + "; ".join(warnings))
    meshes = g.meshes()
    tris = np.concatenate([np.asarray(m.triangles, np.int64) + o for m, o in zip(meshes, offsets)]).astype(np.uint32)
    info = {
        "garment": extras.get("tailor_sample", {}).get("name", Path(garment_path).stem),
        "pieces": len(g.pieces),
        "seams": len(g.seams),
        "particles": sim.num_particles,
        "triangles": int(sim.num_triangles),
        **setup,
    }
    return Dressed(sim, cid, list(offsets), tris, info, body=np.asarray(body, np.float32), pins=pins)


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
