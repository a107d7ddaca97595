"""Reading and writing the painted maps of an object (vertex groups, the level attribute and the
painted level groups)."""

from __future__ import annotations

import numpy as np

from ..core.paint import BY_KEY, LEVEL_ATTR, WEIGHT_MAPS, level_of_group, painted_levels, values  # noqa: F401


def group_weights(obj, group: str) -> tuple[np.ndarray, np.ndarray] | None:
    """(weights, painted mask) of a vertex group over the object's vertices, or None."""
    vg = obj.vertex_groups.get(group)
    if vg is None:
        return None
    n = len(obj.data.vertices)
    w = np.zeros(n, np.float32)
    painted = np.zeros(n, bool)
    gi = vg.index
    for v in obj.data.vertices:
        for g in v.groups:
            if g.group == gi:
                w[v.index], painted[v.index] = g.weight, True
    return w, painted


def level_groups(obj) -> dict[int, str]:
    """{level: vertex group name} of the object's painted level groups (`tailor_level_N`)."""
    return {lv: vg.name for vg in obj.vertex_groups if (lv := level_of_group(vg.name)) is not None}


def collision_levels(obj) -> np.ndarray | None:
    """(n,) int32 collision levels of a mesh object (the level attribute, overridden where a level
    group is painted: `core.paint.painted_levels`), or None when neither is there."""
    n = len(obj.data.vertices)
    attr = obj.data.attributes.get(LEVEL_ATTR)
    base = None
    if attr is not None and attr.domain == "POINT":
        base = np.empty(n, np.int32)
        attr.data.foreach_get("value", base)
    return painted_levels(base, n, level_group_weights(obj))


def level_group_weights(obj) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """{level: (weights, painted mask)} of every painted level group, read in one pass over the
    vertices (the overlay reads them at every redraw: a pass per group cost 13 ms each on the
    sample character's 24k vertices)."""
    index = {obj.vertex_groups[name].index: lv for lv, name in level_groups(obj).items()}
    if not index:
        return {}
    n = len(obj.data.vertices)
    out = {lv: (np.zeros(n, np.float32), np.zeros(n, bool)) for lv in index.values()}
    for v in obj.data.vertices:
        for g in v.groups:
            lv = index.get(g.group)
            if lv is not None:
                w, painted = out[lv]
                w[v.index], painted[v.index] = g.weight, True
    return out


def painted_maps(obj) -> dict:
    """Everything painted on `obj`: {key: (parameter values, painted mask)} for the weight maps
    and {"collision_level": (levels, all-true mask)}; unpainted maps are absent."""
    out = {}
    for m in WEIGHT_MAPS:
        got = group_weights(obj, m.group)
        if got is not None:
            out[m.key] = (values(m.key, got[0]), got[1])
    levels = collision_levels(obj)
    if levels is not None:
        out["collision_level"] = (levels, np.ones(len(levels), bool))
    return out


def write_group(obj, group: str, indices: np.ndarray, weights: np.ndarray) -> None:
    """Vertex group `group` of `obj` (made if missing) with `weights` on vertices `indices`;
    one `add` per distinct weight (a painted map has few)."""
    vg = obj.vertex_groups.get(group) or obj.vertex_groups.new(name=group)
    indices, weights = np.asarray(indices, np.int64), np.asarray(weights, np.float32)
    for w in np.unique(weights):
        vg.add(indices[weights == w].tolist(), float(w), "REPLACE")


def write_collision_levels(obj, levels: np.ndarray) -> None:
    """Replaces the object's collision levels (the INT point attribute) with `levels`."""
    me = obj.data
    old = me.attributes.get(LEVEL_ATTR)
    if old is not None:
        me.attributes.remove(old)
    me.attributes.new(LEVEL_ATTR, "INT", "POINT").data.foreach_set("value", np.asarray(levels, np.int32))
    me.update()
