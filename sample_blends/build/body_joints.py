"""Joint positions of the sample body, found from its mesh by cross-section analysis (no bpy).

The GarmentCode mean body (`sources/mean_all.obj`) is stored Y-up, facing +Z, feet at y = 0, in
metres. Blender is Z-up and a character faces -Y, so a point (x, y, z) of the file becomes
(x, -z, y); +X stays the character's left in both (Blender's `.L` side).

Every joint is measured on the converted mesh rather than typed in, so a different body of the
same pose (A-pose, arms down at about 45 degrees) gets a fitting skeleton:

- crotch: the lowest vertex on the mid-sagittal plane above the knees; the hip joints sit a fixed
  fraction of the height above it (5.8 %, the pelvis depth of the SMPL mean body), centred in each
  leg's cross-section just below the crotch;
- cross-sections cut the mesh's edges with a horizontal plane (vertices alone are too sparse on
  the long triangles of the limbs);
- ankles: the centre of each leg's cross-section at 4.4 % of the height; the knee is at the
  popliteal hollow (where the back of the leg is shallowest between calf and thigh);
- feet: heel and toe tip are the extreme vertices of each foot along the walking direction; the
  ball of the foot is 72 % of the way from heel to toe;
- arms: each arm's axis is fitted (principal component) to the vertices outside the torso; the
  wrist is the thinnest cross-section before the hand widens; the shoulder joint is on the
  upper arm's centre line, 2 cm inside the acromion (half of `shoulder_w` of mean_all.yaml,
  the body's measurement sheet); the elbow
  divides shoulder-wrist in the ratio of upper arm to forearm (0.186 : 0.146 of stature,
  Drillis & Contini 1966);
- spine, neck and head: centres of the torso's cross-sections at the pelvis, the waist, the
  base of the neck (where the shoulders' width collapses into the neck), and the skull base.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

# Distance between the acromions (`shoulder_w` of mean_all.yaml, the body's measurement sheet), m.
DEFAULT_SHOULDER_WIDTH = 0.364568


def read_obj(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (n, 3) float64 and triangles (m, 3) int of an OBJ with only `v` and `f` lines used."""
    verts, faces = [], []
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("v "):
                verts.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                idx = [int(t.split("/")[0]) - 1 for t in line.split()[1:]]
                faces.extend([idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1))
    if not verts or not faces:
        raise ValueError(f"{path}: no vertices or faces")
    return np.asarray(verts), np.asarray(faces, dtype=np.int64)


def y_up_to_z_up(v: np.ndarray) -> np.ndarray:
    """(x, y, z) Y-up facing +Z  ->  (x, -z, y) Z-up facing -Y (Blender's front view)."""
    return np.stack([v[:, 0], -v[:, 2], v[:, 1]], axis=1)


class Sections:
    """Horizontal cross-sections of a mesh: the points where its edges cross a plane z = const
    (vertices alone are too sparse on the long triangles of the limbs)."""

    def __init__(self, v: np.ndarray, tris: np.ndarray):
        e = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
        e = np.unique(e, axis=0)
        self.a, self.b = v[e[:, 0]], v[e[:, 1]]

    def __call__(self, z: float) -> np.ndarray:
        za, zb = self.a[:, 2], self.b[:, 2]
        hit = (np.minimum(za, zb) <= z) & (np.maximum(za, zb) > z)
        a, b = self.a[hit], self.b[hit]
        t = (z - a[:, 2]) / (b[:, 2] - a[:, 2])
        return a + (b - a) * t[:, None]


def _leg_centre(sec: Sections, z: float, side: float) -> np.ndarray:
    """Centre (bounding box in x and y) of one leg's horizontal cross-section at height z."""
    s = sec(z)
    s = s[(np.sign(s[:, 0]) == side) & (np.abs(s[:, 0]) < 0.25)]
    lo, hi = s.min(axis=0), s.max(axis=0)
    return np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, z])


def _torso_centre(sec: Sections, z: float, half_width: float) -> np.ndarray:
    s = sec(z)
    s = s[np.abs(s[:, 0]) < half_width]
    lo, hi = s.min(axis=0), s.max(axis=0)
    return np.array([0.0, (lo[1] + hi[1]) / 2, z])


def _arm(v: np.ndarray, side: float, shoulder_width: float) -> dict[str, np.ndarray]:
    pts = v[v[:, 0] * side > 0.30]  # beyond the torso: forearm and hand
    c = pts.mean(axis=0)
    axis = np.linalg.eigh(np.cov((pts - c).T))[1][:, -1]
    axis *= np.sign(axis[0] * side)  # points out towards the fingers
    t = (v - c) @ axis
    near = (v[:, 0] * side > 0.12) & (v[:, 2] > 0.45 * v[:, 2].max())  # the arm, not the leg
    tip = c + axis * t[near].max()
    # Cross-sections perpendicular to the axis: the wrist is the thinnest one in the 10 cm
    # before the hand's vertices (densely meshed fingers) start.
    sections = []
    for s in np.arange(-0.45, t[near].max(), 0.01):
        sel = near & (np.abs(t - s) < 0.005)
        p = v[sel]
        off = p - c - np.outer((p - c) @ axis, axis)
        p = p[np.linalg.norm(off, axis=1) < 0.09]
        if len(p) < 4:
            continue
        sections.append((s, p.mean(axis=0), np.ptp(p - np.outer((p - c) @ axis, axis), axis=0).max()))
    hand_start = next(s for s, _, w in sections if s > -0.2 and w > 0.075)
    wrist_s, wrist, _ = min((x for x in sections if hand_start - 0.1 <= x[0] < hand_start), key=lambda x: x[2])
    # Upper arm centre line: a line through the section centres between armpit and elbow region.
    upper = np.array([p for s, p, _ in sections if -0.42 <= s <= -0.14])
    uc = upper.mean(axis=0)
    udir = np.linalg.eigh(np.cov((upper - uc).T))[1][:, -1]
    udir *= np.sign(udir[0] * side)
    # The joint centre lies 2 cm inside the acromion (half the shoulder width) on that line.
    shoulder = uc + udir * ((side * (shoulder_width / 2 - 0.02) - uc[0]) / udir[0])
    elbow = shoulder + (wrist - shoulder) * (0.186 / (0.186 + 0.146))
    return {"shoulder": shoulder, "elbow": elbow, "wrist": wrist, "hand_tip": tip}


def find_joints(
    v: np.ndarray, tris: np.ndarray, shoulder_width: float = DEFAULT_SHOULDER_WIDTH
) -> dict[str, np.ndarray]:
    """Joint positions (Z-up, metres) by name; `.L` is +X. `v`, `tris` are the Z-up body."""
    sec = Sections(v, tris)
    height = v[:, 2].max()
    mid = v[(np.abs(v[:, 0]) < 0.01) & (v[:, 2] > 0.3 * height) & (v[:, 2] < 0.6 * height)]
    crotch = mid[:, 2].min()
    j: dict[str, np.ndarray] = {}
    for side, tag in ((1.0, "L"), (-1.0, "R")):
        hip_z = crotch + 0.058 * height
        hip = _leg_centre(sec, crotch - 0.01, side)
        hip[2] = hip_z
        ankle = _leg_centre(sec, 0.044 * height, side)
        # Popliteal hollow: the back of the leg (largest y, the body faces -Y) is shallowest.
        zs = np.arange(0.40 * hip_z, 0.80 * hip_z, 0.005)
        backs = []
        for z in zs:
            s = sec(z)
            s = s[np.sign(s[:, 0]) == side]
            backs.append(s[:, 1].max())
        backs = np.array(backs)
        # The hollow is a plateau a few cm long: take its middle, not its noisy minimum.
        knee = _leg_centre(sec, float(zs[backs <= backs.min() + 0.003].mean()), side)
        foot = v[(np.sign(v[:, 0]) == side) & (v[:, 2] < 0.03 * height)]
        heel_y, toe_y = foot[:, 1].max(), foot[:, 1].min()
        toe_tip = np.array([ankle[0], toe_y, 0.02])
        ball = np.array([ankle[0], heel_y + 0.72 * (toe_y - heel_y), 0.025])
        j.update({f"hip.{tag}": hip, f"knee.{tag}": knee, f"ankle.{tag}": ankle, f"ball.{tag}": ball})
        j[f"toe_tip.{tag}"] = toe_tip
        j[f"heel.{tag}"] = np.array([ankle[0], heel_y, 0.0])
        for k, p in _arm(v, side, shoulder_width).items():
            j[f"{k}.{tag}"] = p
    shoulder_z = j["shoulder.L"][2]
    # Base of the neck: the lowest height above the shoulder joints where the cross-section is
    # narrower than 1.5 times the neck's narrowest width.
    zs = np.arange(shoulder_z, shoulder_z + 0.25, 0.005)
    widths = np.array([np.ptp(s[np.abs(s[:, 0]) < 0.3, 0]) for s in map(sec, zs)])
    neck_min = zs[int(np.argmin(widths))]
    neck_base = zs[int(np.argmax(widths < 1.5 * widths.min()))]
    j["pelvis"] = _torso_centre(sec, crotch + 0.058 * height, 0.2)
    j["waist"] = _torso_centre(sec, crotch + 0.16 * height, 0.2)
    j["chest"] = _torso_centre(sec, crotch + 0.27 * height, 0.2)
    j["neck"] = _torso_centre(sec, neck_base, 0.15)
    # The skull base is about 6 cm above the neck's narrowest section, behind the jaw: take the
    # neck section's centre in depth, not the head's (the chin pulls that forward).
    j["head"] = np.array([0.0, _torso_centre(sec, neck_min, 0.15)[1], neck_min + 0.06])
    j["head_top"] = np.array([0.0, j["head"][1], height])
    for tag, side in (("L", 1.0), ("R", -1.0)):
        j[f"clavicle.{tag}"] = j["neck"] + np.array([side * 0.025, 0.0, -0.02])
    return j
