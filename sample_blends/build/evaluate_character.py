"""Evaluates character.blend in Blender: the deformed body at every frame of every action.

    .venv/bin/python sample_blends/build/evaluate_character.py sample_blends/character.blend out.npz

Writes an .npz with, per action NAME, `NAME` (frames, vertices, 3) float32 positions in
Blender's Z-up world space, frame 1 of the action first, and `meta`, a JSON string with the
scene's settings (active action, fps, frame range, unit system, camera, bones, vertex groups),
`triangles` and `dominant` (each vertex's strongest vertex group, an index into meta's groups).
Tests run it in a subprocess so that opening the .blend does not disturb other tests' Blender
state. Needs the bpy wheel: `.venv/bin/pip install "bpy==4.5.*"`.
"""

from __future__ import annotations

import json
import sys

try:
    import bpy
except ImportError:
    sys.exit('evaluate_character.py needs the bpy wheel: .venv/bin/pip install "bpy==4.5.*"')

import numpy as np


def evaluate(blend: str, out: str) -> None:
    bpy.ops.wm.open_mainfile(filepath=blend)
    scene = bpy.context.scene
    rig, body = bpy.data.objects["Rig"], bpy.data.objects["Body"]
    active = rig.animation_data.action
    arrays = {}
    actions = [t.strips[0].action for t in rig.animation_data.nla_tracks]
    for action in actions:
        rig.animation_data.action = action
        start, end = (int(x) for x in action.frame_range)
        frames = []
        for f in range(start, end + 1):
            scene.frame_set(f)
            dg = bpy.context.evaluated_depsgraph_get()
            ev = body.evaluated_get(dg)
            mesh = ev.to_mesh()
            co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
            mesh.vertices.foreach_get("co", co)
            ev.to_mesh_clear()
            world = np.array(body.matrix_world, dtype=np.float64)
            co = co.reshape(-1, 3) @ world[:3, :3].T + world[:3, 3]
            frames.append(co.astype(np.float32))
        arrays[action.name] = np.stack(frames)
    rig.animation_data.action = active
    if any(p.loop_total != 3 for p in body.data.polygons):
        sys.exit(f"{blend}: the body is not all triangles")
    tris = np.empty(len(body.data.polygons) * 3, dtype=np.int32)
    body.data.polygons.foreach_get("vertices", tris)
    # Each vertex's strongest bone, so a test can tell the arms' triangles from the torso's.
    groups = [g.name for g in body.vertex_groups]
    dominant = np.array([max(v.groups, key=lambda g: g.weight).group for v in body.data.vertices], dtype=np.int32)
    meta = {
        "active_action": active.name if active else None,
        "actions": [a.name for a in actions],
        "fps": scene.render.fps / scene.render.fps_base,
        "frame_range": [scene.frame_start, scene.frame_end],
        "unit_system": scene.unit_settings.system,
        "camera": scene.camera.name if scene.camera else None,
        "bones": [b.name for b in rig.data.bones],
        "groups": groups,
        "modifiers": [m.type for m in body.modifiers],
    }
    np.savez(out, meta=json.dumps(meta), triangles=tris.reshape(-1, 3), dominant=dominant, **arrays)


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]
    if len(args) != 2:
        sys.exit(__doc__)
    evaluate(*args)
