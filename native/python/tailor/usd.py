"""A baked garment as USD: one ``UsdGeom.Mesh`` with time-sampled points and normals and the
pattern's UVs, the garment welded along its seams (``tailor.export.WeldedGarment``), or one
mesh per piece on request (``tailor.export.PieceGarment``, ``--per-piece``), the format
Houdini, Maya, Unreal, Omniverse and Blender all read without a plug-in (``tailor simulate
--usd``). With the frame's fit maps (``Simulation.fit_maps``, ``tailor simulate --maps``) each
is a time-sampled per-point primvar too: ``tailor_strain``, ``tailor_pressure`` (pascals) and
``tailor_distance`` (metres to the body), the names the add-on's Live writes. With a
``thickness`` the mesh carries it as the constant primvar ``tailor_thickness`` (metres: the
distance the cloth was simulated keeping from the body, so a shell or solidify of up to that
much at render time stays outside it).

The UVs are ``primvars:st``, ``faceVarying`` (a seam's two sides keep their own). The stage says
its up axis and that a unit is a metre. Frames are added as they are solved (``add``) and the
layer is saved every ``save_every`` frames and at the end (``close``): USD rewrites its file on
each save, so a crash loses at most the frames since the last save. ``pxr`` comes from PyPI's
``usd-core``; it is imported only here.
"""

from __future__ import annotations

import os
from typing import Sequence

import numpy as np

from tailor._tailor import Simulation, TailorIOError
from tailor.export import WeldedGarment


class _MeshPrim:
    """One part's mesh prim (``tailor.export.Part``) and its time-sampled attributes."""

    def __init__(self, stage, path: str, part, Sdf, UsdGeom, Vt, thickness: float | None):
        self.part = part
        self.mesh = UsdGeom.Mesh.Define(stage, path)
        tris = np.asarray(part.triangles, np.int32)
        self.mesh.CreateFaceVertexCountsAttr(Vt.IntArray.FromNumpy(np.full(len(tris), 3, np.int32)))
        self.mesh.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(np.ascontiguousarray(tris.reshape(-1))))
        self.mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
        self.mesh.CreateDoubleSidedAttr(True)
        self.primvars = UsdGeom.PrimvarsAPI(self.mesh)
        st = self.primvars.CreatePrimvar("st", Sdf.ValueTypeNames.TexCoord2fArray, UsdGeom.Tokens.faceVarying)
        st.Set(Vt.Vec2fArray.FromNumpy(np.ascontiguousarray(part.corner_uvs, np.float32)))
        if thickness is not None:
            self.primvars.CreatePrimvar("tailor_thickness", Sdf.ValueTypeNames.Float,
                                        UsdGeom.Tokens.constant).Set(float(thickness))
        self.points = self.mesh.CreatePointsAttr()
        self.extent = self.mesh.CreateExtentAttr()
        # Vertex normals, area-weighted, sampled with the points (a viewer then shades the
        # frames as solved instead of recomputing them from the triangles).
        self.normals = self.mesh.CreateNormalsAttr()
        self.mesh.SetNormalsInterpolation(UsdGeom.Tokens.vertex)
        self.maps: dict = {}


class UsdCache:
    """A USD file of the garment of `sim`, frame by frame: `add(positions)` writes the next time
    sample (frame `start_frame`, then +1 each), `close()` saves. The garment is welded into one
    mesh named `name` unless `garment` gives another export shape (``tailor.export``: a
    ``PieceGarment`` writes one mesh a piece), under ``/Garment``. `up` is "y" or "z";
    `thickness` (metres, optional) is written on every mesh as the constant primvar
    ``tailor_thickness``."""

    def __init__(self, path: str | os.PathLike, sim: Simulation, start_frame: float = 1.0, fps: float = 30.0,
                 up: str = "y", name: str = "garment", save_every: int = 10, thickness: float | None = None,
                 garment=None):
        try:
            from pxr import Gf, Sdf, Usd, UsdGeom, Vt
        except ImportError as exc:  # an optional dependency: say how to get it
            raise TailorIOError(f"{os.fspath(path)}: writing USD needs the `usd-core` package "
                                "(pip install usd-core)") from exc
        if thickness is not None and not (np.isfinite(thickness) and thickness >= 0.0):
            raise ValueError(f"thickness must be finite and >= 0, got {thickness}")
        self._Vt, self._Gf, self._Sdf = Vt, Gf, Sdf
        self.path, self.start_frame, self.save_every = os.fspath(path), float(start_frame), int(save_every)
        self.garment = garment if garment is not None else WeldedGarment(sim, name)
        self.frames = 0
        self.stage = Usd.Stage.CreateNew(self.path) if not os.path.exists(self.path) else None
        if self.stage is None:  # CreateNew refuses an existing file: start it afresh
            layer = Sdf.Layer.FindOrOpen(self.path)
            layer.Clear()
            self.stage = Usd.Stage.Open(layer)
        UsdGeom.SetStageUpAxis(self.stage, UsdGeom.Tokens.y if up == "y" else UsdGeom.Tokens.z)
        UsdGeom.SetStageMetersPerUnit(self.stage, 1.0)
        self.stage.SetTimeCodesPerSecond(float(fps))
        self.stage.SetStartTimeCode(self.start_frame)
        root = UsdGeom.Xform.Define(self.stage, "/Garment")
        self.stage.SetDefaultPrim(root.GetPrim())
        names: list[str] = []
        for part in self.garment.parts:  # one prim a part, however alike their names are made
            n = _prim_name(part.name)
            names.append(n if n not in names else f"{n}_{len(names)}")
        self.meshes = [_MeshPrim(self.stage, f"/Garment/{n}", part, Sdf, UsdGeom, Vt, thickness)
                       for n, part in zip(names, self.garment.parts)]

    @property
    def mesh(self):
        """The first mesh prim (the welded garment's only one)."""
        return self.meshes[0].mesh

    def add(self, positions: np.ndarray, maps: dict | None = None) -> None:
        """The next frame: the particles' positions ((n, 3), as `Simulation.positions`), and
        with `maps` (`Simulation.fit_maps`' dict) its fit maps, welded as the points are."""
        points = self.garment.points(positions)
        values = {k: self.garment.values(v) for k, v in (maps or {}).items() if v is not None}
        t = self.start_frame + self.frames
        for m in self.meshes:
            lo_hi = slice(m.part.start, m.part.start + m.part.count)
            p = points[lo_hi]
            m.points.Set(self._Vt.Vec3fArray.FromNumpy(p), t)
            m.normals.Set(self._Vt.Vec3fArray.FromNumpy(vertex_normals(p, m.part.triangles)), t)
            for key, v in values.items():
                if key not in m.maps:
                    m.maps[key] = m.primvars.CreatePrimvar(f"tailor_{key}", self._Sdf.ValueTypeNames.FloatArray,
                                                           "vertex")
                m.maps[key].Set(self._Vt.FloatArray.FromNumpy(np.ascontiguousarray(v[lo_hi])), t)
            lo, hi = p.min(axis=0), p.max(axis=0)
            m.extent.Set(self._Vt.Vec3fArray([self._Gf.Vec3f(*map(float, lo)), self._Gf.Vec3f(*map(float, hi))]), t)
        self.frames += 1
        self.stage.SetEndTimeCode(t)
        if self.save_every > 0 and self.frames % self.save_every == 0:
            self.stage.GetRootLayer().Save()

    def add_all(self, frames: Sequence[np.ndarray]) -> None:
        for f in frames:
            self.add(f)

    def close(self) -> None:
        self.stage.GetRootLayer().Save()


def set_thickness(path: str | os.PathLike, thickness: float) -> int:
    """Writes `thickness` (metres) as the constant primvar ``tailor_thickness`` on every mesh of
    the USD file at `path` (written by another exporter, as the add-on's Blender one), and saves
    it; returns how many meshes it marked."""
    try:
        from pxr import Sdf, Usd, UsdGeom
    except ImportError as exc:
        raise TailorIOError(f"{os.fspath(path)}: marking USD needs the `usd-core` package "
                            "(pip install usd-core)") from exc
    if not (np.isfinite(thickness) and thickness >= 0.0):
        raise ValueError(f"thickness must be finite and >= 0, got {thickness}")
    stage = Usd.Stage.Open(os.fspath(path))
    if stage is None:
        raise TailorIOError(f"{os.fspath(path)}: not a USD file USD can open")
    meshes = [p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)]
    for prim in meshes:
        UsdGeom.PrimvarsAPI(prim).CreatePrimvar("tailor_thickness", Sdf.ValueTypeNames.Float,
                                                UsdGeom.Tokens.constant).Set(float(thickness))
    stage.GetRootLayer().Save()
    return len(meshes)


def vertex_normals(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Unit per-point normals ((k, 3) float32): the sum of the adjoining triangles' area-weighted
    normals (a point in no triangle, or where they cancel, gets (0, 0, 1))."""
    p = np.asarray(points, np.float64)
    t = np.asarray(triangles, np.int64)
    face = np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]])
    n = np.zeros_like(p)
    for k in range(3):
        np.add.at(n, t[:, k], face)
    length = np.linalg.norm(n, axis=1, keepdims=True)
    out = np.where(length > 1e-20, n / np.maximum(length, 1e-30), [0.0, 0.0, 1.0])
    return out.astype(np.float32)


def _prim_name(name: str) -> str:
    """`name` as a USD prim name (letters, digits and underscores, not starting with a digit)."""
    out = "".join(c if c.isalnum() or c == "_" else "_" for c in name) or "garment"
    return out if not out[0].isdigit() else f"_{out}"
