"""Fit maps onto the pieces (issue 28): Live's measured frames and a bake's frames (played back
by the frame-change handler) write `Simulation.fit_maps` as point attributes on each piece
(`core.fit_maps.ATTRIBUTES`), and the chosen map's colours as the active colour attribute.

A bake with a Fit Map chosen keeps every frame's maps (`tailor.bake.Bake.keep_fit_maps`) and
writes them beside its caches as `GARMENT.maps.npz` (`strain`, `pressure`, `distance`: frames x
particles, `frames`, and the pieces' names and particle offsets); `show_baked(scene)` writes the
current frame's onto the pieces, the file read once per change of it.
"""

from __future__ import annotations

import os

import bpy
import numpy as np

from ..core import fit_maps

_LOADED: dict[str, tuple[float, dict]] = {}


def write(objects, offsets, total: int, maps: dict, map_id: str) -> None:
    """One frame's `maps` ({key: (total,) array or None}) onto `objects` (the pieces, in the
    garment's order; particles `offsets[k]`.. of the garment are piece k's vertices)."""
    ends = list(offsets[1:]) + [total]
    shown = fit_maps.KEY.get(map_id)
    for obj, a, b in zip(objects, offsets, ends):
        if obj is None:
            continue
        me = obj.data
        if len(me.vertices) != int(b) - int(a):
            continue  # re-meshed since: the maps no longer fit it
        for key, values in maps.items():
            if values is None or key not in fit_maps.ATTRIBUTES:
                continue
            name = fit_maps.ATTRIBUTES[key]
            attr = me.attributes.get(name) or me.attributes.new(name, "FLOAT", "POINT")
            attr.data.foreach_set("value", np.ascontiguousarray(np.asarray(values, np.float32)[int(a):int(b)]))
        if shown is not None and maps.get(shown) is not None:
            col = me.color_attributes.get(fit_maps.COLOUR_ATTRIBUTE) or me.color_attributes.new(
                fit_maps.COLOUR_ATTRIBUTE, "FLOAT_COLOR", "POINT")
            part = np.asarray(maps[shown], np.float32)[int(a):int(b)]
            col.data.foreach_set("color", fit_maps.colours(map_id, part).reshape(-1))
            me.color_attributes.active_color = col
        me.update()


def save_baked(path: str, frame_maps: dict[int, dict], piece_names, offsets, total: int) -> None:
    """A bake's maps by frame into `path` (.npz, atomically)."""
    frames = sorted(frame_maps)
    arrays = {"frames": np.asarray(frames, np.int64), "piece_names": np.asarray(list(piece_names)),
              "offsets": np.asarray(list(offsets) + [total], np.int64)}
    for key in fit_maps.ATTRIBUTES:
        rows = [frame_maps[f].get(key) for f in frames]
        if all(r is not None for r in rows):
            arrays[key] = np.stack([np.asarray(r, np.float32) for r in rows])
    tmp = path + ".partial.npz"
    np.savez(tmp, **arrays)
    os.replace(tmp, path)


def _load(path: str) -> dict | None:
    try:
        mtime = os.path.getmtime(path)
    except OSError:
        return None
    got = _LOADED.get(path)
    if got is None or got[0] != mtime:
        with np.load(path) as z:
            got = (mtime, {k: z[k] for k in z.files})
        _LOADED[path] = got
    return got[1]


def show_baked(scene) -> bool:
    """Writes the scene's baked fit maps of the current frame onto the pieces, when a Fit Map
    is chosen and the last bake kept maps; True when it wrote."""
    s = scene.tailor_simulate
    if s.fit_map == "NONE" or not s.baked_fit_maps or s.live_running:
        return False
    data = _load(bpy.path.abspath(s.baked_fit_maps))
    if data is None:
        return False
    hit = np.nonzero(data["frames"] == scene.frame_current)[0]
    if len(hit) == 0:
        return False
    row = int(hit[0])
    objects = [bpy.data.objects.get(str(n)) for n in data["piece_names"]]
    offsets = data["offsets"]
    write(objects, offsets[:-1], int(offsets[-1]), {k: data[k][row] for k in fit_maps.ATTRIBUTES if k in data},
          s.fit_map)
    return True
