"""What went wrong and what to do about it, for every error an operator can meet.

`describe(exc)` turns a `tailor.TailorError` subclass (raised by the native module) or an
`AddonError` (raised by the add-on's own checks) into one line for the status bar: the
message, which names what and where, followed by what the artist can do. The Blender layer
(`reporting.py`) is the only caller that shows it.
"""

from __future__ import annotations

import tailor


class AddonError(ValueError):
    """A problem the add-on detects itself (wrong selection, edited mesh, missing data).

    `hint` says what the artist can do about it."""

    def __init__(self, message: str, hint: str = ""):
        super().__init__(message)
        self.hint = hint


# Most specific first: every class below is also a `tailor.TailorError`.
_HINTS: list[tuple[type, str]] = [
    (
        tailor.PatternError,
        "Check that the file is a DXF (AAMA/ASTM or plain), SVG or GarmentCode JSON pattern with closed "
        "outlines; set Units if the sizes come out wrong",
    ),
    (
        tailor.SeamError,
        "Pick two contour runs with the same number of vertices, or set the seam's mode to Unequal",
    ),
    (
        tailor.InvalidMeshError,
        "The piece's mesh is not a valid cloth mesh; re-import the pattern or apply its resolution again "
        "to rebuild it",
    ),
    (tailor.InvalidParameterError, "Change the value named above (in the panel or the operator's redo panel)"),
    (tailor.TailorIOError, "Check that the path exists and that Blender may read or write it"),
    (
        tailor.SimulationError,
        "Lower the time step or raise substeps and iterations; check the colliders for bad geometry",
    ),
    (tailor.CancelledError, "Nothing was changed"),
    (tailor.TailorError, "Nothing was changed; see the message for the offending item"),
]


def hint_for(exc: BaseException) -> str:
    if isinstance(exc, AddonError):
        return exc.hint
    for cls, hint in _HINTS:
        if isinstance(exc, cls):
            return hint
    return ""


def describe(exc: BaseException, what: str = "") -> str:
    """`"<what> failed: <message>. <hint>."` on one line."""
    msg = str(exc).strip().rstrip(".") or type(exc).__name__
    head = f"{what} failed: {msg}" if what else msg
    hint = hint_for(exc)
    return f"{head}. {hint}." if hint else f"{head}."


def is_reportable(exc: BaseException) -> bool:
    """Errors that are the input's fault and are reported, not raised as add-on bugs."""
    return isinstance(exc, (tailor.TailorError, AddonError))
