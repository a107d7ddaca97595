"""A Tailor garment file read back into what the scene stores: the inverse of File > Export >
Tailor Garment (`scene_data.garment_file` + `core.simulate.garment_of`).

`read_garment_file(path)` loads the file with the module (`tailor.Garment.load`: a missing,
malformed or truncated file, or a missing .bin, raises `tailor.TailorError` there) and turns it
into plain data, one `ImportedPiece` per piece: the mesh arrays (vertex coordinates in the
piece's own frame), the object transform (its placement), the stored bend in the piece's frame,
its fabric, its painted maps as vertex-group weights and collision levels; plus the seams
resolved on the pieces, the Simulate panel's settings and the collider's painted levels. The
Blender layer (`patterns/import_garment.py`) only writes these into the scene, so everything
here is computed, and every error raised, before the scene changes.

Placements, bends and meshers come from the module's getters (`Garment.placements`, `bends`,
`meshers`), with the file's own rules applied there (a piece's placement falls back on its pattern
piece's; a bend without a `mode` is the paper's rotation, as in files written before the roll).

A piece is meshed by the add-on (`core.piece_mesh`: the resolution a float32 property, the file's
mesher), as after File > Import > Sewing Pattern. A file the add-on exported is meshed alike
vertex for vertex; one written elsewhere at a resolution a float32 cannot hold (or with other
meshing options) gets another mesh: its painted values are carried to the nearest vertices (in
the rest frame, as Set Resolution carries them) and its shape as placed is not kept (placement
and bend are applied again), with a warning.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

import tailor

from .errors import AddonError
from .garment import SeamData, piece_mesh, remap_seam_modes, resolve
from .layout import Y_UP_TO_Z_UP, euler_of, rotation_matrix, side_by_side
from .mesh_arrays import MeshArrays, mesh_arrays
from .paint import BY_KEY, unpainted, weights
from .simulate import PieceFabric, setup_fabrics, setup_settings

#: `read_garment_file`'s `up`: the file's own axis (AUTO), or Y or Z whatever it says.
UP_AXES = ("AUTO", "Y", "Z")
#: The finest resolution a piece object holds (`TailorPieceSettings.edge_length`'s minimum,
#: which Blender would otherwise clamp to silently), metres.
MIN_EDGE = 0.001


@dataclass
class PieceBend:
    """A piece's stored bend (`Object.tailor_piece.bend_*`), its axis in the piece's own frame."""

    angle: float  # radians
    axis_point: tuple[float, float, float]
    axis_direction: tuple[float, float, float]
    symmetry: tuple[tuple[float, float], tuple[float, float]] | None
    threshold: float
    rolled: bool
    radius: float | None = None  # the roll's cylinder (None: from the angle)
    taper: float = 0.0  # radians: the cone's half-angle (0: a cylinder)


@dataclass
class ImportedPiece:
    """One piece object to create: what `Object.tailor_piece`, the mesh and the transform hold."""

    name: str
    piece_json: str
    edge_length: float  # as the float32 property holds it
    mesher: int
    contour_length: float
    arrays: MeshArrays  # `co`: the piece in its own frame, as it stands
    location: tuple[float, float, float]
    rotation: tuple[float, float, float]  # Euler radians, `layout.PLACEMENT_ROTATION_MODE`
    bend: PieceBend | None
    fabric: PieceFabric
    #: Vertex group name -> (vertex indices, weights): the painted weight maps; a group the
    #: file paints nowhere (every value the unpainted one) is there with no vertex.
    groups: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    levels: np.ndarray | None = None  # `tailor_collision_level`, int32 per vertex


@dataclass
class ImportedGarment:
    name: str  # the setup's name (the file's stem on export)
    pieces: list[ImportedPiece]
    seams: list[SeamData]
    resolved: list[dict]  # `tailor.Seam.resolve` of each seam on the pieces' meshes
    settings: dict  # `Scene.tailor_simulate` property -> value
    garment: tailor.Garment
    warnings: list[str] = field(default_factory=list)

    @property
    def painted_maps(self) -> int:
        """How many painted maps the pieces receive (vertex groups and level attributes)."""
        return sum(len(p.groups) + (p.levels is not None) for p in self.pieces)

    @property
    def collider_vertices(self) -> int | None:
        """The vertex count of the collider the file's painted levels belong to, or None."""
        levels = self.garment.setup.get("collider_levels")
        return int(levels["vertices"]) if levels else None

    def collider_levels(self, collider: str | None, num_vertices: int) -> tuple[np.ndarray | None, str | None]:
        """(levels, None) for the scene's collider `collider` of `num_vertices` vertices when the
        file's levels were painted on a mesh of that count, else (None, why they were not
        applied); (None, None) when the file has none."""
        n = self.collider_vertices
        if n is None:
            return None, None
        if collider is not None and num_vertices == n:
            levels, _ = self.garment.collider_levels(n)
            return np.asarray(levels, np.int32), None
        where = (f"the scene's collider '{collider}' has {num_vertices}" if collider is not None
                 else "the scene has no collider")
        return None, (f"the file's collider collision levels were not applied: they were painted on a collider of "
                      f"{n} vertices and {where} (mark the collider they belong to, then import again, or paint them)")


def turns_up(up: str, stated: str | None) -> bool:
    """Whether the file's placed pieces are turned from Y up to Blender's Z up: as `up` says,
    or (AUTO) as the file states; a file that states nothing is taken as Y up (GarmentCode's,
    as `tailor import` and the sample garments write it)."""
    if up not in UP_AXES:
        raise AddonError(f"unknown up axis '{up}'", f"Pick one of {', '.join(UP_AXES)}")
    if up != "AUTO":
        return up == "Y"
    return stated != "z"


@dataclass
class _Frame:
    """A piece object's transform: world = rotation · local + location (float32 as stored)."""

    location: np.ndarray
    euler: np.ndarray
    turn: np.ndarray  # file -> scene coordinates of this piece's world values

    @property
    def rotation(self) -> np.ndarray:
        return rotation_matrix(self.euler)

    def local_points(self, world: np.ndarray) -> np.ndarray:
        """Points given in the file's world coordinates, in the piece's own frame."""
        return (np.asarray(world, np.float64) @ self.turn.T - self.location) @ self.rotation

    def local_direction(self, world: np.ndarray) -> np.ndarray:
        return np.asarray(world, np.float64) @ self.turn.T @ self.rotation


def piece_frame(placement: dict | None, turn: bool, beside: tuple[float, float, float]) -> _Frame:
    """The object transform of a piece: its placement (turned to Z up with `turn`), or the
    side-by-side location `beside` for a piece without one (never turned: flat in the XY plane,
    as Import Sewing Pattern and the module lay such pieces out)."""
    if placement is None:
        return _Frame(np.asarray(beside, np.float32).astype(np.float64), np.zeros(3), np.eye(3))
    t = np.asarray(placement["translation"], np.float64)
    euler = np.radians(np.asarray(placement["rotation_deg"], np.float64))
    up = Y_UP_TO_Z_UP if turn else np.eye(3)
    if turn:
        t, euler = up @ t, np.asarray(euler_of(up @ rotation_matrix(euler)))
    # The local coordinates are computed with the transform as Blender stores it (float32).
    return _Frame(t.astype(np.float32).astype(np.float64), euler.astype(np.float32).astype(np.float64), up)


def piece_bend(bend: dict | None, frame: _Frame) -> PieceBend | None:
    """A manifest bend (axis in world coordinates, after placement) as the add-on stores it."""
    if bend is None:
        return None
    sym = bend["symmetry"]
    symmetry = None if sym is None else (tuple(float(c) for c in sym[0]), tuple(float(c) for c in sym[1]))
    point = frame.local_points(np.asarray([bend["axis_point"]], np.float64))[0]
    direction = frame.local_direction(np.asarray(bend["axis_direction"], np.float64))
    return PieceBend(
        angle=math.radians(float(bend["angle_deg"])),
        axis_point=tuple(float(c) for c in point),
        axis_direction=tuple(float(c) for c in direction),
        symmetry=symmetry,
        threshold=float(bend["threshold"]),
        rolled=bend["mode"] == "roll",
        radius=None if bend.get("radius") is None else float(bend["radius"]),
        taper=math.radians(float(bend.get("taper_deg") or 0.0)),
    )


def bent_flat(mesh: tailor.PieceMesh, bend: PieceBend | None) -> np.ndarray:
    """The piece flat in its own frame, bent as stored."""
    co = np.zeros((len(mesh.rest), 3), np.float32)
    co[:, :2] = mesh.rest
    if bend is None:
        return co
    return tailor.bend(co, mesh.rest, bend.axis_point, bend.axis_direction, math.degrees(bend.angle),
                       symmetry=bend.symmetry, threshold=bend.threshold, radius=bend.radius,
                       taper_deg=math.degrees(bend.taper), mode="roll" if bend.rolled else "rotate")


def same_mesh(a: tailor.PieceMesh, b: tailor.PieceMesh) -> bool:
    """Whether per-vertex data of mesh `b` fits mesh `a`: the same triangles over the same rest
    shape (to a float32 step)."""
    if len(a.rest) != len(b.rest) or len(a.triangles) != len(b.triangles):
        return False
    return bool(np.array_equal(a.triangles, b.triangles) and np.allclose(a.rest, b.rest, atol=1e-6))


def nearest_rest(old: np.ndarray, new: np.ndarray) -> np.ndarray:
    """For each rest point of `new`, the index of the nearest rest point of `old`."""
    old, new = np.asarray(old, np.float64), np.asarray(new, np.float64)
    out = np.empty(len(new), np.int64)
    for s in range(0, len(new), 512):  # a few MB at a time, whatever the piece's size
        d = ((new[s:s + 512, None, :] - old[None, :, :]) ** 2).sum(axis=2)
        out[s:s + 512] = d.argmin(axis=1)
    return out


def remeshed_warning(names: list[str], edges: list[float]) -> str:
    """What changed for pieces the add-on meshes otherwise than the file's writer did."""
    listed = ", ".join(f"'{n}' ({e!r} m)" for n, e in zip(names, edges))
    return (f"{len(names)} piece(s) were meshed by the file's writer otherwise than the add-on meshes them (at a "
            f"resolution a float32 cannot hold, or with other meshing options): {listed}; they were meshed again, "
            "placed and bent as the file says, any painted values carried to the nearest vertices, and a shape "
            "edited by hand is not kept")


def painted_of(name: str, maps: dict, setup: dict) -> tuple[dict, np.ndarray | None, list[str]]:
    """A piece's painted maps from the file ({map: values per vertex}) as vertex groups and
    collision levels. A vertex whose value is what the module gives an unpainted vertex is left
    unpainted, so it follows the panel (the cloth's friction) as before the export."""
    groups, levels, warnings = {}, None, []
    for key, values in maps.items():
        if key == "collision_level":
            levels = np.asarray(values, np.int32)
            continue
        m = BY_KEY.get(key)
        if m is None:
            warnings.append(f"piece '{name}': the painted map '{key}' is not one the add-on paints; left out")
            continue
        values = np.asarray(values, np.float32)
        painted = np.flatnonzero(values != np.float32(unpainted(key, setup["friction"])))
        w, clipped = weights(key, values[painted])
        if clipped:
            warnings.append(f"piece '{name}': {clipped} {m.label} values beyond what a weight holds were clipped")
        groups[m.group] = (painted, w)
    return groups, levels, warnings


def read_garment_file(path: str, up: str = "AUTO") -> ImportedGarment:
    """Everything File > Import > Tailor Garment puts into the scene, computed without touching
    it. Raises `tailor.TailorError` (a missing or malformed file, a missing .bin) or
    `AddonError`."""
    g = tailor.Garment.load(path)
    sources = g.pieces
    placements, bends, meshers = g.placements, g.bends, g.meshers
    setup = g.setup
    turn = turns_up(up, setup.get("up"))
    file_meshes = g.meshes()
    maps: list[dict] = [{} for _ in sources]
    for name, piece, values in g.particle_params:
        maps[piece][name] = np.asarray(values)
    fabrics = setup_fabrics(setup, len(sources))
    warnings = list(g.warnings)

    for s, e in zip(sources, g.edge_lengths):
        if e < MIN_EDGE:
            raise AddonError(f"piece '{s.name}' is meshed at {e * 1000:.3g} mm, finer than the {MIN_EDGE * 1000:g} mm "
                             "a piece object holds", "Write the garment at a coarser resolution")
    meshes = [piece_mesh(s.to_json(), float(np.float32(e)), mesher)
              for s, e, mesher in zip(sources, g.edge_lengths, meshers)]
    remeshed = {i for i, (m, f) in enumerate(zip(meshes, file_meshes)) if not same_mesh(m, f)}
    unplaced = [i for i, placement in enumerate(placements) if placement is None]
    beside = dict(zip(unplaced, side_by_side([np.asarray(meshes[i].rest) for i in unplaced])))

    pieces = []
    for i, (source, placement, stored, mesh) in enumerate(zip(sources, placements, bends, meshes)):
        frame = piece_frame(placement, turn, beside.get(i, (0.0, 0.0, 0.0)))
        bend = piece_bend(stored, frame)
        positions = maps[i].pop("position", None)
        if i in remeshed:
            near = nearest_rest(file_meshes[i].rest, mesh.rest)
            maps[i] = {k: np.asarray(v)[near] for k, v in maps[i].items()}
            positions = None
        if positions is not None:
            co = frame.local_points(np.asarray(positions, np.float64).reshape(-1, 3))
        else:
            co = bent_flat(mesh, bend)
        groups, levels, painted_warnings = painted_of(source.name, maps[i], setup)
        warnings += painted_warnings
        pieces.append(ImportedPiece(
            name=source.name,
            piece_json=source.to_json(),
            edge_length=float(np.float32(g.edge_lengths[i])),
            mesher=meshers[i],
            contour_length=mesh.contour_length,
            arrays=mesh_arrays(mesh, np.asarray(co, np.float32)),
            location=tuple(float(c) for c in frame.location),
            rotation=tuple(float(c) for c in frame.euler),
            bend=bend,
            fabric=fabrics[i],
            groups=groups,
            levels=levels,
        ))

    if remeshed:
        warnings.append(remeshed_warning([sources[i].name for i in sorted(remeshed)],
                                         [g.edge_lengths[i] for i in sorted(remeshed)]))
    seams = [SeamData.from_tailor(s) for s in g.seams]
    if remeshed:
        seams = remap_seam_modes(seams, meshes, remeshed)
    resolved = [resolve(s, meshes) for s in seams]
    return ImportedGarment(str(setup.get("name") or ""), pieces, seams, resolved, setup_settings(setup), g, warnings)
