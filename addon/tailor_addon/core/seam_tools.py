"""The interactive seam tools' logic, without Blender: what a hover shows and what a click does.

Two tools, each a small state machine over picks on piece contours; the modal operators
(`seams/modal_pick.py`, `seams/modal_suggest.py`) only turn mouse events into rest-frame points
on named pieces (`core.picking`), feed them here, draw the returned highlight and show the
returned prompt. Every contour computation is the module's.

Manual seam (paper Sec. 4, the five steps):
  1. click a1 on piece A's contour;
  2-3. hover: the shortest contour path from a1 to the vertex under the cursor is highlighted
       (`tailor.shortest_path`); click an (on piece A);
  4. click b1 on piece B's contour (B may be A);
  5. hover: of the two n-vertex paths from b1 (n = side A's count), the one whose end is nearer
     the cursor is highlighted (`tailor.nearer_candidate`); click bn.
  The result is a `SeamRequest`, the arguments of the exec-path operator `tailor.seam_add`.

Automatic suggestion: hovering a piece highlights the contour run between the two corners
around the contour edge nearest the cursor (`tailor.find_corners` with the panel's corner
angle, `tailor.nearest_corner_segment`); a click takes it as side A, a second click on another
run takes side B. Side B is walked from the end nearer (in 3D) to a1, so two panels laid side
by side or placed around a body are sewn edge to edge rather than crossed; the seam is equal
when both runs have the same vertex count and unequal otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

import tailor

MeshFor = Callable[[str], "tailor.PieceMesh"]
# (piece name, contour position) -> current 3D position (world), to orient suggested seams.
Locate = Callable[[str, int], np.ndarray]

CANCEL_HINT = "Esc/right-click: cancel · Backspace: undo last pick"


@dataclass
class SeamRequest:
    """The arguments of `bpy.ops.tailor.seam_add` (contour positions, directions CCW/CW)."""

    piece_a: str
    a_start: int
    a_end: int
    a_direction: str
    piece_b: str
    b_start: int
    b_end: int
    b_direction: str
    mode: str = "EQUAL"

    def operator_kwargs(self) -> dict:
        return {
            "piece_a": self.piece_a,
            "a_start": self.a_start,
            "a_end": self.a_end,
            "a_direction": self.a_direction,
            "piece_b": self.piece_b,
            "b_start": self.b_start,
            "b_end": self.b_end,
            "b_direction": self.b_direction,
            "mode": self.mode,
        }


@dataclass
class Highlight:
    """What to draw: contour paths per piece (`role` is 'picked' for fixed sides, 'preview' for
    what the next click would give) and single contour vertices (`points`)."""

    paths: list[tuple[str, list[int], str]] = field(default_factory=list)  # (piece, positions, role)
    points: list[tuple[str, int, str]] = field(default_factory=list)  # (piece, position, role)


@dataclass
class ClickResult:
    """`accepted`: the pick was taken; `request`: the seam is complete; `message`: why a pick
    was refused (shown in the status bar)."""

    accepted: bool
    request: SeamRequest | None = None
    message: str = ""


def _direction(path) -> str:
    return "CCW" if path.direction == "ccw" else "CW"


class ManualSeamTool:
    """The five-step manual seam. `hover`/`click` take the piece under the cursor (or None)
    and the cursor's rest-frame point on it."""

    STEPS = ("a1", "an", "b1", "bn")

    def __init__(self, mesh_for: MeshFor):
        self._mesh_for = mesh_for
        self.picks: list[tuple[str, int]] = []  # (piece, contour position)
        self.path_a = None  # tailor.ContourPath once an is picked

    @property
    def step(self) -> str:
        return self.STEPS[len(self.picks)]

    def prompt(self) -> str:
        """What the next click does (the header text)."""
        if not self.picks:
            text = "Manual seam 1/4: click a1, the first vertex of side A on a piece's contour"
        elif len(self.picks) == 1:
            text = f"Manual seam 2/4: click an on '{self.picks[0][0]}' (the shortest contour path from a1 is shown)"
        elif len(self.picks) == 2:
            text = f"Manual seam 3/4: click b1, the first vertex of side B ({len(self.path_a.positions)} vertices)"
        else:
            text = (
                f"Manual seam 4/4: click bn on '{self.picks[2][0]}': the {len(self.path_a.positions)}-vertex path "
                "towards the cursor is shown"
            )
        return f"{text} · {CANCEL_HINT}"

    def position(self, piece: str, rest_point) -> int:
        return tailor.nearest_contour_position(self._mesh_for(piece), (float(rest_point[0]), float(rest_point[1])))

    def _candidate(self, piece: str, rest_point, position: int):
        """The path the next click would fix (steps an and bn), or None."""
        mesh = self._mesh_for(piece)
        if len(self.picks) == 1:
            return tailor.shortest_path(mesh, self.picks[0][1], position)
        if len(self.picks) == 3:
            n = len(self.path_a.positions)
            return tailor.nearer_candidate(mesh, self.picks[2][1], n, (float(rest_point[0]), float(rest_point[1])))
        return None

    def _refusal(self, piece: str, position: int) -> str:
        if len(self.picks) in (1, 3) and piece != self.picks[-1][0]:
            side = "an" if len(self.picks) == 1 else "bn"
            return f"{side} must be on '{self.picks[-1][0]}', the piece of the previous pick"
        if len(self.picks) == 1 and position == self.picks[0][1]:
            return "an must differ from a1: a seam side has at least two vertices"
        if len(self.picks) == 3:
            n, size = len(self.path_a.positions), len(self._mesh_for(piece).contour)
            if n > size:
                return f"side A has {n} vertices but '{piece}' has only {size} contour vertices"
        return ""

    def highlight(self, piece: str | None, rest_point=None) -> Highlight:
        """The picked sides, and what a click at `rest_point` on `piece` would pick."""
        h = Highlight()
        if self.path_a is not None:
            h.paths.append((self.picks[0][0], list(self.path_a.positions), "picked"))
        for p, pos in self.picks:
            h.points.append((p, pos, "picked"))
        if piece is None:
            return h
        position = self.position(piece, rest_point)
        if self._refusal(piece, position):
            return h
        h.points.append((piece, position, "preview"))
        path = self._candidate(piece, rest_point, position)
        if path is not None:
            h.paths.append((piece, list(path.positions), "preview"))
            h.points.append((piece, path.positions[-1], "preview"))
        return h

    def click(self, piece: str | None, rest_point=None) -> ClickResult:
        if piece is None:
            return ClickResult(False, message=f"Nothing picked: click on a piece's contour for {self.step}")
        position = self.position(piece, rest_point)
        refusal = self._refusal(piece, position)
        if refusal:
            return ClickResult(False, message=refusal)
        path = self._candidate(piece, rest_point, position)
        if len(self.picks) == 1:
            self.path_a = path
            position = path.positions[-1]
        elif len(self.picks) == 3:
            (pa, a1), (_, an), (pb, b1) = self.picks
            request = SeamRequest(
                pa, a1, an, _direction(self.path_a), pb, b1, path.positions[-1], _direction(path), "EQUAL"
            )
            self.picks.append((piece, path.positions[-1]))
            return ClickResult(True, request=request)
        self.picks.append((piece, position))
        return ClickResult(True)

    def undo(self) -> bool:
        """Forgets the last pick (Backspace); False when there is none."""
        if not self.picks:
            return False
        self.picks.pop()
        if len(self.picks) < 2:
            self.path_a = None
        return True


class SuggestSeamTool:
    """Automatic suggestion: corner-delimited contour runs, side A then side B."""

    def __init__(self, mesh_for: MeshFor, locate: Locate, corner_angle_deg: float):
        self._mesh_for = mesh_for
        self._locate = locate
        self.corner_angle_deg = float(corner_angle_deg)
        self._corners: dict[str, list[int]] = {}
        self.side_a: tuple[str, list[int]] | None = None  # (piece, ccw positions)

    def corners(self, piece: str) -> list[int]:
        if piece not in self._corners:
            self._corners[piece] = tailor.find_corners(self._mesh_for(piece), self.corner_angle_deg)
        return self._corners[piece]

    def segment(self, piece: str, rest_point) -> list[int] | None:
        """Contour positions (counter-clockwise) of the corner-delimited run nearest the point,
        or None when the piece has fewer than two corners at this angle."""
        corners = self.corners(piece)
        if len(corners) < 2:
            return None
        path = tailor.nearest_corner_segment(
            self._mesh_for(piece), corners, (float(rest_point[0]), float(rest_point[1]))
        )
        return list(path.positions)

    def prompt(self, hovered: tuple[str, list[int]] | None = None) -> str:
        angle = f"corner angle {self.corner_angle_deg:.0f}°"
        if self.side_a is None:
            text = f"Seam suggestion 1/2: click the contour segment for side A ({angle})"
            if hovered is not None:
                text += f" · '{hovered[0]}': {len(hovered[1])} vertices"
        else:
            n = len(self.side_a[1])
            text = f"Seam suggestion 2/2: click the partner segment (side A: {n} vertices on '{self.side_a[0]}')"
            if hovered is not None:
                m = len(hovered[1])
                text += f" · {m} vertices: {'equal' if m == n else 'unequal'} seam"
        return f"{text} · {CANCEL_HINT}"

    def _refusal(self, piece: str, positions: list[int] | None) -> str:
        if positions is None:
            return (
                f"'{piece}' has fewer than two corners under {self.corner_angle_deg:.0f}°: "
                "raise the corner angle in the Seams panel"
            )
        if self.side_a is not None and self.side_a == (piece, positions):
            return "that is side A: click its partner segment"
        return ""

    def highlight(self, piece: str | None, rest_point=None) -> Highlight:
        h = Highlight()
        if self.side_a is not None:
            h.paths.append((self.side_a[0], self.side_a[1], "picked"))
        if piece is None:
            return h
        positions = self.segment(piece, rest_point)
        if not self._refusal(piece, positions):
            h.paths.append((piece, positions, "preview"))
            h.points.extend([(piece, positions[0], "preview"), (piece, positions[-1], "preview")])
        return h

    def click(self, piece: str | None, rest_point=None) -> ClickResult:
        if piece is None:
            return ClickResult(False, message="Nothing picked: click near a piece's contour")
        positions = self.segment(piece, rest_point)
        refusal = self._refusal(piece, positions)
        if refusal:
            return ClickResult(False, message=refusal)
        if self.side_a is None:
            self.side_a = (piece, positions)
            return ClickResult(True)
        pa, run_a = self.side_a
        a1 = self._locate(pa, run_a[0])
        d_first = float(np.linalg.norm(self._locate(piece, positions[0]) - a1))
        d_last = float(np.linalg.norm(self._locate(piece, positions[-1]) - a1))
        if d_first <= d_last:
            b_start, b_end, b_dir = positions[0], positions[-1], "CCW"
        else:
            b_start, b_end, b_dir = positions[-1], positions[0], "CW"
        mode = "EQUAL" if len(positions) == len(run_a) else "UNEQUAL"
        request = SeamRequest(pa, run_a[0], run_a[-1], "CCW", piece, b_start, b_end, b_dir, mode)
        return ClickResult(True, request=request)

    def undo(self) -> bool:
        if self.side_a is None:
            return False
        self.side_a = None
        return True
