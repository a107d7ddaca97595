"""A simulated garment as meshes for other programs: welded along its seams by default, or piece
by piece on request (``tailor simulate -o``, ``--usd``, ``--obj-dir``; ``--per-piece``).

The simulation's particles are the pieces' vertices, so a seam is two rows of vertices in the
same place: exported as they are, the pieces show a crack along every seam once shaded.
``WeldedGarment`` welds them once (``tailor.weld``: one vertex where a seam's two sides meet)
and carries each frame's positions over (``WeldedMesh.apply``); the pattern's flat rest
coordinates become UVs per face corner (a seam's two sides keep their own). ``PieceGarment`` is
the other face of the same output: the pieces as the solver holds them, one part each, for a
pipeline that keeps them as separate objects (the add-on's bake does, to play each piece).

Both are an *export shape*: ``num_vertices``, ``triangles`` and ``corner_uvs`` of the whole,
``points(positions)`` for a frame, and ``parts``, the named meshes a format that has objects
writes (one for the welded garment, one per piece). The vertex order of a PC2 cache is
``points``'; ``write_mesh`` writes the mesh it deforms.
``ObjSequence`` writes one OBJ a frame and part (``tailor.write_obj``, atomic), the form every
DCC imports without a plug-in; ``tailor.usd.UsdCache`` writes USD.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from tailor._tailor import Simulation, weld, write_obj


@dataclass(frozen=True)
class Part:
    """One named mesh of an export shape: its vertices are ``points(...)[start:start + count]``;
    `triangles` index them from 0; `corner_uvs` (3 per triangle)."""

    name: str
    start: int
    count: int
    triangles: np.ndarray
    corner_uvs: np.ndarray


def _corner_uvs(rest: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(rest[triangles.reshape(-1).astype(np.int64)], np.float32).reshape(-1, 2)


class WeldedGarment:
    """`sim`'s garment welded along its seams: `triangles` (m', 3), `corner_uvs` (3m', 2),
    `num_vertices`, `parts` (one: the garment, named `name`) and `points(positions)` for a
    frame. The weld's topology is the garment's alone (seam pairs and triangles), so two runs of
    one garment file weld alike, as a resumed cache needs."""

    def __init__(self, sim: Simulation, name: str = "garment"):
        triangles = np.asarray(sim.triangles, np.uint32)
        self.weld = weld(sim.positions, triangles, sim.seam_pairs())
        self.triangles = np.asarray(self.weld.triangles, np.uint32)
        rest = np.asarray(sim.rest, np.float32)
        self.corner_uvs = np.asarray(self.weld.apply_corners(_corner_uvs(rest, triangles)), np.float32).reshape(-1, 2)
        self.num_vertices = int(self.weld.num_vertices)
        self.parts = [Part(name, 0, self.num_vertices, self.triangles, self.corner_uvs)]

    def points(self, positions: np.ndarray) -> np.ndarray:
        """A frame's particle positions ((n, 3)) as the welded mesh's points ((k, 3) float32)."""
        return np.ascontiguousarray(self.weld.apply(np.asarray(positions, np.float32)), np.float32)

    def values(self, per_particle: np.ndarray) -> np.ndarray:
        """A per-particle value ((n,), a fit map) at the welded points ((k,) float32)."""
        v = np.asarray(per_particle, np.float32)
        return np.ascontiguousarray(self.weld.apply(np.repeat(v[:, None], 3, axis=1))[:, 0], np.float32)


class PieceGarment:
    """`sim`'s pieces as the solver holds them (per piece, on request): the particles themselves,
    piece after piece in the garment file's order; `parts` one per piece (`names`, `counts` of
    vertices and `triangle_counts`, as `Garment.meshes()` gives them), each with its own
    triangles and its pattern's UVs."""

    def __init__(self, sim: Simulation, names: list[str], counts: list[int], triangle_counts: list[int]):
        triangles = np.asarray(sim.triangles, np.uint32)
        if sum(counts) != sim.num_particles or sum(triangle_counts) != len(triangles):
            raise ValueError(f"the pieces hold {sum(counts)} vertices and {sum(triangle_counts)} triangles, the "
                             f"simulation {sim.num_particles} and {len(triangles)}")
        rest = np.asarray(sim.rest, np.float32)
        self.triangles = triangles
        self.corner_uvs = _corner_uvs(rest, triangles)
        self.num_vertices = int(sim.num_particles)
        self.parts, v, t = [], 0, 0
        for name, n, m in zip(_unique(names), counts, triangle_counts):
            tris = triangles[t:t + m].astype(np.int64) - v
            if len(tris) and (tris.min() < 0 or tris.max() >= n):
                raise ValueError(f"piece {name!r}: its triangles reach outside its {n} vertices")
            self.parts.append(Part(name, v, n, tris.astype(np.uint32), self.corner_uvs[3 * t:3 * (t + m)]))
            v, t = v + n, t + m

    @classmethod
    def of_garment(cls, sim: Simulation, garment) -> "PieceGarment":
        """The pieces of `garment` (a `tailor.Garment`, as built into `sim`)."""
        meshes = garment.meshes()
        return cls(sim, [p.name for p in garment.pieces], [len(m.rest) for m in meshes],
                   [len(m.triangles) for m in meshes])

    def points(self, positions: np.ndarray) -> np.ndarray:
        return np.ascontiguousarray(np.asarray(positions, np.float32).reshape(-1, 3))

    def values(self, per_particle: np.ndarray) -> np.ndarray:
        return np.ascontiguousarray(per_particle, np.float32)


def write_mesh(path: str | os.PathLike, shape, positions: np.ndarray) -> None:
    """The mesh a cache of `shape` deforms, at `positions` (particles), as one OBJ with UVs
    (atomic): every part in one object, in the cache's vertex order."""
    write_obj(os.fspath(path), shape.points(positions), shape.triangles, shape.corner_uvs)


class ObjSequence:
    """One OBJ a frame in `folder`, the export shape `garment` with its UVs: `NAME.0001.obj` for
    frame 1 (`start_frame` on) when it is one part (welded), `NAME.PIECE.0001.obj` a part
    otherwise."""

    def __init__(self, folder: str | os.PathLike, garment, name: str = "garment", start_frame: int = 1):
        self.folder, self.garment, self.name = os.fspath(folder), garment, name
        self.next_frame = int(start_frame)
        os.makedirs(self.folder, exist_ok=True)

    def path(self, frame: int, part: Part | None = None) -> str:
        stem = self.name if part is None or len(self.garment.parts) == 1 else f"{self.name}.{_file_name(part.name)}"
        return os.path.join(self.folder, f"{stem}.{frame:04d}.obj")

    def add(self, positions: np.ndarray) -> list[str]:
        """Writes the next frame; returns its paths (one a part)."""
        points, paths = self.garment.points(positions), []
        for part in self.garment.parts:
            path = self.path(self.next_frame, part)
            write_obj(path, points[part.start:part.start + part.count], part.triangles, part.corner_uvs)
            paths.append(path)
        self.next_frame += 1
        return paths


def _unique(names: list[str]) -> list[str]:
    """`names` with a repeated one numbered (``sleeve``, ``sleeve.001``), as Blender names objects."""
    seen: set[str] = set()
    out = []
    for name in names:
        n, k = name or "piece", 0
        while n in seen:
            k += 1
            n = f"{name or 'piece'}.{k:03d}"
        seen.add(n)
        out.append(n)
    return out


def _file_name(name: str) -> str:
    """`name` as part of a file name (letters, digits, '-' and '_')."""
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in name) or "piece"
