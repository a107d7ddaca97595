"""Painted per-particle parameters (paper Sec. 5): what is stored where, and what it means.

Friction, mass scale, bend scale and pin weight are vertex groups (painted with Blender's
weight paint, weights in 0..1); the collision level is an integer point attribute, on garment
pieces and on colliders alike. `values(map, weights)` turns weights into the solver's parameter.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

LEVEL_ATTR = "tailor_collision_level"
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
