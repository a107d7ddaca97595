"""The fabric presets of a piece (issue 28), bpy-free: the module's fabric library
(`tailor.fabric_library()`, measured fabrics with their sources in `tailor_core::fabrics`) as
the choices of an enum, and the values a choice sets.

`CUSTOM` is a piece whose values are its own (typed, imported or from a garment file);
choosing a library fabric sets them all to that fabric's solver values (the library's fabrics are
anisotropic: the four values, *Anisotropic* on and the three other directions); changing one of
them by hand makes the piece `CUSTOM` again, so the panel never names a fabric the values are not.
"""

from __future__ import annotations

import tailor

#: The choice "the piece's own values".
CUSTOM = "CUSTOM"
#: The four values every fabric has, in the piece settings' names.
FIELDS = ("density", "stretch", "shear", "bend")
#: An anisotropic fabric's other directions (`tailor.Fabric`'s; None: isotropic).
ANISOTROPIC = ("stretch_v", "bend_bias", "bend_v")


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


def fabric_values(f) -> dict[str, float | None]:
    """A `tailor.Fabric`'s values by the piece settings' names (the directions None where the
    fabric has none)."""
    out: dict[str, float | None] = {k: float(getattr(f, k)) for k in FIELDS}
    out.update({k: None if getattr(f, k) is None else float(getattr(f, k)) for k in ANISOTROPIC})
    return out


def values(name: str) -> dict[str, float | None]:
    """The values the library fabric `name` sets (InvalidParameterError for another name)."""
    return fabric_values(tailor.Fabric.named(name))


def piece_values(piece) -> dict[str, float | None]:
    """The values a piece's settings hold (the directions None unless it is anisotropic)."""
    out: dict[str, float | None] = {k: getattr(piece, k) for k in FIELDS}
    out.update({k: getattr(piece, k) if piece.anisotropic else None for k in ANISOTROPIC})
    return out


def set_piece_fabric(piece, values: dict[str, float | None]) -> None:
    """Sets a piece's settings to `values` (`fabric_values`' shape): *Anisotropic* where any
    direction is given, a missing one as the module takes it (`tailor.Fabric.directions`)."""
    for k in FIELDS:
        setattr(piece, k, values[k])
    given = {k: values.get(k) for k in ANISOTROPIC}
    piece.anisotropic = any(v is not None for v in given.values())
    if piece.anisotropic:
        d = tailor.Fabric(*(values[k] for k in FIELDS), **given).directions()
        piece.stretch_v, piece.bend_bias, piece.bend_v = d["stretch_v"], d["bend_bias"], d["bend_v"]


def matches(name: str, current: dict[str, float | None]) -> bool:
    """Whether `current` (`piece_values`: as the piece holds them, float32) are preset `name`'s."""
    if name == CUSTOM:
        return True
    want = values(name)
    for k in FIELDS + ANISOTROPIC:
        if (current[k] is None) != (want[k] is None):
            return False
        if want[k] is not None and abs(current[k] - want[k]) > 1e-6 * max(abs(want[k]), 1e-12):
            return False
    return True
