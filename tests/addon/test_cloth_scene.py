"""The add-on benchmark's Blender Cloth scene (`cloth_scene.py`) on the skirt, two walk frames:
the pieces joined into one mesh with one loose edge per sewn vertex pair, sewing springs on,
the body a Collision object, gravity keyed off for the assembly, and the cloth steps."""

from __future__ import annotations

import bpy
import numpy as np

import cloth_scene


def test_blender_cloth_of_the_skirt_sews_its_seams_as_loose_edges(addon, tmp_path):
    setup = cloth_scene.walking_scene("skirt", tmp_path / "skirt_walk.blend", frames=2, preroll=1, transition=1)
    assert (setup["first"], setup["gravity_off_until"], setup["start"], setup["end"]) == (1, 2, 3, 4)
    scene = bpy.context.scene
    arrays, pieces = cloth_scene.garment_arrays(scene, "skirt")
    assert len(pieces) == 4 and len(arrays["positions"]) == sum(len(o.data.vertices) for o in pieces)
    _, scenes, _ = cloth_scene.peers()
    want = scenes.vertex_pairs(arrays)
    obj, mod, pairs = cloth_scene.blender_cloth(scene, arrays, setup, quality=2)

    # The seams as loose edges: exactly one per sewn vertex pair, between those vertices.
    loose = sorted(tuple(sorted(e.vertices)) for e in obj.data.edges if e.is_loose)
    assert len(loose) == len(pairs) == len(want) > 0
    assert loose == sorted(map(tuple, np.asarray(want).tolist()))
    assert len(want) <= len(arrays["seam_a_vertices"])
    cs = mod.settings
    assert cs.use_sewing_springs and cs.sewing_force_max == 0.0
    assert mod.collision_settings.use_collision
    assert mod.collision_settings.use_self_collision == bool(cloth_scene.sample_settings("skirt")["self_collision"])
    body = bpy.data.objects[setup["collider"]]
    assert body.modifiers[-1].type == "COLLISION" and body.modifiers[0].type == "ARMATURE"
    assert len(pieces[0].data.vertices) and all(o.hide_viewport for o in pieces)

    # Gravity off for the assembly, on from the transition; the walk plays from `start`.
    # `cloth_scene._fcurves`: Blender 5.0's layered actions keep their curves in channel bags.
    fc = next(c for c in cloth_scene._fcurves(obj.animation_data.action)
              if c.data_path.endswith("effector_weights.gravity"))
    assert fc.evaluate(2) == 0.0 and fc.evaluate(3) == 1.0
    assert bpy.data.objects["Rig"].data.pose_position == "POSE"

    # It simulates: every frame finite, the cloth moves, the pins (the waistband) hold.
    for f in range(setup["first"] + 1, setup["end"] + 1):
        scene.frame_set(f)
        x = cloth_scene.evaluated_vertices(obj)
        assert np.isfinite(x).all()
    assert np.abs(x - arrays["positions"]).max() > 1e-4
    pinned = arrays["pinned"][arrays["pin_weights"] >= 0.999]
    assert len(pinned) and np.abs(x[pinned] - arrays["positions"][pinned]).max() < 1e-4
