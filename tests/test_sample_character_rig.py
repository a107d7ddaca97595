"""The sample character's rig and motions without Blender (sample_blends/build/body_joints.py and
motions.py): joints measured inside the body, and gaits that loop and keep the feet on the floor."""

import sys
from pathlib import Path

import numpy as np
import pytest

BUILD = Path(__file__).resolve().parents[1] / "sample_blends" / "build"
sys.path.insert(0, str(BUILD))

import body_joints  # noqa: E402
import motions  # noqa: E402

SOURCE = BUILD.parent / "sources" / "mean_all.obj"


@pytest.fixture(scope="module")
def body():
    v, t = body_joints.read_obj(SOURCE)
    v = body_joints.y_up_to_z_up(v)
    return v, t, body_joints.find_joints(v, t)


def inside(point, v, t) -> bool:
    """Parity of a ray's crossings with the closed mesh (ray along an irrational direction)."""
    d = np.array([0.57, 0.31, 0.76])
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    e1, e2 = b - a, c - a
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-12
    s = point - a
    u = np.einsum("ij,ij->i", s, p) / np.where(ok, det, 1)
    q = np.cross(s, e1)
    w = (q @ d) / np.where(ok, det, 1)
    dist = np.einsum("ij,ij->i", e2, q) / np.where(ok, det, 1)
    hits = ok & (u >= 0) & (w >= 0) & (u + w <= 1) & (dist > 0)
    return bool(hits.sum() % 2)


def test_body_is_z_up_and_faces_minus_y(body):
    v, t, _ = body
    assert v.shape == (23752, 3) and t.shape == (47500, 3)
    assert v[:, 2].min() == pytest.approx(0.0, abs=1e-6) and v[:, 2].max() == pytest.approx(1.72, abs=0.01)
    toes = v[v[:, 2] < 0.03]
    assert toes[:, 1].min() < -0.14 and toes[:, 1].max() < 0.12  # toes at -Y, heels just behind


def test_joints_lie_inside_the_body_in_order(body):
    v, t, j = body
    for name in ("pelvis", "waist", "chest", "neck", "head") + tuple(
        f"{k}.{s}" for k in ("hip", "knee", "ankle", "shoulder", "elbow", "wrist") for s in "LR"
    ):
        assert inside(j[name], v, t), f"{name} {j[name]} is outside the body"
    for s, sign in (("L", 1), ("R", -1)):
        assert j[f"hip.{s}"][2] > j[f"knee.{s}"][2] > j[f"ankle.{s}"][2] > 0.05
        assert j["neck"][2] > j[f"shoulder.{s}"][2] > j[f"elbow.{s}"][2] > j[f"wrist.{s}"][2]
        assert sign * j[f"wrist.{s}"][0] > sign * j[f"elbow.{s}"][0] > sign * j[f"shoulder.{s}"][0] > 0.1
    for k in ("hip", "knee", "ankle", "shoulder", "elbow", "wrist"):  # left and right mirror
        mirrored = j[f"{k}.R"] * np.array([-1, 1, 1])
        assert np.linalg.norm(j[f"{k}.L"] - mirrored) < 0.02, k
    bones = motions.skeleton()
    assert all(np.linalg.norm(j[b.tail] - j[b.head]) > 0.03 for b in bones)


@pytest.mark.parametrize("gait", [motions.WALK, motions.RUN], ids=["walk", "run"])
def test_gait_loops_and_keeps_the_feet_on_the_floor(body, gait):
    _, _, j = body
    bones = motions.skeleton()
    poses = motions.frames(bones, j, gait)
    assert len(poses) == gait.frames + 1
    np.testing.assert_allclose(poses[-1][0], poses[0][0], atol=1e-9)
    for name in poses[0][1]:
        np.testing.assert_allclose(poses[-1][1][name], poses[0][1][name], atol=1e-9)
    lowest = {s: [] for s in "LR"}
    for root, R in poses[:-1]:
        for name, m in R.items():  # proper rotations
            np.testing.assert_allclose(m @ m.T, np.eye(3), atol=1e-9)
        D, heads = motions.forward_kinematics(bones, j, root, R)
        for s in "LR":
            # The sole under heel, ball and toe tip (the ball and toe joints lie inside the foot).
            on = {k: j[f"{k}.{s}"] * np.array([1, 1, 0]) for k in ("heel", "ball", "toe_tip")}
            sole = [heads[f"toe.{s}"] + D[f"toe.{s}"] @ (on["toe_tip"] - j[f"ball.{s}"])]
            sole += [heads[f"foot.{s}"] + D[f"foot.{s}"] @ (on[k] - j[f"ankle.{s}"]) for k in ("heel", "ball")]
            lowest[s].append(min(p[2] for p in sole))
    for s in "LR":
        low = np.array(lowest[s])
        assert low.min() > -0.002, f"{s} foot {low.min():.3f} m below the floor"
        # On the floor (within 1 cm) for the stance fraction of the cycle.
        on_floor = np.mean(np.abs(low) < 0.01)
        assert on_floor >= gait.stance - 0.05, f"{s} foot on the floor {on_floor:.0%} of the cycle"
        assert low.max() > 0.05  # and lifted in the swing
