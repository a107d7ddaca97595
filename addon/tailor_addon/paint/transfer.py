"""Carrying painted values over a re-triangulation: each new vertex takes the values of the
old vertex nearest to it in the rest frame (Blender's own KD-tree), for every vertex group
and the collision-level attribute."""

from __future__ import annotations

import numpy as np
from mathutils import kdtree

from .. import scene_data
from ..core.paint import LEVEL_ATTR


def snapshot(obj) -> dict:
    me = obj.data
    rest = scene_data.rest_of(obj)
    if rest is None:
        return {}
    n = len(me.vertices)
    weights = {}
    for vg in obj.vertex_groups:
        weights[vg.name] = np.zeros(n, np.float32), np.zeros(n, bool)
    names = [vg.name for vg in obj.vertex_groups]
    for v in me.vertices:
        for g in v.groups:
            w, has = weights[names[g.group]]
            w[v.index], has[v.index] = g.weight, True
    levels = scene_data.point_attribute(me, LEVEL_ATTR, np.int32)
    return {"rest": rest, "weights": weights, "levels": levels}


def restore(obj, values: dict, new_rest: np.ndarray) -> None:
    if not values:
        return
    old = values["rest"]
    tree = kdtree.KDTree(len(old))
    for i, (x, y) in enumerate(old):
        tree.insert((float(x), float(y), 0.0), i)
    tree.balance()
    nearest = np.array([tree.find((float(x), float(y), 0.0))[1] for x, y in new_rest], np.int64)
    for name, (w, has) in values["weights"].items():
        # Clearing the geometry drops the groups too (their names live on the mesh since 3.0).
        vg = obj.vertex_groups.get(name) or obj.vertex_groups.new(name=name)
        for i, j in enumerate(nearest):
            if has[j]:
                vg.add([i], float(w[j]), "REPLACE")
    if values["levels"] is not None:
        me = obj.data
        attr = me.attributes.get(LEVEL_ATTR) or me.attributes.new(LEVEL_ATTR, "INT", "POINT")
        attr.data.foreach_set("value", values["levels"][nearest].astype(np.int32))
