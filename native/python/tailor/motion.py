"""A collider's vertex positions per frame, from files: the one collider motion of the package.

Every driver that simulates a garment on a collider read from disk (``tailor simulate``, the
demo in ``demo/``, the samples' builder, the drape suite) needs the same thing: the collider's
triangles, its rest pose and its vertices at frame ``f``. ``ColliderMotion`` gives them for the
three kinds of input, so that the rule for each is written once:

* ``"static"``: a mesh (OBJ, PLY, or a glTF/GLB without animation): the same vertices at every
  frame;
* ``"cache"``: a PC2 point cache of the mesh's vertices, one frame per simulation frame (its
  vertex count must match the mesh's);
* ``"skin"``: a glTF/GLB skin animation (``tailor.AnimatedMesh``), chosen by name (default the
  file's first clip), sampled at ``frame / fps`` seconds.

``rest`` is the mesh as stored (a glTF's rest pose, before any clip), which is where a garment
placed for that pose assembles; ``tailor.bake.Bake`` takes it as its ``assembly`` pose. Past the
end of a clip or cache the last pose holds, or, with ``loop``, the motion starts over.

A collider whose up axis is not the garment's (a Y-up glTF body, a garment the Blender add-on
exported, Z up) is turned into the garment's coordinates with ``turn_up`` (``tailor simulate``
does when the garment file states its up axis): a rotation about X, so triangles keep their
winding and the turned body faces the way the garment was placed round it.

The positions go to ``tailor.bake.Bake`` (``lambda f: [motion.at(f)]``), which sets them on the
solver; nothing here touches a simulation.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from tailor._tailor import AnimatedMesh, InvalidParameterError, check_playback, read_mesh, read_pc2

GLTF = (".glb", ".gltf")


def turn_up(points: np.ndarray, frm: str, to: str) -> np.ndarray:
    """`points` ((n, 3)) from coordinates with `frm` up ("y" or "z") into coordinates with `to`
    up: Y up to Z up is (x, y, z) -> (x, -z, y), as Blender's glTF importer maps glTF; Z up to Y
    up the inverse, (x, y, z) -> (x, z, -y). Both are rotations (determinant 1)."""
    for axis in (frm, to):
        if axis not in ("y", "z"):
            raise InvalidParameterError(f"up axis '{axis}': expected 'y' or 'z'")
    p = np.asarray(points, np.float32)
    if frm == to:
        return p
    if frm == "y":
        return np.ascontiguousarray(np.stack([p[:, 0], -p[:, 2], p[:, 1]], axis=1), np.float32)
    return np.ascontiguousarray(np.stack([p[:, 0], p[:, 2], -p[:, 1]], axis=1), np.float32)


class ColliderMotion:
    """The vertices of collider mesh `path` at every frame.

    `cache`: a PC2 file of its vertices per frame (it wins over a glTF's animation).
    `animation`: the glTF clip to play, by name (None: the first; the file must be a glTF with
    that clip). `fps`: frames per second of the simulation (a skin is sampled at `frame / fps`
    seconds). `loop`: past the clip's or cache's end, start over (else hold the last pose).

    Attributes: `path`, `kind` ("static", "cache" or "skin"), `triangles` ((m, 3) uint32),
    `rest` ((n, 3) float32: the mesh as stored, a glTF's rest pose), `animations` (a glTF's
    clip names, in the file's order), `animation` (the clip that plays, None unless "skin"),
    `duration` (its length in seconds; 0 unless "skin"), `frames` (the cache's frame count, 0
    unless "cache")."""

    def __init__(self, path: str | os.PathLike, cache: str | os.PathLike | None = None, *,
                 animation: str | None = None, fps: float = 30.0, loop: bool = False):
        check_playback(fps)
        self.path, self.fps, self.loop = os.fspath(path), float(fps), bool(loop)
        self.animations: list[str] = []
        self.animation: str | None = None
        self.duration = 0.0
        self._skin: AnimatedMesh | None = None
        self._clip = 0
        self._cache: np.ndarray | None = None
        if Path(self.path).suffix.lower() in GLTF:
            scene = AnimatedMesh(self.path)
            self.triangles = np.asarray(scene.triangles, np.uint32)
            self.rest = np.asarray(scene.positions_at(0.0, None), np.float32)
            self.animations = [name for name, _ in scene.animations]
            if animation is not None and animation not in self.animations:
                have = ", ".join(f"'{n}'" for n in self.animations) or "none"
                raise InvalidParameterError(f"{self.path}: no animation '{animation}' (its animations: {have})")
            if self.animations and cache is None:
                self._skin, self._clip = scene, self.animations.index(animation) if animation is not None else 0
                self.animation = self.animations[self._clip]
                self.duration = float(scene.animations[self._clip][1])
        else:
            if animation is not None:
                raise InvalidParameterError(f"{self.path}: animation '{animation}' asked of a mesh that is not glTF "
                                            "(only a glTF/GLB file holds skin animations)")
            self.rest, self.triangles = read_mesh(self.path)
            self.triangles = np.asarray(self.triangles, np.uint32)
        if cache is not None:
            if animation is not None:
                raise InvalidParameterError(f"{os.fspath(cache)}: a PC2 cache and animation '{animation}' both given "
                                            "for the collider: one motion at a time")
            frames = read_pc2(cache)["frames"]
            if frames.shape[1] != len(self.rest):
                raise InvalidParameterError(f"{os.fspath(cache)}: the cache has {frames.shape[1]} points but "
                                            f"{self.path} has {len(self.rest)} vertices")
            self._cache = frames
        self.frames = 0 if self._cache is None else len(self._cache)
        self._turn: tuple[str, str] | None = None

    def turn(self, frm: str, to: str) -> None:
        """From now on every pose (and `rest`) comes turned from `frm` up to `to` up (`turn_up`)."""
        base = self.rest if self._turn is None else turn_up(self.rest, self._turn[1], self._turn[0])
        turn_up(base[:0], frm, to)  # checks the axes before anything changes
        self._turn = None if frm == to else (frm, to)
        self.rest = turn_up(base, frm, to)

    @property
    def kind(self) -> str:
        return "cache" if self._cache is not None else "skin" if self._skin is not None else "static"

    @property
    def num_vertices(self) -> int:
        return len(self.rest)

    def pose(self, t: float) -> np.ndarray:
        """The vertices at `t` seconds of the motion ((n, 3) float32)."""
        if self._skin is not None:
            if self.loop:
                t = t % self.duration if self.duration > 0 else 0.0
            return self._turned(self._skin.positions_at(t, self._clip))
        return self.at(int(round(t * self.fps)))

    def _turned(self, points: np.ndarray) -> np.ndarray:
        return points if self._turn is None else turn_up(points, *self._turn)

    def at(self, frame: int) -> np.ndarray:
        """The vertices at simulation frame `frame` (0 is the motion's start), (n, 3) float32."""
        if frame < 0:
            raise InvalidParameterError(f"collider {self.path}: frame {frame} is before the motion's start (0)")
        if self._cache is not None:
            k = frame % len(self._cache) if self.loop else min(frame, len(self._cache) - 1)
            return self._turned(self._cache[k])
        if self._skin is not None:
            return self.pose(frame / self.fps)
        return self.rest
