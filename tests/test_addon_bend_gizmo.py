"""The bend gizmo's bpy-free logic (`core.bend_gizmo`): where its parts go and what a drag of
each does, against the module's `tailor.bend`, without Blender."""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

import tailor

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "addon"))
from tailor_addon.core import bend_gizmo as bg  # noqa: E402


def sheet(nx=41, ny=11, width=0.4, height=0.3):
    x, y = np.meshgrid(np.linspace(-width / 2, width / 2, nx), np.linspace(0, height, ny))
    rest = np.c_[x.ravel(), y.ravel()].astype(np.float32)
    return np.c_[rest, np.zeros(len(rest), np.float32)], rest


def test_gizmo_logic_imports_without_blender():
    assert "bpy" not in sys.modules


@pytest.mark.parametrize("symmetric", [True, False])
@pytest.mark.parametrize("threshold", [0.0, 0.03])
def test_the_radius_shown_is_the_one_the_angle_rolls_onto(symmetric, threshold):
    """The arrow's length for a bend by angle is the radius the kernel rolls onto: bending to
    that radius gives the same piece."""
    flat, rest = sheet()
    sym = ((0.0, 0.0), (0.0, 1.0)) if symmetric else None
    axis = ((0.0, 0.15, -0.1), (0.0, 1.0, 0.0))
    angle = math.radians(130)
    r = bg.shown_radius(angle, None, bg.reach(rest, axis[1], sym, threshold))
    by_angle = tailor.bend(flat, rest, *axis, math.degrees(angle), symmetry=sym, threshold=threshold)
    by_radius = tailor.bend(flat, rest, *axis, 1.0, symmetry=sym, threshold=threshold, radius=r)
    np.testing.assert_allclose(by_angle, by_radius, atol=2e-6)
    assert bg.shown_radius(angle, 0.07, 0.2) == 0.07 and bg.shown_radius(0.0, None, 0.2) == 0.0


def test_handles_lie_on_the_axis_and_point_at_the_piece():
    h = bg.handles((0.05, 0.1, -0.08), (0.0, 2.0, 0.0), (-0.2, 0.0), (0.2, 0.3), 0.06)
    np.testing.assert_allclose(h.direction, (0, 1, 0))
    np.testing.assert_allclose(h.out, (0, 0, 1))  # from behind the piece towards it
    np.testing.assert_allclose(h.axis_from, (0.05, -0.03, -0.08), atol=1e-12)
    np.testing.assert_allclose(h.axis_to, (0.05, 0.33, -0.08), atol=1e-12)
    assert h.radius == 0.06 and h.dial == pytest.approx(0.1)  # a quarter of the 0.4 m across
    # An axis in front of the piece points the arrow back at it; an axis along x runs across.
    assert bg.handles((0, 0, 0.1), (0, 1, 0), (-0.2, 0), (0.2, 0.3), 0.05).out[2] == -1.0
    h = bg.handles((0, 0.1, -0.1), (1, 0, 0), (-0.2, 0), (0.2, 0.3), 0.05)
    np.testing.assert_allclose([h.axis_from[0], h.axis_to[0]], [-0.24, 0.24])
    m = bg.axis_frame(h.direction, h.out)
    np.testing.assert_allclose(m.T @ m, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(m[:, 2], (1, 0, 0)) and np.testing.assert_allclose(m[:, 0], (0, 0, 1))
    a = bg.arrow_frame(h.out, h.direction)
    np.testing.assert_allclose(a[:, 2], (0, 0, 1)) and np.testing.assert_allclose(np.linalg.det(a), 1.0)


def test_dragging_the_axis_moves_it_and_the_symmetry_line_in_the_plane():
    hit0 = bg.ray_plane_z((0.0, 0.0, 1.0), (0.1, 0.05, -1.0))
    hit1 = bg.ray_plane_z((0.0, 0.0, 1.0), (0.13, 0.05, -1.0))
    np.testing.assert_allclose(hit0, (0.1, 0.05, 0.0))
    point, sym = bg.moved_axis((0.0, 0.15, -0.1), (0.0, 0.15), hit0, hit1)
    assert point == pytest.approx((0.03, 0.15, -0.1)) and sym == pytest.approx((0.03, 0.15))
    assert bg.ray_plane_z((0, 0, 1), (1, 0, 0)) is None


def test_dragging_the_arrow_tip_sets_the_radius():
    # The arrow runs 100 px right for a 5 cm radius: 40 px further right is 7 cm, back past the
    # base clamps to the minimum, a motion across it changes nothing.
    assert bg.arrow_radius(0.05, (0, 0), (100, 0), (100, 0), (140, 0)) == pytest.approx(0.07)
    assert bg.arrow_radius(0.05, (0, 0), (100, 0), (100, 0), (100, 50)) == pytest.approx(0.05)
    assert bg.arrow_radius(0.05, (0, 0), (100, 0), (100, 0), (-300, 0)) == bg.MIN_RADIUS
    assert bg.arrow_radius(0.05, (0, 0), (0, 0), (0, 0), (10, 0)) == 0.05  # seen end on


def test_the_dial_counts_whole_turns_and_its_sense_follows_the_view():
    centre = (200.0, 200.0)
    for facing, sense in ((1.0, 1.0), (-1.0, -1.0)):
        dial = bg.DialDrag(math.radians(10), centre, (300.0, 200.0), facing=facing)
        for k in range(1, 25):  # one and a half turns counter-clockwise, 22.5 degrees a step
            a = math.radians(22.5 * k)
            angle = dial.update((200 + 100 * math.cos(a), 200 + 100 * math.sin(a)))
        assert math.degrees(angle) == pytest.approx(10 + sense * 540)
    dial = bg.DialDrag(0.0, centre, (300.0, 200.0))
    assert dial.update((200.0, 200.5)) == 0.0  # on the centre: no bearing, no change
