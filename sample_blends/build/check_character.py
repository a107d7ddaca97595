"""Prints the sample character's measured checks (the figures of sample_blends/README.md).

    .venv/bin/python sample_blends/build/check_character.py

Evaluates character.blend in Blender (evaluate_character.py, in a subprocess), then with the
`tailor` module: the largest distance between character.glb in `tailor.AnimatedMesh` and Blender's
deformed body over every frame of both actions, and per frame how many triangle pairs of each
arm part intersect the torso (bone regions by each vertex's strongest bone; the rest pose is the
GarmentCode source mesh, read from the .glb). Needs the bpy wheel and the built module.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

import tailor

SAMPLES = Path(__file__).resolve().parents[1]
TORSO = ["hips", "spine", "chest", "shoulder.L", "shoulder.R"]
PARTS = [f"{p}.{s}" for p in ("upper_arm", "forearm", "hand") for s in "LR"]


def crossings(p: np.ndarray, tris: np.ndarray, bone: np.ndarray) -> dict[str, int]:
    """Intersecting triangle pairs between each arm part and the torso."""
    torso = np.isin(bone, TORSO)
    base = tailor.count_self_intersections(p, tris[torso])
    out = {}
    for part in PARTS:
        limb = bone == part
        both = tailor.count_self_intersections(p, tris[torso | limb])
        out[part] = both - base - tailor.count_self_intersections(p, tris[limb])
    return out


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        npz = Path(tmp) / "evaluated.npz"
        script = SAMPLES / "build" / "evaluate_character.py"
        subprocess.run([sys.executable, str(script), str(SAMPLES / "character.blend"), str(npz)], check=True,
                       capture_output=True)
        data = np.load(npz)
        meta = json.loads(str(data["meta"]))
        tris = data["triangles"]
        bone = np.array(meta["groups"])[data["dominant"][tris[:, 0]]]
        glb = tailor.AnimatedMesh(SAMPLES / "character.glb")
        names = [n for n, _ in glb.animations]
        rest = glb.positions_at(0.0, None)
        rest = np.stack([rest[:, 0], -rest[:, 2], rest[:, 1]], axis=1)  # back to Z-up
        print("arm part vs torso, intersecting triangle pairs:", " ".join(PARTS))
        print(f"  rest: {list(crossings(rest, tris, bone).values())}")
        for action in meta["actions"]:
            frames, index = data[action], names.index(action)
            dev = max(
                float(np.abs(glb.positions_at(f / meta["fps"], index)
                             - np.stack([p[:, 0], p[:, 2], -p[:, 1]], axis=1)).max())
                for f, p in enumerate(frames)
            )
            per_frame = np.array([list(crossings(p, tris, bone).values()) for p in frames])
            print(f"  {action}: max over {len(frames)} frames {per_frame.max(axis=0).tolist()}")
            print(f"{action}: character.glb vs Blender, max deviation over {len(frames)} frames: {dev * 1e3:.4f} mm")


if __name__ == "__main__":
    main()
