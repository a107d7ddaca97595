"""A simulated garment as a single mesh for other programs: welded along its seams, with the
pattern's UVs (``tailor simulate --usd`` and ``--obj-dir``).

The simulation's particles are the pieces' vertices, so a seam is two rows of vertices in the
same place: exported as they are, the pieces show a crack along every seam once shaded.
``WeldedGarment`` welds them once (``tailor.weld``: one vertex where a seam's two sides meet)
and carries each frame's positions over (``WeldedMesh.apply``); the pattern's flat rest
coordinates become UVs per face corner (a seam's two sides keep their own).
``ObjSequence`` writes one OBJ a frame (``tailor.write_obj``, atomic), the form every DCC
imports without a plug-in; ``tailor.usd.UsdCache`` writes USD.
"""

from __future__ import annotations

import os

import numpy as np

from tailor._tailor import Simulation, weld, write_obj


class WeldedGarment:
    """`sim`'s garment welded along its seams: `triangles` (m', 3), `corner_uvs` (3m', 2),
    `num_vertices`, and `points(positions)` for a frame."""

    def __init__(self, sim: Simulation):
        triangles = np.asarray(sim.triangles, np.uint32)
        self.weld = weld(sim.positions, triangles, sim.seam_pairs())
        self.triangles = np.asarray(self.weld.triangles, np.uint32)
        rest = np.asarray(sim.rest, np.float32)
        self.corner_uvs = np.asarray(self.weld.apply_corners(rest[triangles.reshape(-1).astype(np.int64)]),
                                     np.float32).reshape(-1, 2)
        self.num_vertices = int(self.weld.num_vertices)

    def points(self, positions: np.ndarray) -> np.ndarray:
        """A frame's particle positions ((n, 3)) as the welded mesh's points ((k, 3) float32)."""
        return np.ascontiguousarray(self.weld.apply(np.asarray(positions, np.float32)), np.float32)


class ObjSequence:
    """One OBJ a frame in `folder`: `NAME.0001.obj` for frame 1 (`start_frame` on), the welded
    garment with its UVs."""

    def __init__(self, folder: str | os.PathLike, garment: WeldedGarment, name: str = "garment",
                 start_frame: int = 1):
        self.folder, self.garment, self.name = os.fspath(folder), garment, name
        self.next_frame = int(start_frame)
        os.makedirs(self.folder, exist_ok=True)

    def path(self, frame: int) -> str:
        return os.path.join(self.folder, f"{self.name}.{frame:04d}.obj")

    def add(self, positions: np.ndarray) -> str:
        """Writes the next frame; returns its path."""
        path = self.path(self.next_frame)
        write_obj(path, self.garment.points(positions), self.garment.triangles, self.garment.corner_uvs)
        self.next_frame += 1
        return path
