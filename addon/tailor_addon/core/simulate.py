"""From the Simulate panel's settings and the scene's arrays to a ready `tailor.Simulation`.

Bpy-free: the Blender layer (`simulate/`) reads the panel, the pieces' fabric, the painted
maps and the colliders' evaluated meshes into the plain structures below, and this module
builds the simulation the Bake and Live modes drive through `tailor.bake.Bake`. Everything is
validated here, before anything in the scene changes, so a bad setting is a report and the
scene stays as it was.

Per-piece fabric: stretch and shear become per-triangle stiffness, density a per-particle
mass scale (relative to the simulation's base fabric, the first piece's); painted maps
(`core/paint.py`) override friction, mass, pins and collision levels per particle. Bending
is one value per simulation in the module: the first piece's (a warning says so when the
pieces differ).

Pins (`SimSettings.pin_mode`): `ATTACH` (default) makes the painted pins ride on the first
collider (the character): `tailor.bake.Bake` attaches them, softly at `pin_stiffness` N/m times
the painted weight, once every seam has met (attached from the first frame they would hold the
seams open), and from then on they follow the body. `FIXED` holds them where they were placed,
in world space, from the first frame: weight 1 hard pins, lower weights soft attachments.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

import tailor
from tailor import bake

from .errors import AddonError
from .garment import SceneGarment

#: Quality presets over substeps, iterations and tolerance (used when the module has no
#: `Settings.preset`). Preview keeps Live interactive; final is what the issue's quality
#: figures are measured with (`tailor simulate` defaults).
PRESETS = {
    "PREVIEW": {"substeps": 4, "iterations": 10, "tolerance": 1e-3},
    "FINAL": {"substeps": 8, "iterations": 15, "tolerance": 0.0},
}

#: Pin weights at or above this are hard pins; lower (non-zero) ones are soft attachments,
#: grouped by weight rounded to this many steps.
HARD_PIN = 0.999
ATTACHMENT_STEPS = 20

#: How painted pins hold (`SimSettings.pin_mode`): riding on the collider, or fixed in place.
PIN_MODES = ("ATTACH", "FIXED")


def preset_values(name: str) -> dict:
    """Substeps, iterations and tolerance of preset `name` (`PREVIEW`/`FINAL`): the module's
    `Settings.preset` when it has one, else the table above."""
    preset = getattr(tailor.Settings, "preset", None)
    if preset is not None:
        s = preset(name.lower())
        return {"substeps": s.substeps, "iterations": s.iterations, "tolerance": s.tolerance}
    if name not in PRESETS:
        raise AddonError(f"unknown quality preset '{name}'", f"Pick one of {', '.join(PRESETS)}")
    return dict(PRESETS[name])


def backend_support() -> str | None:
    """How the module takes a backend choice: 'settings' (a `Settings.backend` field),
    'simulation' (a `Simulation(..., backend=)` argument) or None (CPU only)."""
    if hasattr(tailor.Settings(), "backend"):
        return "settings"
    sig = getattr(tailor.Simulation, "__text_signature__", None) or ""
    return "simulation" if "backend" in sig else None


def adapter_of(sim) -> str:
    """The adapter a simulation runs on, as the module reports it."""
    for name in ("adapter", "backend_info", "backend"):
        v = getattr(sim, name, None)
        if v is not None and not callable(v):
            return str(v)
    return "CPU (this build of tailor has no backend choice)"


@dataclass
class SimSettings:
    """The Simulate panel's settings (SI units)."""

    substeps: int = 8
    iterations: int = 15
    tolerance: float = 0.0
    backend: str = "auto"  # auto | cpu | gpu
    gravity: tuple[float, float, float] = (0.0, 0.0, -9.81)
    air_damping: float | None = None
    ramp_enabled: bool = True
    ramp_closing_speed: float | None = None
    ramp_closing_damping: float | None = None
    thickness: float = 0.004
    self_collision: bool = False
    self_collision_radius: float = 0.0  # sphere radius, metres; 0: half the mean rest edge
    fps: float = 30.0
    seam_stiffness: float = 1.0e4  # tailor.DEFAULT_SEAM_STIFFNESS: the gap of a closed seam is tension / stiffness
    seam_bend_stiffness: float = 1e-5
    friction_static: float = 0.5
    friction_kinetic: float = 0.3
    pin_mode: str = "ATTACH"  # ATTACH: ride on the collider once the seams meet | FIXED: held in place
    pin_stiffness: float = 100.0  # N/m per ATTACH pin at weight 1: holds a waistband against its ~1e-3 N weight

    def to_tailor(self) -> tailor.Settings:
        if self.substeps < 1:
            raise tailor.InvalidParameterError(f"substeps is {self.substeps}: must be at least 1")
        if self.iterations < 1:
            raise tailor.InvalidParameterError(f"iterations is {self.iterations}: must be at least 1")
        if not self.fps > 0:
            raise tailor.InvalidParameterError(f"frame rate is {self.fps}: must be positive")
        kw = dict(
            substeps=int(self.substeps),
            iterations=int(self.iterations),
            tolerance=float(self.tolerance),
            gravity=tuple(float(g) for g in self.gravity),
            ramp_enabled=bool(self.ramp_enabled),
        )
        for name in ("air_damping", "ramp_closing_speed", "ramp_closing_damping"):
            v = getattr(self, name)
            if v is not None:
                kw[name] = float(v)
        if backend_support() == "settings":
            kw["backend"] = self.backend
        return tailor.Settings(**kw)


@dataclass
class PieceFabric:
    density: float
    stretch: float
    shear: float
    bend: float


@dataclass
class ColliderData:
    """A collider mesh at the start frame: world-space (n, 3) positions, (m, 3) triangles."""

    name: str
    positions: np.ndarray
    triangles: np.ndarray
    friction_static: float = 0.5
    friction_kinetic: float = 0.3
    levels: np.ndarray | None = None


@dataclass
class Built:
    sim: tailor.Simulation
    colliders: list[bake.Collider]
    warnings: list[str] = field(default_factory=list)
    adapter: str = ""
    #: Pins to attach to the collider once the seams have met (`pin_mode` ATTACH), for `Bake`.
    pins: bake.ColliderPins | None = None


def _per_particle(garment: SceneGarment, maps: list[dict], key: str, default: float) -> tuple[np.ndarray, bool]:
    """Values of painted map `key` over all particles (`default` where unpainted) and whether
    anything is painted."""
    out = np.full(garment.num_particles, default, np.float32)
    any_painted = False
    for i, m in enumerate(maps):
        if key in m:
            vals, painted = m[key]
            o = int(garment.offsets[i])
            sl = out[o : o + len(vals)]
            sl[painted] = np.asarray(vals, np.float32)[painted]
            any_painted |= bool(np.any(painted))
    return out, any_painted


def file_extras(name: str, settings: SimSettings, fabrics: list[PieceFabric], maps: list[dict],
                collider_levels: np.ndarray | None = None) -> tuple[dict, list]:
    """What a garment file exported from the scene records besides its pieces and seams, in the
    form `tailor.commands.on_character.file_setup` (and so `python -m tailor simulate`) reads
    back: (settings, per-particle params) for `tailor.commands.garment_extras.add_extras`. The
    settings (under `tailor_sample`, the key the sample garments introduced): fabric per piece,
    thickness, self-collision and its radius, the cloth's friction, and the collider's collision
    levels when painted;
    the params: painted pin weights (0 where unpainted) and collision levels per piece."""
    from tailor.commands import garment_extras

    sample = {
        "name": name,
        "fabric_per_piece": [{"density": f.density, "stretch": f.stretch, "shear": f.shear, "bend": f.bend}
                             for f in fabrics],
        "thickness": float(settings.thickness),
        "self_collision": bool(settings.self_collision),
        "self_collision_radius": float(settings.self_collision_radius),
        "friction_static": float(settings.friction_static),
        "friction_kinetic": float(settings.friction_kinetic),
    }
    if collider_levels is not None and np.any(collider_levels):
        sample["collider_levels"] = {"vertices": int(len(collider_levels)),
                                     "runs": garment_extras.encode_runs(collider_levels)}
    params = []
    for piece, m in enumerate(maps):
        if "pin" in m:
            values, painted = m["pin"]
            params.append(("pin", piece, np.where(painted, values, 0.0).astype(np.float32)))
        if "collision_level" in m:
            params.append(("collision_level", piece, np.asarray(m["collision_level"][0], np.int32)))
    return {"tailor_sample": sample}, params


def self_collision_args(settings: SimSettings) -> dict:
    """`Simulation.set_self_collision`'s arguments for `settings` (radius None: automatic). The
    cloth's friction (the panel's, where not painted) is also its friction against itself:
    painted friction overrides it per particle (`apply_friction`)."""
    r = float(settings.self_collision_radius)
    if not (np.isfinite(r) and r >= 0.0):
        raise tailor.InvalidParameterError(f"self-collision radius is {r}: must be 0 (automatic) or a positive length")
    fs, fk = float(settings.friction_static), float(settings.friction_kinetic)
    if not (np.isfinite(fs) and np.isfinite(fk) and fs >= 0.0 and fk >= 0.0):
        raise tailor.InvalidParameterError(f"cloth friction is static {fs}, kinetic {fk}: must be non-negative")
    return {"enabled": bool(settings.self_collision), "radius": r if r > 0.0 else None,
            "static_friction": fs, "kinetic_friction": fk}


def build(
    garment: SceneGarment,
    settings: SimSettings,
    fabrics: list[PieceFabric],
    maps: list[dict],
    colliders: list[ColliderData],
) -> Built:
    """The simulation of `garment` on `colliders` with everything the panels set. Raises
    `AddonError`/`tailor.TailorError` naming the offending piece, collider or setting."""
    if len(fabrics) != len(garment.pieces) or len(maps) != len(garment.pieces):
        raise AddonError("fabric or painted maps missing for some pieces", "Re-import the garment")
    for c in colliders:
        bake.check_collider_positions(c.name, c.positions, len(c.positions))
        if len(c.triangles) == 0:
            raise AddonError(f"collider '{c.name}' has no faces", "Pick a mesh with faces as collider")
    if not settings.thickness > 0:
        raise tailor.InvalidParameterError(f"thickness is {settings.thickness}: must be positive")
    if settings.pin_mode not in PIN_MODES:
        raise tailor.InvalidParameterError(f"pin mode is '{settings.pin_mode}': must be one of {', '.join(PIN_MODES)}")
    if settings.pin_mode == "ATTACH" and not (settings.pin_stiffness > 0 and np.isfinite(settings.pin_stiffness)):
        raise tailor.InvalidParameterError(f"pin stiffness is {settings.pin_stiffness}: must be positive")
    warnings = list(garment.warnings)
    base = fabrics[0]
    sim = garment.build_simulation(
        tailor.Fabric(density=base.density, stretch=base.stretch, shear=base.shear, bend=base.bend),
        settings.to_tailor(),
        seam_stiffness=settings.seam_stiffness,
        seam_bend_stiffness=settings.seam_bend_stiffness,
    )
    sim.thickness = float(settings.thickness)
    apply_fabric(sim, garment, fabrics, maps)
    apply_friction(sim, garment, maps, settings)
    attach = settings.pin_mode == "ATTACH" and bool(colliders)
    if not attach:
        hard, soft = pin_sets(garment, maps)
        if settings.pin_mode == "ATTACH" and (len(hard) or soft):
            warnings.append("pins are held in place: there is no collider for them to ride on")
        apply_pins(sim, garment, maps)
    levels, painted = _per_particle(garment, maps, "collision_level", 0)
    if painted:
        sim.set_particle_levels(levels.astype(np.int32))
    sim.set_self_collision(**self_collision_args(settings))
    out = []
    for c in colliders:
        cid = sim.add_mesh_collider(
            np.ascontiguousarray(c.positions, np.float32),
            np.ascontiguousarray(c.triangles, np.int64),
            static_friction=c.friction_static,
            kinetic_friction=c.friction_kinetic,
        )
        if c.levels is not None:
            sim.set_collider_levels(cid, np.asarray(c.levels, np.int32))
        out.append(bake.Collider(c.name, cid, len(c.positions)))
    pins = bake.ColliderPins(out[0].id, attach_groups(garment, maps, settings.pin_stiffness)) if attach else None
    return Built(sim, out, warnings, adapter_of(sim), pins)


def apply_fabric(sim, garment: SceneGarment, fabrics: list[PieceFabric], maps: list[dict]) -> None:
    """Per-triangle stretch/shear and bending (the piece's, times the painted bend scale averaged
    over each triangle's vertices), per-particle mass scale (density x painted mass)."""
    counts = [len(m.triangles) for m in garment.meshes]

    def per_tri(values: list[float]) -> np.ndarray:
        return np.repeat(values, counts).astype(np.float32)

    sim.set_triangle_stiffness(per_tri([f.stretch for f in fabrics]), per_tri([f.shear for f in fabrics]))
    bend_scale, _ = _per_particle(garment, maps, "bend_scale", 1.0)
    sim.set_triangle_bending(per_tri([f.bend for f in fabrics]) * bend_scale[garment.triangles].mean(axis=1))
    n = [len(m.rest) for m in garment.meshes]
    density = np.repeat([f.density / fabrics[0].density for f in fabrics], n).astype(np.float32)
    painted, _ = _per_particle(garment, maps, "mass_scale", 1.0)
    sim.set_mass_scale(density * painted)


def apply_friction(sim, garment: SceneGarment, maps: list[dict], settings: SimSettings) -> None:
    fs, a = _per_particle(garment, maps, "friction_static", settings.friction_static)
    fk, b = _per_particle(garment, maps, "friction_kinetic", settings.friction_kinetic)
    if a or b:
        sim.set_particle_friction(fs, fk)


def pin_sets(garment: SceneGarment, maps: list[dict]) -> tuple[np.ndarray, list[tuple[float, np.ndarray]]]:
    """(hard-pinned particles, [(weight, particles)] soft attachments) from the pin map."""
    w, _ = _per_particle(garment, maps, "pin", 0.0)
    hard = np.flatnonzero(w >= HARD_PIN)
    soft_w = np.round(w * ATTACHMENT_STEPS) / ATTACHMENT_STEPS
    soft = [(float(v), np.flatnonzero((soft_w == v) & (w < HARD_PIN))) for v in np.unique(soft_w) if 0 < v < 1]
    return hard, [(v, p) for v, p in soft if len(p)]


def attach_groups(garment: SceneGarment, maps: list[dict], stiffness: float) -> list[tuple[np.ndarray, float]]:
    """`pin_mode` ATTACH: [(particles, N/m)] from the pin map, `stiffness` times the painted
    weight (weight 1 pins and each rounded soft weight a group)."""
    hard, soft = pin_sets(garment, maps)
    groups = [(hard, float(stiffness))] if len(hard) else []
    return groups + [(p, float(stiffness) * w) for w, p in soft]


def apply_pins(sim, garment: SceneGarment, maps: list[dict]) -> None:
    """`pin_mode` FIXED: pins at the particles' current positions (where the artist placed the
    garment), held there in world space from the first frame."""
    hard, soft = pin_sets(garment, maps)
    pos = garment.positions
    if len(hard):
        sim.pin(hard.astype(np.int64), pos[hard])
    for weight, particles in soft:
        sim.add_attachments(particles.astype(np.int64), pos[particles], weight)


def triangle_size_spread(vertices: np.ndarray, triangles: np.ndarray) -> dict:
    """How even a mesh's triangles are (the spatial hash wants them even, paper Sec. 6):
    mean edge length, its coefficient of variation and the 95th/5th percentile ratio."""
    v = np.asarray(vertices, np.float64).reshape(-1, 3)
    t = np.asarray(triangles, np.int64).reshape(-1, 3)
    if len(t) == 0:
        return {"triangles": 0, "edge_mean": 0.0, "edge_cv": 0.0, "edge_p95_p5": 0.0}
    e = np.concatenate([np.linalg.norm(v[t[:, i]] - v[t[:, (i + 1) % 3]], axis=1) for i in range(3)])
    p5, p95 = np.percentile(e, [5, 95])
    return {
        "triangles": int(len(t)),
        "edge_mean": float(e.mean()),
        "edge_cv": float(e.std() / e.mean()) if e.mean() > 0 else 0.0,
        "edge_p95_p5": float(p95 / p5) if p5 > 0 else float("inf"),
    }


def split_pieces(positions: np.ndarray, offsets: np.ndarray, total: int) -> list[np.ndarray]:
    """Concatenated per-particle rows back into one array per piece."""
    ends = list(offsets[1:]) + [total]
    return [positions[..., int(a) : int(b), :] for a, b in zip(offsets, ends)]
