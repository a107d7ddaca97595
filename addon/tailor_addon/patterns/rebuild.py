"""Re-triangulating pieces in place (the resolution control).

Every piece keeps its pattern piece and resolution, so a new resolution is a new
`tailor.triangulate`; the seams touching it are remapped by resolving their stored sides on
the new meshes (an equal-count seam whose counts now differ becomes unequal). All of that is
computed first, then the meshes are rewritten: an error leaves the scene as it was.
"""

from __future__ import annotations

import numpy as np

import tailor

from .. import scene_data
from ..core import mesh_arrays, mesh_of, piece_mesh
from ..core.garment import remap_seam_modes, resolve
from ..seams.store import store_seam_counts


def bent_positions(obj, mesh: tailor.PieceMesh, co: np.ndarray) -> np.ndarray:
    """The flat positions `co` with the piece's stored bend applied again (local frame)."""
    p = obj.tailor_piece
    if p.bend_angle == 0.0:
        return co
    return tailor.bend(
        co,
        mesh.rest,
        tuple(p.bend_axis_point),
        tuple(p.bend_axis_direction),
        float(np.degrees(p.bend_angle)),
        **scene_data.stored_bend_kwargs(p),
    )


def set_resolution(scene, targets: list, edge: float) -> None:
    from ..paint import transfer  # paint values follow the vertices they were painted on

    objects = scene_data.piece_objects(scene)
    index = {o.name: i for i, o in enumerate(objects)}
    changed = {index[o.name] for o in targets}
    meshes = [
        piece_mesh(o.tailor_piece.piece_json, edge, tailor.MESHER_VERSION)
        if i in changed
        else mesh_of(o.tailor_piece)
        for i, o in enumerate(objects)
    ]
    stored = [(item, scene_data.read_seam(item, index)) for item in scene.tailor.seams]
    stored = [(item, s) for item, s in stored if s is not None]
    seams = remap_seam_modes([s for _, s in stored], meshes, changed)
    resolved = [resolve(s, meshes) for s in seams]
    rebuilt = {}
    for i in sorted(changed):
        arr = mesh_arrays(meshes[i])
        arr.co = np.ascontiguousarray(bent_positions(objects[i], meshes[i], arr.co), np.float32)
        rebuilt[i] = arr

    for i, arr in rebuilt.items():
        obj = objects[i]
        values = transfer.snapshot(obj)
        scene_data.write_mesh(obj.data, arr)
        transfer.restore(obj, values, arr.rest)
        obj.tailor_piece.edge_length = edge
        obj.tailor_piece.mesher = tailor.MESHER_VERSION
        obj.tailor_piece.contour_length = meshes[i].contour_length
    for (item, _), seam, r in zip(stored, seams, resolved):
        item.mode = scene_data.MODE_ENUM[seam.mode]
        store_seam_counts(item, r)
