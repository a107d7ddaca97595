"""The Fit Map overlay's colours (bpy-free): a map of `Simulation.fit_maps` (strain, pressure,
distance to the body) turned into per-vertex colours on a blue-green-yellow-red ramp, as
garment tools colour fit, each map over a fixed, stated range so that colours mean the same
from frame to frame and garment to garment:

* strain: 0 (blue) to 20 % (red): woven fabric stretches a few percent, so red is overstretched;
* pressure: 0 to 2 kPa (about what a snug sleeve or a waistband presses), on a square-root
  scale, so that the few pascals of a drape's own weight still show;
* distance: touching (red) to 5 cm off the body (blue): tight to loose.
"""

from __future__ import annotations

import numpy as np

#: The maps the overlay shows: (enum id, label, Simulation.fit_maps key, what it shows).
MAPS = (
    ("STRAIN", "Strain", "strain", "Largest stretch in any direction: blue 0, red 20 % or more"),
    ("PRESSURE", "Pressure", "pressure", "The body's pressure on the cloth: blue 0, red 2 kPa or more"),
    ("DISTANCE", "Distance", "distance", "Distance to the body: red touching, blue 5 cm or more"),
)
KEY = {m[0]: m[2] for m in MAPS}
STRAIN_RED = 0.20
PRESSURE_RED_PA = 2000.0
DISTANCE_BLUE_M = 0.05

#: The point attributes every map is written to (float), and the colour attribute shown.
ATTRIBUTES = {"strain": "tailor_strain", "pressure": "tailor_pressure", "distance": "tailor_distance"}
COLOUR_ATTRIBUTE = "tailor_fit_map"

_RAMP = np.array([[0.05, 0.15, 0.9], [0.1, 0.8, 0.3], [0.95, 0.85, 0.1], [0.9, 0.1, 0.05]], np.float32)


def unit(map_id: str, values: np.ndarray) -> np.ndarray:
    """Map `map_id`'s values as 0..1 along its ramp (see the module docs)."""
    v = np.nan_to_num(np.asarray(values, np.float64), nan=0.0)
    if map_id == "STRAIN":
        t = v / STRAIN_RED
    elif map_id == "PRESSURE":
        t = np.sqrt(np.maximum(v, 0.0) / PRESSURE_RED_PA)
    elif map_id == "DISTANCE":
        t = 1.0 - v / DISTANCE_BLUE_M
    else:
        raise ValueError(f"no fit map {map_id!r}: expected one of {', '.join(KEY)}")
    return np.clip(t, 0.0, 1.0)


def colours(map_id: str, values: np.ndarray) -> np.ndarray:
    """(n, 4) float32 RGBA of `values` on the ramp, alpha 1."""
    t = unit(map_id, values) * (len(_RAMP) - 1)
    k = np.minimum(t.astype(np.int64), len(_RAMP) - 2)
    f = (t - k)[:, None]
    rgb = _RAMP[k] * (1.0 - f) + _RAMP[k + 1] * f
    return np.concatenate([rgb, np.ones((len(rgb), 1))], axis=1).astype(np.float32)
