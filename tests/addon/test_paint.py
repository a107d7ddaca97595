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
