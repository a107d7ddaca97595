"""The add-on's bpy-free half: numpy conversions and the garment data model.

Nothing here imports `bpy`, so it is tested with plain pytest and usable from pipeline
scripts. The Blender layer (the feature folders) reads scene data into the plain structures
defined here (`PieceData`, `SeamData`), calls these functions, and writes the results back.
"""

from .errors import AddonError, describe
from .garment import PieceData, SeamData, SceneGarment, garment_from_scene, mesh_of, piece_mesh, remap_seam_modes
from .layout import placement_rotation, side_by_side
from .mesh_arrays import MeshArrays, mesh_arrays
from . import welded

__all__ = [
    "AddonError",
    "describe",
    "PieceData",
    "SeamData",
    "SceneGarment",
    "garment_from_scene",
    "mesh_of",
    "piece_mesh",
    "remap_seam_modes",
    "placement_rotation",
    "side_by_side",
    "MeshArrays",
    "mesh_arrays",
    "welded",
]
