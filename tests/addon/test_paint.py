"""Painting per-particle parameters from an edit-mode selection and reading them back."""

import bmesh
import numpy as np
import pytest

import bpy

from conftest import DATA, import_pattern

SKIRT_SVG = DATA / "svg/skirt_two_panels.svg"


def select(obj, idx):
    """Enters Edit Mode with exactly vertices `idx` selected (as an artist's selection)."""
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.mode_set(mode="EDIT")
    bm = bmesh.from_edit_mesh(obj.data)
    sel = np.zeros(len(bm.verts), bool)
    sel[idx] = True
    for f in bm.faces:
        f.select_set(False)
    for e in bm.edges:
        e.select_set(False)
    bm.verts.ensure_lookup_table()
    for v in bm.verts:
        v.select_set(bool(sel[v.index]))
    bmesh.update_edit_mesh(obj.data)
    return sel


def test_paint_from_edit_mode_selection_and_clear(scene, addon):
    obj = import_pattern(SKIRT_SVG, edge_length=0.05)[0]
    bpy.context.view_layer.objects.active = obj
    n = len(obj.data.vertices)
    sel = select(obj, np.arange(0, n, 3))
    assert bpy.ops.tailor.paint_set(map="FRICTION_STATIC", value=0.3) == {"FINISHED"}
    assert bpy.ops.tailor.paint_set(map="MASS_SCALE", value=1.0) == {"FINISHED"}
    assert bpy.ops.tailor.paint_set(map="BEND_SCALE", value=1.0) == {"FINISHED"}
    assert bpy.ops.tailor.collision_level_set(level=2) == {"FINISHED"}
    assert obj.mode == "EDIT"  # the artist stays where they were
    bpy.ops.object.mode_set(mode="OBJECT")
    maps = addon.paint.maps.painted_maps(obj)
    assert set(maps) == {"friction_static", "mass_scale", "bend_scale", "collision_level"}
    values, painted = maps["friction_static"]
    assert np.array_equal(painted, sel) and np.allclose(values[sel], 0.3)
    assert np.allclose(maps["mass_scale"][0][sel], 2.0)
    assert np.allclose(maps["bend_scale"][0][sel], 100.0)  # weight 1: 100x stiffer
    levels = maps["collision_level"][0]
    assert np.array_equal(levels == 2, sel) and not levels[~sel].any()
    pos, colours = addon.paint.draw.level_points(obj)
    assert pos.shape == (n, 3) and np.array_equal(colours[sel][0], addon.paint.draw.LEVEL_COLOURS[2])
    # Outside edit mode a value goes on every vertex.
    bpy.ops.tailor.paint_set(map="PIN", value=1.0)
    assert addon.paint.maps.painted_maps(obj)["pin"][1].all()
    bpy.ops.tailor.paint_clear(map="FRICTION_STATIC")
    bpy.ops.tailor.paint_clear(map="COLLISION_LEVEL")
    bpy.ops.tailor.paint_clear(map="BEND_SCALE")
    assert set(addon.paint.maps.painted_maps(obj)) == {"mass_scale", "pin"}
    with pytest.raises(RuntimeError, match="has no collision levels"):
        bpy.ops.tailor.paint_clear(map="COLLISION_LEVEL")


def test_collision_levels_on_the_character_and_empty_selection(scene, addon):
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.3)
    body = bpy.context.active_object
    select(body, [])
    with pytest.raises(RuntimeError, match="Select vertices in Edit Mode first"):
        bpy.ops.tailor.collision_level_set(level=1)
    bpy.ops.object.mode_set(mode="OBJECT")
    assert addon.paint.maps.collision_levels(body) is None
    assert bpy.ops.tailor.collision_level_set(level=1) == {"FINISHED"}
    assert (addon.paint.maps.collision_levels(body) == 1).all()
    bpy.ops.tailor.paint_weights(map="PIN")
    assert body.mode == "WEIGHT_PAINT" and body.vertex_groups.active.name == "tailor_pin"
    bpy.ops.object.mode_set(mode="OBJECT")


def test_collision_levels_painted_with_the_weight_brush(scene, addon):
    # Issue 25: levels painted like the other maps, a vertex group a level; where painted at
    # 0.5 or more they override the level set on a selection, the heaviest group winning.
    obj = import_pattern(SKIRT_SVG, edge_length=0.05)[0]
    bpy.context.view_layer.objects.active = obj
    n = len(obj.data.vertices)
    assert bpy.ops.tailor.collision_level_set(level=1) == {"FINISHED"}  # every vertex at 1
    assert bpy.ops.tailor.collision_level_paint(level=3) == {"FINISHED"}
    assert obj.mode == "WEIGHT_PAINT" and obj.vertex_groups.active.name == "tailor_level_3"
    assert bpy.context.scene.tailor.show_collision_levels
    bpy.ops.object.mode_set(mode="OBJECT")
    # What the brush would leave: strokes of weight 1, a soft edge of 0.3, and a second level
    # painted over part of the first one, heavier there.
    obj.vertex_groups["tailor_level_3"].add(list(range(0, 20)), 1.0, "REPLACE")
    obj.vertex_groups["tailor_level_3"].add(list(range(20, 30)), 0.3, "REPLACE")
    bpy.ops.tailor.collision_level_paint(level=2)
    bpy.ops.object.mode_set(mode="OBJECT")
    obj.vertex_groups["tailor_level_2"].add(list(range(10, 15)), 0.6, "REPLACE")
    obj.vertex_groups["tailor_level_2"].add(list(range(15, 20)), 1.0, "REPLACE")
    levels = addon.paint.maps.collision_levels(obj)
    want = np.ones(n, np.int32)
    want[0:15] = 3
    want[15:20] = 3  # 1.0 in level 2 ties 1.0 in level 3: a tie goes to the higher level
    assert np.array_equal(levels, want), np.nonzero(levels != want)
    obj.vertex_groups["tailor_level_3"].add(list(range(15, 20)), 0.9, "REPLACE")
    want[15:20] = 2  # now level 2 is the heavier there
    assert np.array_equal(addon.paint.maps.collision_levels(obj), want)
    # The module gets them: the garment the simulation is built from, and the overlay.
    maps = addon.paint.maps.painted_maps(obj)
    assert np.array_equal(maps["collision_level"][0], want)
    pos, colours = addon.paint.draw.level_points(obj)
    assert np.array_equal(colours[0], addon.paint.draw.LEVEL_COLOURS[3])
    assert np.array_equal(colours[40], addon.paint.draw.LEVEL_COLOURS[1])
    # Clearing the levels takes the attribute and every level group.
    assert bpy.ops.tailor.paint_clear(map="COLLISION_LEVEL") == {"FINISHED"}
    assert addon.paint.maps.collision_levels(obj) is None
    assert not [vg for vg in obj.vertex_groups if vg.name.startswith("tailor_level_")]


def test_painted_level_groups_alone_give_levels_over_zero(scene, addon):
    obj = import_pattern(SKIRT_SVG, edge_length=0.05)[0]
    bpy.context.view_layer.objects.active = obj
    bpy.ops.tailor.collision_level_paint(level=4)
    bpy.ops.object.mode_set(mode="OBJECT")
    obj.vertex_groups["tailor_level_4"].add([0, 1, 2], 1.0, "REPLACE")
    levels = addon.paint.maps.collision_levels(obj)
    assert levels[:3].tolist() == [4, 4, 4] and not levels[3:].any()
