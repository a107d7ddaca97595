"""What the simulation takes from and leaves in Blender's own data: the bake's Mesh Cache
modifier first in the stack, gravity from the scene (and older files' own gravity carried over)."""

from __future__ import annotations

import bpy

from simulate_scene import shirt_on_character


def test_the_bakes_mesh_cache_goes_first_in_the_modifier_stack(addon, tmp_path):
    sc = shirt_on_character(tmp_path / "scene.blend", frames=(1, 1), preroll=0)
    scene, pieces = sc["scene"], sc["pieces"]
    scene.tailor_simulate.transition = 0
    piece = pieces[0]
    piece.modifiers.new("Subdivision", "SUBSURF")
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    cache = addon.simulate.job.MODIFIER
    assert [m.name for m in piece.modifiers] == [cache, "Subdivision"]
    assert all(o.modifiers[0].name == cache for o in pieces)
    # The subdivided mesh is built on the cached shape (the cache plays on the base mesh).
    dg = bpy.context.evaluated_depsgraph_get()
    assert len(piece.evaluated_get(dg).data.vertices) > len(piece.data.vertices)
    # A bake again puts it back first if the artist moved it down.
    piece.modifiers.move(0, 1)
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    assert [m.name for m in piece.modifiers] == [cache, "Subdivision"]


def test_moving_a_modifier_first_by_the_operator_as_blender_3_4_does(addon, scene):
    # Blender 3.4 has no ObjectModifiers.move: compat falls back to the operator.
    me = bpy.data.meshes.new("plane")
    me.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0)], [], [(0, 1, 2)])
    obj = bpy.data.objects.new("plane", me)
    scene.collection.objects.link(obj)
    obj.modifiers.new("Subdivision", "SUBSURF")
    obj.modifiers.new("Solidify", "SOLIDIFY")
    cache = obj.modifiers.new("Cache", "MESH_CACHE")
    addon.compat.move_modifier_by_operator(obj, cache)
    assert [m.name for m in obj.modifiers] == ["Cache", "Subdivision", "Solidify"]


def test_gravity_is_the_scenes(addon, scene):
    gather = addon.simulate.gather
    assert not hasattr(scene.tailor_simulate, "gravity")  # one gravity per scene: Blender's
    scene.gravity = (0.5, -1.0, -3.75)  # exact in float32
    scene.use_gravity = True
    settings = gather.sim_settings(scene)
    assert settings.gravity == (0.5, -1.0, -3.75)
    assert tuple(settings.to_tailor().gravity) == (0.5, -1.0, -3.75)
    scene.use_gravity = False  # the scene's Gravity off: none
    assert gather.sim_settings(scene).gravity == (0.0, 0.0, 0.0)
    assert tuple(gather.sim_settings(scene).to_tailor().gravity) == (0.0, 0.0, 0.0)


def test_a_file_with_the_addons_own_gravity_opens_with_it_as_the_scenes(addon, scene, tmp_path):
    # Files saved before the add-on used the scene's gravity keep theirs as an ID property.
    scene.tailor_simulate["gravity"] = (0.0, 0.0, -4.0)
    path = tmp_path / "old.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=str(path))
    scene = bpy.context.scene
    assert tuple(scene.gravity) == (0.0, 0.0, -4.0)
    assert "gravity" not in scene.tailor_simulate.keys()
    assert addon.simulate.gather.sim_settings(scene).gravity == (0.0, 0.0, -4.0)
