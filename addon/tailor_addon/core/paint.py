"""Painted per-particle parameters (paper Sec. 5): what is stored where, and what it means.

Friction, mass scale, bend scale and pin weight are vertex groups (painted with Blender's
weight paint, weights in 0..1); the collision level is an integer point attribute, on garment
pieces and on colliders alike, set on a selection, and can be painted too: a vertex group per
level (`tailor_level_N`), painted with the same weight brush, overrides the attribute where its
weight is at least one half (`painted_levels`). `values(map, weights)` turns weights into the
solver's parameter.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

LEVEL_ATTR = "tailor_collision_level"
LEVEL_GROUP_PREFIX = "tailor_level_"
LEVEL_GROUP_MIN_WEIGHT = 0.5  # a vertex belongs to a painted level from this weight on
MASS_SCALE_MIN = 0.05
BEND_SCALE_RANGE = 100.0  # a bend-scale weight of 0 or 1 divides or multiplies the bending by this


@dataclass(frozen=True)
class WeightMap:
    key: str
    group: str  # vertex group name
    label: str
    meaning: str


WEIGHT_MAPS = (
    WeightMap("friction_static", "tailor_friction_static", "Static Friction", "Coulomb coefficient = weight"),
    WeightMap("friction_kinetic", "tailor_friction_kinetic", "Kinetic Friction", "Coulomb coefficient = weight"),
    WeightMap("mass_scale", "tailor_mass_scale", "Mass Scale", "mass factor = 2 x weight (0.5 = unchanged)"),
    WeightMap("bend_scale", "tailor_bend_scale", "Bend Scale",
              "bending factor = 100^(2 x weight - 1): 0.5 = unchanged, 1 = 100x stiffer, 0 = 100x softer"),
    WeightMap("pin", "tailor_pin", "Pin", "1 = pinned in place, between 0 and 1 = soft attachment weight"),
)
BY_KEY = {m.key: m for m in WEIGHT_MAPS}
BY_GROUP = {m.group: m for m in WEIGHT_MAPS}


def values(key: str, weights: np.ndarray) -> np.ndarray:
    """The solver parameter for weights of map `key` (float32)."""
    w = np.clip(np.asarray(weights, np.float32), 0.0, 1.0)
    if key == "mass_scale":
        return np.maximum(2.0 * w, MASS_SCALE_MIN).astype(np.float32)
    if key == "bend_scale":
        # Logarithmic: bending stiffness spans decades (a collar or a cuff is 10-100x the body).
        return np.power(BEND_SCALE_RANGE, 2.0 * w - 1.0).astype(np.float32)
    return w


def weights(key: str, params: np.ndarray) -> tuple[np.ndarray, int]:
    """The weights that give solver parameters `params` of map `key` (the inverse of `values`),
    float32, and how many had to be clipped to what a weight holds (0..1: a friction over 1, a
    mass scale over 2 or under MASS_SCALE_MIN, a bend scale beyond 100x either way)."""
    p = np.asarray(params, np.float64)
    if key == "mass_scale":
        w = p / 2.0
    elif key == "bend_scale":
        w = (np.log(np.maximum(p, 1e-30)) / np.log(BEND_SCALE_RANGE) + 1.0) / 2.0
    else:
        w = p
    # A tolerance of a float32 step: a bend scale of exactly 100 may come back as 1 + 1e-8.
    out = (w < -1e-6) | (w > 1.0 + 1e-6)
    if key == "mass_scale":
        out |= p < MASS_SCALE_MIN * (1.0 - 1e-6)  # `values` never gives less
    clipped = int(np.count_nonzero(out))
    return np.clip(w, 0.0, 1.0).astype(np.float32), clipped


def unpainted(key: str, friction: dict) -> float:
    """What the module gives an unpainted vertex of map `key` (the garment setup's rule,
    `GarmentSetup::unpainted`): the cloth's friction (`friction`, the setup's), scales of 1,
    no pin."""
    if key in ("mass_scale", "bend_scale"):
        return 1.0
    if key == "friction_static":
        return float(friction["static"])
    if key == "friction_kinetic":
        return float(friction["kinetic"])
    return 0.0


def level_group_name(level: int) -> str:
    """The vertex group that paints collision level `level`."""
    return f"{LEVEL_GROUP_PREFIX}{int(level)}"


def level_of_group(name: str) -> int | None:
    """The collision level a vertex group paints (`tailor_level_2` -> 2), or None for other groups."""
    m = re.fullmatch(re.escape(LEVEL_GROUP_PREFIX) + r"(-?\d+)", name)
    return int(m.group(1)) if m else None


def painted_levels(base: np.ndarray | None, n: int,
                   groups: dict[int, tuple[np.ndarray, np.ndarray]]) -> np.ndarray | None:
    """Per-vertex collision levels (int32, `n` vertices) from the level attribute `base` (None:
    level 0) and the painted level groups `{level: (weights, painted mask)}`: a vertex painted
    with a weight of at least `LEVEL_GROUP_MIN_WEIGHT` in one or more level groups takes the level
    of the heaviest (a tie: the higher level, so the result does not depend on group order);
    elsewhere the attribute's. None when there is neither an attribute nor a level group."""
    if base is None and not groups:
        return None
    out = np.zeros(n, np.int32) if base is None else np.asarray(base, np.int32).copy()
    best = np.full(n, -1.0, np.float32)
    for level in sorted(groups):
        w, painted = groups[level]
        w = np.where(painted, np.asarray(w, np.float32), -1.0)
        take = (w >= LEVEL_GROUP_MIN_WEIGHT) & (w >= best)
        out[take] = level
        best[take] = w[take]
    return out

