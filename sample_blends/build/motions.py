"""Procedural, loopable motions for the sample character: a walk and a run, in place (no bpy).

A pose is the root bone's offset and one rotation per bone, each a 3x3 matrix `R` in the
armature's rest axes, relative to the parent: a bone's posed rotation is `D = D_parent @ R` (`D`
is the rotation it has moved by since the rest pose, in armature space), and its head follows
its parent rigidly. The Blender layer turns `R` into the bone's local quaternion
`B⁻¹ R B` (`B` the bone's rest orientation), so nothing here depends on bone rolls.

The legs are placed by two-bone inverse kinematics on a foot trajectory drawn as on a treadmill:
during stance the foot rests on the floor and slides back at the walking speed, rolling from
heel strike (toes up, pivot on the heel) through flat to heel rise (pivot on the ball); during
swing it is lifted and carried forward. The knee bends in the plane of hip, ankle and the
walking direction (-Y), so it points forward. The pelvis bobs twice a cycle, shifts over the
stance leg, turns with the forward leg and rolls towards the swing side; the chest turns back
against it, the neck keeps the head level, and the arms swing opposite to the legs, bent at the
elbow. Every curve is periodic in the phase, so frame N+1 equals frame 1 and the action loops.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

FORWARD = np.array([0.0, -1.0, 0.0])  # a Blender character faces -Y


def rot(axis, angle: float) -> np.ndarray:
    """Rotation matrix about `axis` by `angle` radians (Rodrigues)."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * (k @ k)


def rot_between(a, b) -> np.ndarray:
    """The smallest rotation taking direction `a` to direction `b`."""
    a = np.asarray(a, float) / np.linalg.norm(a)
    b = np.asarray(b, float) / np.linalg.norm(b)
    axis = np.cross(a, b)
    s = np.linalg.norm(axis)
    if s < 1e-9:
        return np.eye(3)
    return rot(axis, np.arctan2(s, a @ b))


def rx(deg: float) -> np.ndarray:
    """About +X (the character's left): positive swings a bone that points down backwards (+Y),
    one that points up forwards (-Y)."""
    return rot([1, 0, 0], np.radians(deg))


def ry(deg: float) -> np.ndarray:
    return rot([0, 1, 0], np.radians(deg))


def rz(deg: float) -> np.ndarray:
    return rot([0, 0, 1], np.radians(deg))


def smoothstep(x):
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3 - 2 * x)


@dataclass
class Bone:
    name: str
    head: str  # joint names of body_joints.find_joints
    tail: str
    parent: str | None


def skeleton() -> list[Bone]:
    """The bones, parents first. Sides: `.L` is +X, the character's left."""
    bones = [
        Bone("hips", "pelvis", "waist", None),
        Bone("spine", "waist", "chest", "hips"),
        Bone("chest", "chest", "neck", "spine"),
        Bone("neck", "neck", "head", "chest"),
        Bone("head", "head", "head_top", "neck"),
    ]
    for s in ("L", "R"):
        bones += [
            Bone(f"shoulder.{s}", f"clavicle.{s}", f"shoulder.{s}", "chest"),
            Bone(f"upper_arm.{s}", f"shoulder.{s}", f"elbow.{s}", f"shoulder.{s}"),
            Bone(f"forearm.{s}", f"elbow.{s}", f"wrist.{s}", f"upper_arm.{s}"),
            Bone(f"hand.{s}", f"wrist.{s}", f"hand_tip.{s}", f"forearm.{s}"),
            Bone(f"thigh.{s}", f"hip.{s}", f"knee.{s}", "hips"),
            Bone(f"shin.{s}", f"knee.{s}", f"ankle.{s}", f"thigh.{s}"),
            Bone(f"foot.{s}", f"ankle.{s}", f"ball.{s}", f"shin.{s}"),
            Bone(f"toe.{s}", f"ball.{s}", f"toe_tip.{s}", f"foot.{s}"),
        ]
    return bones


@dataclass
class Gait:
    """Parameters of one cyclic gait. Angles in degrees, lengths in metres."""

    frames: int  # frames per cycle
    stance: float  # fraction of the cycle a foot is on the floor
    half_stride: float  # the foot slides from -half_stride to +half_stride (y) in stance
    lift: float  # ankle lift at mid-swing
    heel_kick: float  # extra lift early in the swing (the run folds the leg up behind)
    drop: float  # mean pelvis drop below the rest height
    bob: float  # pelvis vertical amplitude
    bob_low: float  # phase of a foot's stance at which the pelvis is lowest (0 heel strike)
    sway: float  # pelvis shift over the stance leg
    yaw: float  # pelvis turn
    roll: float  # pelvis roll towards the swing side
    lean: float  # forward lean of the torso
    chest_yaw: float  # chest counter-turn
    arm_out: float  # arm angle from vertical, in the frontal plane
    arm_swing: float
    arm_bias: float  # mean arm swing (negative: forward)
    elbow: float  # mean elbow flexion
    elbow_swing: float  # extra flexion with the arm forward
    strike_pitch: float  # foot pitch at heel strike (negative: toes up)
    toe_off_pitch: float  # foot pitch at toe-off (heel up)


WALK = Gait(
    frames=32, stance=0.6, half_stride=0.22, lift=0.07, heel_kick=0.05, drop=0.025, bob=0.015,
    bob_low=0.08, sway=0.015, yaw=5.0, roll=3.0, lean=2.0, chest_yaw=8.0, arm_out=26.0,
    arm_swing=14.0, arm_bias=-3.0, elbow=15.0, elbow_swing=12.0, strike_pitch=-12.0, toe_off_pitch=30.0,
)
RUN = Gait(
    frames=20, stance=0.38, half_stride=0.2, lift=0.10, heel_kick=0.22, drop=0.035, bob=0.02,
    bob_low=0.5, sway=0.01, yaw=7.0, roll=3.0, lean=9.0, chest_yaw=12.0, arm_out=28.0,
    arm_swing=25.0, arm_bias=-5.0, elbow=75.0, elbow_swing=15.0, strike_pitch=-6.0, toe_off_pitch=35.0,
)


def _foot(g: Gait, psi: float) -> tuple[float, float, float, float]:
    """(y offset, lift, pitch in degrees, toe bend in degrees) of a foot at its phase psi,
    psi = 0 at heel strike."""
    if psi < g.stance:
        u = psi / g.stance
        y = -g.half_stride + 2 * g.half_stride * u
        pitch = float(np.interp(u, [0, 0.15, 0.65, 1.0], [g.strike_pitch, 0, 0, g.toe_off_pitch]))
        return y, 0.0, pitch, -max(pitch, 0.0)
    s = (psi - g.stance) / (1 - g.stance)
    # The foot stays behind while the knee folds (more so in the run: heel_kick), then reaches.
    y = g.half_stride - 2 * g.half_stride * smoothstep(s ** (1 + 2 * g.heel_kick))
    lift = g.lift * np.sin(np.pi * s) + g.heel_kick * np.sin(np.pi * min(s / 0.7, 1.0)) * (1 - s)
    pitch = float(np.interp(s, [0, 0.35, 1.0], [g.toe_off_pitch, 10.0, g.strike_pitch]))
    return y, lift, pitch, -g.toe_off_pitch * (1 - smoothstep(s / 0.3))


def _two_bone(hip, target, a: float, b: float) -> tuple[np.ndarray, np.ndarray]:
    """Knee and ankle positions reaching for `target` with the knee bending forward."""
    d = target - hip
    dist = min(np.linalg.norm(d), 0.995 * (a + b))
    u = d / np.linalg.norm(d)
    w = FORWARD - (FORWARD @ u) * u
    w /= np.linalg.norm(w)
    cos_a = np.clip((a * a + dist * dist - b * b) / (2 * a * dist), -1, 1)
    knee = hip + a * (cos_a * u + np.sqrt(1 - cos_a * cos_a) * w)
    return knee, hip + u * dist


def pose(bones: list[Bone], joints: dict[str, np.ndarray], g: Gait, phase: float):
    """Root offset (3,) and {bone: R} at `phase` in [0, 1) of gait `g`."""
    by = {b.name: b for b in bones}
    R: dict[str, np.ndarray] = {b.name: np.eye(3) for b in bones}
    c = 2 * np.pi * phase
    # Pelvis: lowest twice a cycle, over the left foot while it is in stance (its phase = phase).
    low = g.bob_low * g.stance
    root = np.array([
        g.sway * np.cos(c - 2 * np.pi * 0.5 * g.stance),
        0.0,
        -g.drop - g.bob * np.cos(2 * c - 4 * np.pi * low),
    ])
    R["hips"] = rz(-g.yaw * np.cos(c)) @ ry(-g.roll * np.cos(c - 2 * np.pi * 0.5 * g.stance)) @ rx(g.lean / 2)
    R["spine"] = rx(g.lean / 2)
    R["chest"] = rz(g.chest_yaw * np.cos(c))
    D_chest = R["hips"] @ R["spine"] @ R["chest"]
    R["neck"] = D_chest.T @ rx(g.lean / 3)  # keep the head level, looking ahead
    for s, sign, off in (("L", 1.0, 0.0), ("R", -1.0, 0.5)):
        # Arms: hang at arm_out from vertical, swing opposite to this side's leg.
        up = joints[f"elbow.{s}"] - joints[f"shoulder.{s}"]
        hang = np.array([sign * np.sin(np.radians(g.arm_out)), 0.0, -np.cos(np.radians(g.arm_out))])
        swing = np.cos(c + 2 * np.pi * off)  # +1 when this side's leg strikes forward
        R[f"upper_arm.{s}"] = rx(g.arm_bias + g.arm_swing * swing) @ rot_between(up, hang)
        fore = joints[f"wrist.{s}"] - joints[f"elbow.{s}"]
        hinge = np.cross(fore, FORWARD)
        R[f"forearm.{s}"] = rot(hinge, np.radians(g.elbow + g.elbow_swing * (1 - swing) / 2))
        # Legs.
        y, lift, pitch, toe = _foot(g, (phase + off) % 1.0)
        heel, ball, ankle0 = joints[f"heel.{s}"], joints[f"ball.{s}"], joints[f"ankle.{s}"]
        pivot = heel if pitch < 0 else ball
        Rp = rx(pitch)
        ankle = pivot + Rp @ (ankle0 - pivot) + np.array([0.0, y, lift])
        hip = joints["pelvis"] + root + R["hips"] @ (joints[f"hip.{s}"] - joints["pelvis"])
        knee0 = joints[f"knee.{s}"]
        a = np.linalg.norm(knee0 - joints[f"hip.{s}"])
        b = np.linalg.norm(ankle0 - knee0)
        knee, ankle = _two_bone(hip, ankle, a, b)
        D_thigh = rot_between(knee0 - joints[f"hip.{s}"], knee - hip)
        D_shin = rot_between(ankle0 - knee0, ankle - knee)
        R[f"thigh.{s}"] = R["hips"].T @ D_thigh
        R[f"shin.{s}"] = D_thigh.T @ D_shin
        R[f"foot.{s}"] = D_shin.T @ Rp
        R[f"toe.{s}"] = rx(toe)
    assert set(R) == set(by)
    return root, R


def frames(bones, joints, g: Gait):
    """Poses of one cycle plus the closing frame (equal to the first): frames+1 poses."""
    return [pose(bones, joints, g, (f % g.frames) / g.frames) for f in range(g.frames + 1)]


def forward_kinematics(bones: list[Bone], joints: dict[str, np.ndarray], root: np.ndarray, R: dict[str, np.ndarray]):
    """Posed rotations `D` (armature space, relative to rest) and head positions of every bone,
    the way Blender chains them: `D = D_parent @ R`, a head follows its parent rigidly."""
    D: dict[str, np.ndarray] = {}
    heads: dict[str, np.ndarray] = {}
    rest_head = {b.name: joints[b.head] for b in bones}
    for b in bones:
        if b.parent is None:
            D[b.name] = R[b.name]
            heads[b.name] = rest_head[b.name] + root
        else:
            D[b.name] = D[b.parent] @ R[b.name]
            heads[b.name] = heads[b.parent] + D[b.parent] @ (rest_head[b.name] - rest_head[b.parent])
    return D, heads
