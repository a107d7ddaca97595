"""From what the scene stores to the module's objects: piece meshes, seams, a Simulation.

The scene keeps, per piece, the pattern piece itself (`Piece.to_json()`) and its resolution;
the piece mesh is rebuilt from them with `tailor.triangulate`, which is deterministic, so vertex
`i` of the Blender mesh is vertex `i` of the rebuilt `PieceMesh`. Seams are kept as the
module's resolution-independent sides (rest-frame endpoints and a walking direction), so
resolving them on the current meshes is also how they are remapped after a change of
resolution. This module only calls `tailor`; it holds no geometry of its own.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

import tailor

from .errors import AddonError


@dataclass
class PieceData:
    """One piece object, read from the scene: `positions` are world-space (n, 3) float32."""

    name: str
    piece_json: str
    edge_length: float
    positions: np.ndarray
    rest: np.ndarray | None = None
    mesher: int = tailor.MESHER_VERSION  # the mesher that made its mesh (`tailor.triangulate`)


@dataclass
class SeamSide:
    piece: int  # index into the list of pieces passed alongside
    start: tuple[float, float]
    end: tuple[float, float]
    direction: str  # "ccw" or "cw"

    def as_dict(self) -> dict:
        return {"piece": self.piece, "start": list(self.start), "end": list(self.end), "direction": self.direction}

    @staticmethod
    def from_dict(d: dict) -> "SeamSide":
        start, end = (float(d["start"][0]), float(d["start"][1])), (float(d["end"][0]), float(d["end"][1]))
        return SeamSide(int(d["piece"]), start, end, str(d["direction"]))


@dataclass
class SeamData:
    """One stored seam; `stiffness` and `bend_stiffness` are factors on the solver's."""

    name: str
    a: SeamSide
    b: SeamSide
    mode: str = "equal"
    stiffness: float = 1.0
    bend_stiffness: float = 1.0

    def to_tailor(self) -> tailor.Seam:
        return tailor.Seam(
            self.name, self.a.as_dict(), self.b.as_dict(), self.mode, float(self.stiffness), float(self.bend_stiffness)
        )

    @staticmethod
    def from_tailor(seam: tailor.Seam) -> "SeamData":
        return SeamData(
            seam.name,
            SeamSide.from_dict(seam.a),
            SeamSide.from_dict(seam.b),
            seam.mode,
            seam.stiffness,
            seam.bend_stiffness,
        )

    def flipped(self) -> "SeamData":
        """The same seam with side B walked the other way (its start and end swapped)."""
        b = SeamSide(self.b.piece, self.b.end, self.b.start, "cw" if self.b.direction == "ccw" else "ccw")
        return SeamData(self.name, self.a, b, self.mode, self.stiffness, self.bend_stiffness)


@lru_cache(maxsize=64)
def _triangulated(piece_json: str, edge: float, mesher: int) -> tailor.PieceMesh:
    return tailor.triangulate(tailor.Piece.from_json(piece_json), float(edge), mesher=int(mesher))


def piece_mesh(piece_json: str, edge: float, mesher: int) -> tailor.PieceMesh:
    """The piece's mesh at `edge` metres made by mesher `mesher` (memoised: the draw handler and
    operators ask often).

    `edge` must be the stored value itself (a float32 property): the triangulation depends on
    its last bits, so the same value must be used at import and at every rebuild; `mesher` is
    the one the piece was made with (`tailor.MESHER_VERSION` for a piece imported today), so a
    piece saved by an older version comes back vertex for vertex."""
    return _triangulated(piece_json, float(edge), int(mesher))


def mesh_of(p) -> tailor.PieceMesh:
    """The mesh of a stored piece: anything with `piece_json`, `edge_length` and `mesher` (a
    `PieceData`, or a piece object's `tailor_piece` settings)."""
    return piece_mesh(p.piece_json, p.edge_length, p.mesher)


def resolve(seam: SeamData, meshes: list[tailor.PieceMesh]) -> dict:
    """`tailor.Seam.resolve` of a stored seam on `meshes` (indexed by piece)."""
    return seam.to_tailor().resolve(meshes)


def remap_seam_modes(seams: list[SeamData], meshes: list[tailor.PieceMesh], changed: set[int]) -> list[SeamData]:
    """After pieces `changed` were re-triangulated: an equal-count seam touching them whose
    sides no longer have the same count becomes unequal, one that matches again stays or
    becomes equal (as `Garment.set_resolution` does). Raises if a seam no longer resolves."""
    out = []
    for s in seams:
        if s.a.piece in changed or s.b.piece in changed:
            r = resolve(SeamData(s.name, s.a, s.b, "unequal", s.stiffness, s.bend_stiffness), meshes)
            equal = len(r["a_vertices"]) == len(r["b_vertices"])
            if s.mode == "equal" and not equal:
                s = SeamData(s.name, s.a, s.b, "unequal", s.stiffness, s.bend_stiffness)
        resolve(s, meshes)
        out.append(s)
    return out


@dataclass
class SceneGarment:
    """The garment of a scene, resolved: one sewn cloth mesh over all pieces.

    `offsets[i]` is the first particle of piece `i`; `positions` (world), `rest` and
    `triangles` are the concatenation of the pieces; `seams[k]` resolved is `resolved[k]`
    (piece-local indices, as `tailor.Seam.resolve` returns)."""

    pieces: list[PieceData]
    seams: list[SeamData]
    meshes: list[tailor.PieceMesh]
    resolved: list[dict]
    offsets: np.ndarray
    positions: np.ndarray
    rest: np.ndarray
    triangles: np.ndarray
    warnings: list[str] = field(default_factory=list)
    _tailor: tailor.Garment | None = field(default=None, repr=False, compare=False)
    _pairs: list[dict] | None = field(default=None, repr=False, compare=False)

    @property
    def num_particles(self) -> int:
        return len(self.positions)

    def tailor_garment(self, placements: list | None = None, bends: list | None = None) -> tailor.Garment:
        """The garment as the module's `tailor.Garment`, the pieces as they stand in the scene
        (their positions, used instead of placing them again) and the seams as stored; with
        `placements` and `bends` (per piece, for a garment file) recorded too. Cached for the
        plain case: the module triangulates the pieces once."""
        plain = placements is None and bends is None
        if plain and self._tailor is not None:
            return self._tailor
        g = tailor.Garment.from_parts(
            [tailor.Piece.from_json(p.piece_json) for p in self.pieces],
            [p.edge_length for p in self.pieces],
            [s.to_tailor() for s in self.seams],
            placements=placements,
            bends=bends,
            meshers=[p.mesher for p in self.pieces],
            positions=[np.asarray(p.positions, np.float32).reshape(-1, 3) for p in self.pieces],
        )
        if plain:
            self._tailor = g
        return g

    def seam_pairs(self, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Seam `k`'s sewn points as global (a_vertices, a_weights, b_vertices, b_weights), as
        the module sews them (`Garment.seam_pairs`: a dart's tip, sewn to itself, left out)."""
        if self._pairs is None:
            self._pairs = self.tailor_garment().seam_pairs()
        p = self._pairs[k]
        return (np.asarray(p["a_vertices"], np.int64), np.asarray(p["a_weights"], np.float32),
                np.asarray(p["b_vertices"], np.int64), np.asarray(p["b_weights"], np.float32))

    def build_simulation(
        self,
        fabric: tailor.Fabric | None = None,
        settings: tailor.Settings | None = None,
        seam_stiffness: float | None = None,
        seam_bend_stiffness: float | None = None,
    ) -> tailor.Simulation:
        """A `tailor.Simulation` of the pieces as they stand in the scene, every seam added
        with its own stiffness factors (`Garment.build_simulation`, with the default setup)."""
        sim, _ = self.tailor_garment().build_simulation(fabric, settings, seam_stiffness, seam_bend_stiffness)
        return sim


def garment_from_scene(pieces: list[PieceData], seams: list[SeamData]) -> SceneGarment:
    """Resolves a scene's pieces and seams. Raises `AddonError` when a piece's mesh no longer
    matches its pattern (edited by hand), `tailor.SeamError` when a seam does not resolve."""
    if not pieces:
        raise AddonError("the scene has no garment pieces", "Import a pattern first (File > Import > Sewing Pattern)")
    meshes = []
    for p in pieces:
        m = mesh_of(p)
        n = len(p.positions)
        if n != len(m.rest):
            raise AddonError(
                f"piece '{p.name}' has {n} vertices but its pattern at {p.edge_length * 100:.3g} cm gives "
                f"{len(m.rest)}",
                "Its mesh was edited by hand: set its resolution again (Patterns panel) to rebuild it",
            )
        if p.rest is not None and not np.allclose(p.rest, m.rest, atol=1e-6):
            raise AddonError(
                f"piece '{p.name}': the stored rest shape differs from its pattern",
                "Set its resolution again (Patterns panel) to rebuild it",
            )
        if not np.isfinite(p.positions).all():
            raise AddonError(f"piece '{p.name}' has a non-finite vertex position", "Fix or re-import the piece")
        meshes.append(m)
    resolved = []
    for s in seams:
        for side in (s.a, s.b):
            if not 0 <= side.piece < len(pieces):
                raise AddonError(f"seam '{s.name}' refers to a missing piece", "Delete the seam or re-create it")
        resolved.append(resolve(s, meshes))
    counts = np.array([len(m.rest) for m in meshes], np.int64)
    offsets = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
    positions = np.concatenate([np.asarray(p.positions, np.float32).reshape(-1, 3) for p in pieces])
    rest = np.concatenate([np.asarray(m.rest, np.float32) for m in meshes])
    triangles = np.concatenate([np.asarray(m.triangles, np.int64) + o for m, o in zip(meshes, offsets)])
    return SceneGarment(
        pieces=pieces,
        seams=list(seams),
        meshes=meshes,
        resolved=resolved,
        offsets=offsets,
        positions=positions,
        rest=rest,
        triangles=triangles,
    )
