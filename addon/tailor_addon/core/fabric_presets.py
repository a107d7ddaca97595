"""The fabric presets of a piece (issue 28), bpy-free: the module's fabric library
(`tailor.fabric_library()`, measured fabrics with their sources in `tailor_core::fabrics`) as
the choices of an enum, and the values a choice sets.

`CUSTOM` is a piece whose four values are its own (typed, imported or from a garment file);
choosing a library fabric sets all four to that fabric's solver values; changing one of them by
hand makes the piece `CUSTOM` again, so the panel never names a fabric the values are not.
"""

from __future__ import annotations

import tailor

#: The choice "the piece's own values".
CUSTOM = "CUSTOM"
#: The four values a preset sets, in the piece settings' names.
FIELDS = ("density", "stretch", "shear", "bend")


def _title(name: str) -> str:
    return " ".join(w if w[:1].isdigit() else w.capitalize() for w in name.split("-"))


def items() -> list[tuple[str, str, str]]:
    """Enum items: Custom, then every library fabric (lightest first) with what it is and its
    measured figures in its description."""
    out = [(CUSTOM, "Custom", "The piece's own density, stretch, shear and bend")]
    for f in tailor.fabric_library():
        out.append((f["name"], _title(f["name"]),
                    f"{f['description']}: {f['density'] * 1e3:.0f} g/m², stretch {f['stretch_u']:.0f}/"
                    f"{f['stretch_v']:.0f} N/m, bending rigidity {f['rigidity'] * 1e6:.1f} µN·m (Wang, "
                    f"Ramamoorthi and O'Brien 2011)"))
    return out


def values(name: str) -> dict[str, float]:
    """The four values the library fabric `name` sets (InvalidParameterError for another name)."""
    f = tailor.Fabric.named(name)
    return {k: float(getattr(f, k)) for k in FIELDS}


def matches(name: str, current: dict[str, float]) -> bool:
    """Whether `current` (the four values as the piece holds them, float32) are preset `name`'s."""
    if name == CUSTOM:
        return True
    want = values(name)
    return all(abs(current[k] - want[k]) <= 1e-6 * max(abs(want[k]), 1e-12) for k in FIELDS)
