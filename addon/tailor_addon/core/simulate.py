"""From the Simulate panel's settings and the scene's arrays to a ready `tailor.Simulation`.

Bpy-free: the Blender layer (`simulate/`) reads the panel, the pieces' fabric, the painted
maps and the colliders' evaluated meshes into the plain structures below; this module puts
them into a `tailor.Garment` (the pieces as they stand, its typed `setup`, the painted maps)
and the module builds and configures the simulation in Rust (`Garment.build_simulation`), the
one place where that happens: a garment file exported from the scene (`garment_of`, with its
placements and bends) simulates in `tailor simulate` exactly as here. The Bake and Live modes
drive the result through `tailor.bake.Bake`. Everything is validated before anything in the
scene changes, so a bad setting is a report and the scene stays as it was.

Pins (`SimSettings.pin_mode`): `ATTACH` (default) makes the painted pins ride on the first
collider (the character): `tailor.bake.Bake` attaches them (`Garment.attach_groups`: the pin
stiffness times the painted weight) once every seam has met; `FIXED` holds them where they were
placed from the first frame (weight 1 hard, lighter ones softly).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

import tailor
from tailor import bake

from .errors import AddonError
from .garment import SceneGarment

#: The quality presets the panel offers, by its names (`tailor.Settings.preset`'s, upper case).
PRESETS = tuple(name.upper() for name in tailor.Settings.presets())

#: How painted pins hold (`SimSettings.pin_mode`): riding on the collider, or fixed in place.
PIN_MODES = ("ATTACH", "FIXED")

_FINAL = tailor.Settings.preset("final")


def preset_values(name: str) -> dict:
    """Substeps, iterations and tolerance of preset `name` (`PREVIEW`/`FINAL`), the module's."""
    if name not in PRESETS:
        raise AddonError(f"unknown quality preset '{name}'", f"Pick one of {', '.join(PRESETS)}")
    s = tailor.Settings.preset(name.lower())
    return {"substeps": s.substeps, "iterations": s.iterations, "tolerance": s.tolerance}


def adapter_of(sim) -> str:
    """The backend and adapter a simulation runs on, as the module reports them."""
    return f"{sim.backend.upper()}{f' ({sim.adapter})' if sim.adapter else ''}"


@dataclass
class SimSettings:
    """The Simulate panel's settings (SI units)."""

    substeps: int = _FINAL.substeps
    iterations: int = _FINAL.iterations
    tolerance: float = _FINAL.tolerance
    two_level: bool = False  # the two-level global step (tailor.Settings.two_level)
    backend: str = "auto"  # auto | cpu | gpu
    threads: int | None = None  # the solver's CPU threads (None: one per core)
    gravity: tuple[float, float, float] = (0.0, 0.0, -9.81)
    air_damping: float | None = None
    ramp_enabled: bool = True
    ramp_closing_speed: float | None = None
    ramp_closing_damping: float | None = None
    thickness: float = tailor.DEFAULT_THICKNESS
    self_collision: bool = False
    self_collision_radius: float = 0.0  # spheres: radius, 0: half the mean rest edge; triangles: 0: 4 mm
    self_collision_contacts: str = "SPHERES"  # SPHERES | TRIANGLES (tailor's "spheres" | "triangles")
    fps: float = 30.0
    seam_stiffness: float = tailor.DEFAULT_SEAM_STIFFNESS  # the gap of a closed seam is tension / stiffness
    seam_bend_stiffness: float = tailor.DEFAULT_SEAM_BEND_STIFFNESS
    friction_static: float = tailor.DEFAULT_FRICTION[0]
    friction_kinetic: float = tailor.DEFAULT_FRICTION[1]
    pin_mode: str = "ATTACH"  # ATTACH: ride on the collider once the seams meet | FIXED: held in place
    pin_stiffness: float = tailor.DEFAULT_PIN_STIFFNESS  # N/m per pin at weight 1

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
            two_level=bool(self.two_level),
        )
        for name in ("air_damping", "ramp_closing_speed", "ramp_closing_damping"):
            v = getattr(self, name)
            if v is not None:
                kw[name] = float(v)
        return tailor.Settings(**kw)

    def setup(self, name: str, fabrics: list["PieceFabric"]) -> dict:
        """The garment's setup (`tailor.Garment.setup`) these settings and the pieces' fabric
        make (the collider's levels: `Garment.set_collider_levels`)."""
        if self.pin_mode not in PIN_MODES:
            raise tailor.InvalidParameterError(f"pin mode is '{self.pin_mode}': must be one of {', '.join(PIN_MODES)}")
        return {
            "name": name,
            "fabrics": [f.entry() for f in fabrics],
            "thickness": float(self.thickness),
            "friction": {"static": float(self.friction_static), "kinetic": float(self.friction_kinetic)},
            "self_collision": bool(self.self_collision),
            "self_collision_radius": float(self.self_collision_radius),
            "self_collision_contacts": self.self_collision_contacts.lower(),
            "pin_mode": self.pin_mode.lower(),
            "pin_stiffness": float(self.pin_stiffness),
            "seam_stiffness": float(self.seam_stiffness),
            "seam_bend_stiffness": float(self.seam_bend_stiffness),
            "up": "z",  # Blender's world: `tailor simulate` turns a Y-up collider to match
        }


def setup_settings(setup: dict) -> dict:
    """The Simulate panel's settings (`Scene.tailor_simulate`, by property name) that give a
    garment's setup: the inverse of `SimSettings.setup` (a garment file read back). The setup's
    name, fabrics and collider levels belong to the pieces and the collider, not the panel."""
    return {
        "thickness": float(setup["thickness"]),
        "friction_static": float(setup["friction"]["static"]),
        "friction_kinetic": float(setup["friction"]["kinetic"]),
        "self_collision": bool(setup["self_collision"]),
        "self_collision_radius": float(setup["self_collision_radius"]),
        "self_collision_contacts": str(setup.get("self_collision_contacts", "spheres")).upper(),
        "pin_mode": str(setup["pin_mode"]).upper(),
        "pin_stiffness": float(setup["pin_stiffness"]),
        "seam_stiffness": float(setup["seam_stiffness"]),
        "seam_bend_stiffness": float(setup["seam_bend_stiffness"]),
    }


@dataclass
class PieceFabric:
    density: float
    stretch: float
    shear: float
    bend: float
    # An anisotropic fabric's other directions (None: isotropic; `tailor.Fabric` says which).
    stretch_v: float | None = None
    bend_bias: float | None = None
    bend_v: float | None = None

    def entry(self) -> dict:
        """The garment setup's entry for this fabric (the directions only where given)."""
        e = {"density": self.density, "stretch": self.stretch, "shear": self.shear, "bend": self.bend}
        e.update({k: float(getattr(self, k)) for k in ANISOTROPIC if getattr(self, k) is not None})
        return e


#: The fields that make a fabric anisotropic (`tailor.Fabric`'s optional directions).
ANISOTROPIC = ("stretch_v", "bend_bias", "bend_v")


def setup_fabrics(setup: dict, count: int) -> list[PieceFabric]:
    """Each of `count` pieces' fabric in a garment's setup (an empty list: the module's default
    fabric for every piece, as `Garment.build_simulation` reads it)."""
    given = setup.get("fabrics") or []
    if given and len(given) != count:
        raise AddonError(f"the garment's setup has {len(given)} fabrics for {count} pieces",
                         "Export the garment again")
    if not given:
        d = tailor.Fabric()
        return [PieceFabric(d.density, d.stretch, d.shear, d.bend) for _ in range(count)]
    return [PieceFabric(float(f["density"]), float(f["stretch"]), float(f["shear"]), float(f["bend"]),
                        *(None if f.get(k) is None else float(f[k]) for k in ANISOTROPIC)) for f in given]


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
    #: The garment the simulation was built from (Live re-applies edited parts of it).
    garment: tailor.Garment | None = None


def paint(g: tailor.Garment, maps: list[dict]) -> None:
    """The pieces' painted maps (`paint/maps.py`: {name: (values, painted)} per piece) onto
    `g` (every map replaced)."""
    for name in tailor.PAINTED_MAPS:
        if name != "position":
            g.clear_painted(name)
    for piece, m in enumerate(maps):
        for name, (values, painted) in m.items():
            g.set_painted(name, piece, np.asarray(values), np.asarray(painted, bool))


def garment_of(g: tailor.Garment, name: str, settings: SimSettings, fabrics: list[PieceFabric], maps: list[dict],
               collider_levels: np.ndarray | None = None) -> tailor.Garment:
    """`g` (the scene's pieces and seams as a `tailor.Garment`) with the setup and painted maps
    the panels give it: what the add-on simulates and what it exports."""
    if len(fabrics) != len(g.pieces) or len(maps) != len(g.pieces):
        raise AddonError("fabric or painted maps missing for some pieces", "Re-import the garment")
    g.setup = settings.setup(name, fabrics)
    g.set_collider_levels(collider_levels)
    paint(g, maps)
    return g


def build(
    garment: SceneGarment,
    settings: SimSettings,
    fabrics: list[PieceFabric],
    maps: list[dict],
    colliders: list[ColliderData],
) -> Built:
    """The simulation of `garment` on `colliders` with everything the panels set. Raises
    `AddonError`/`tailor.TailorError` naming the offending piece, collider or setting."""
    for c in colliders:
        bake.check_collider_positions(c.name, c.positions, len(c.positions))
        if len(c.triangles) == 0:
            raise AddonError(f"collider '{c.name}' has no faces", "Pick a mesh with faces as collider")
    g = garment_of(garment.tailor_garment(), "", settings, fabrics, maps)
    sim, _offsets = g.build_simulation(settings=settings.to_tailor(), backend=settings.backend, ride=bool(colliders))
    if settings.threads is not None:
        sim.set_threads(settings.threads)
    warnings = list(garment.warnings) + list(g.build_warnings)
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
    attach = settings.pin_mode == "ATTACH" and bool(colliders)
    pins = bake.ColliderPins(out[0].id, g.attach_groups()) if attach else None
    return Built(sim, out, warnings, adapter_of(sim), pins, g)


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
