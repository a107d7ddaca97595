"""The Bend operator against the module's `tailor.bend`."""

import math

import numpy as np
import pytest

import bpy

from conftest import DATA, import_pattern

SKIRT_SVG = DATA / "svg/skirt_two_panels.svg"


def local_positions(obj):
    co = np.empty(3 * len(obj.data.vertices), np.float32)
    obj.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def test_bend_matches_the_module_and_recomputes_from_flat(scene, addon):
    import tailor

    objs = import_pattern(SKIRT_SVG, edge_length=0.05)
    obj = objs[0]
    bpy.context.view_layer.objects.active = obj
    rest = addon.scene_data.rest_of(obj)
    flat = np.c_[rest, np.zeros(len(rest), np.float32)]
    c = (rest.min(axis=0) + rest.max(axis=0)) / 2
    kw = dict(
        axis_point=(c[0], c[1], -0.1),
        axis_direction=(0, 1, 0),
        use_symmetry=True,
        symmetry_point=tuple(c),
        symmetry_direction=(0, 1),
        threshold=0.01,
    )
    assert bpy.ops.tailor.bend(angle=math.radians(90), **kw) == {"FINISHED"}
    sym = (tuple(map(float, c)), (0.0, 1.0))
    ref = tailor.bend(flat, rest, (float(c[0]), float(c[1]), -0.1), (0, 1, 0), 90.0, symmetry=sym, threshold=0.01)
    np.testing.assert_allclose(local_positions(obj), ref, atol=1e-5)
    assert obj.tailor_piece.bend_angle == pytest.approx(math.radians(90)) and obj.tailor_piece.bend_symmetry
    # A second bend starts from flat again (the redo panel's behaviour), not from the bent shape.
    bpy.ops.tailor.bend(angle=math.radians(45), **kw)
    ref45 = tailor.bend(flat, rest, (float(c[0]), float(c[1]), -0.1), (0, 1, 0), 45.0, symmetry=sym, threshold=0.01)
    np.testing.assert_allclose(local_positions(obj), ref45, atol=1e-5)
    # The rest shape never changes; re-triangulating re-applies the bend to the new mesh.
    np.testing.assert_array_equal(addon.scene_data.rest_of(obj), rest)
    bpy.ops.tailor.set_resolution(edge_length=0.03)
    rest2 = addon.scene_data.rest_of(obj)
    ref2 = tailor.bend(
        np.c_[rest2, np.zeros(len(rest2), np.float32)],
        rest2,
        (float(c[0]), float(c[1]), -0.1),
        (0, 1, 0),
        45.0,
        symmetry=sym,
        threshold=0.01,
    )
    np.testing.assert_allclose(local_positions(obj), ref2, atol=1e-5)
    # The operator rolls (lengths kept), and says so to the garment file.
    assert obj.tailor_piece.bend_rolled and addon.scene_data.bend_of(obj)["mode"] == "roll"
    # Angle 0 flattens.
    bpy.ops.tailor.bend(angle=0.0, **kw)
    np.testing.assert_allclose(local_positions(obj)[:, 2], 0.0, atol=1e-7)
    assert obj.tailor_piece.bend_angle == 0.0


def test_a_piece_bent_before_the_roll_is_re_bent_as_it_was(scene, addon):
    """A piece from a file bent before the isometric bend (no `bend_rolled`) keeps the paper's
    rotation when its resolution changes, and its garment file says `rotate`."""
    import tailor

    obj = import_pattern(SKIRT_SVG, edge_length=0.05)[0]
    bpy.context.view_layer.objects.active = obj
    p = obj.tailor_piece
    rest = addon.scene_data.rest_of(obj)
    c = (rest.min(axis=0) + rest.max(axis=0)) / 2
    p.bend_angle, p.bend_axis_point, p.bend_axis_direction = math.radians(40), (c[0], c[1], -0.1), (0, 1, 0)
    assert not p.bend_rolled and addon.scene_data.bend_of(obj)["mode"] == "rotate"
    bpy.ops.tailor.set_resolution(edge_length=0.04)
    rest2 = addon.scene_data.rest_of(obj)
    flat2 = np.c_[rest2, np.zeros(len(rest2), np.float32)]
    args = (flat2, rest2, (float(c[0]), float(c[1]), -0.1), (0, 1, 0), 40.0)
    np.testing.assert_allclose(local_positions(obj), tailor.bend(*args, mode="rotate"), atol=1e-5)
    assert not np.allclose(tailor.bend(*args, mode="rotate"), tailor.bend(*args), atol=1e-3)


def test_bad_bend_is_reported_and_changes_nothing(scene, addon):
    obj = import_pattern(SKIRT_SVG, edge_length=0.05)[0]
    bpy.context.view_layer.objects.active = obj
    before = local_positions(obj)
    with pytest.raises(RuntimeError, match="Bending the piece failed: .*axis"):
        bpy.ops.tailor.bend(angle=1.0, axis_direction=(0, 0, 0))
    np.testing.assert_array_equal(local_positions(obj), before)
    assert obj.tailor_piece.bend_angle == 0.0


def test_rest_point_under_a_world_point_follows_the_bend(scene, addon):
    """Picking tools map a hit on a placed, bent piece back to its rest frame."""
    obj = import_pattern(SKIRT_SVG, edge_length=0.05)[0]
    obj.location = (0.3, -0.2, 0.5)
    obj.rotation_euler = (0.4, 0.0, 1.0)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.tailor.bend(angle=math.radians(70))
    bpy.context.view_layer.update()
    rest = addon.scene_data.rest_of(obj)
    world = addon.scene_data.vertex_positions(obj)
    for i in (0, len(rest) // 3, len(rest) - 1):
        assert addon.scene_data.rest_point(obj, world[i]) == pytest.approx(tuple(rest[i]), abs=1e-5)


def test_bend_onto_a_cone_or_to_a_radius_matches_the_module(scene, addon):
    """The redo panel's Radius and Taper (issue 25) are `tailor.bend`'s `radius` and
    `taper_deg`, stored on the piece, written to its garment file and re-applied after a
    change of resolution."""
    import tailor

    obj = import_pattern(SKIRT_SVG, edge_length=0.05)[0]
    bpy.context.view_layer.objects.active = obj
    rest = addon.scene_data.rest_of(obj)
    flat = np.c_[rest, np.zeros(len(rest), np.float32)]
    c = (rest.min(axis=0) + rest.max(axis=0)) / 2
    axis = (float(c[0]), float(c[1]), -0.1)
    sym = (tuple(map(float, c)), (0.0, 1.0))
    kw = dict(axis_point=axis, axis_direction=(0, 1, 0), use_symmetry=True, symmetry_point=tuple(c),
              symmetry_direction=(0, 1))
    assert bpy.ops.tailor.bend(angle=math.radians(120), taper=math.radians(3), **kw) == {"FINISHED"}
    cone = tailor.bend(flat, rest, axis, (0, 1, 0), 120.0, symmetry=sym, taper_deg=3.0)
    np.testing.assert_allclose(local_positions(obj), cone, atol=1e-5)
    assert not np.allclose(cone, tailor.bend(flat, rest, axis, (0, 1, 0), 120.0, symmetry=sym), atol=1e-3)
    assert addon.scene_data.bend_of(obj)["taper_deg"] == pytest.approx(3.0)
    assert addon.scene_data.bend_of(obj)["radius"] is None
    assert bpy.ops.tailor.bend(angle=1.0, use_radius=True, radius=0.08, taper=math.radians(-2), **kw) == {"FINISHED"}
    ref = tailor.bend(flat, rest, axis, (0, 1, 0), math.degrees(1.0), symmetry=sym, radius=0.08, taper_deg=-2.0)
    np.testing.assert_allclose(local_positions(obj), ref, atol=1e-5)
    assert addon.scene_data.bend_of(obj)["radius"] == pytest.approx(0.08)
    # A new resolution bends the new mesh onto the same cone.
    bpy.ops.tailor.set_resolution(edge_length=0.04)
    rest2 = addon.scene_data.rest_of(obj)
    ref2 = tailor.bend(np.c_[rest2, np.zeros(len(rest2), np.float32)], rest2, axis, (0, 1, 0), math.degrees(1.0),
                       symmetry=sym, radius=0.08, taper_deg=-2.0)
    np.testing.assert_allclose(local_positions(obj), ref2, atol=1e-5)
    # A cone whose apex falls inside the piece is reported, naming the setting, and changes nothing.
    before = local_positions(obj)
    with pytest.raises(RuntimeError, match="taper_deg"):
        bpy.ops.tailor.bend(angle=1.0, use_radius=True, radius=0.05, taper=math.radians(40), **kw)
    np.testing.assert_array_equal(local_positions(obj), before)


def test_the_gizmo_operator_is_the_bend_operator(scene, addon):
    """The gizmo's drag commits through Bend's exec path: run with the same values (as its redo
    panel does) it gives the same mesh and stored bend; the gizmo group shows on a piece while
    the Bend panel's Gizmo toggle is on."""
    obj = import_pattern(SKIRT_SVG, edge_length=0.05)[0]
    bpy.context.view_layer.objects.active = obj
    rest = addon.scene_data.rest_of(obj)
    c = (rest.min(axis=0) + rest.max(axis=0)) / 2
    kw = dict(angle=math.radians(150), axis_point=(c[0] + 0.02, c[1], -0.08), axis_direction=(0, 1, 0),
              use_symmetry=True, symmetry_point=(c[0] + 0.02, c[1]), symmetry_direction=(0, 1), threshold=0.01,
              use_radius=False, radius=0.05, taper=math.radians(4))
    assert bpy.ops.tailor.bend_gizmo("EXEC_DEFAULT", handle="ANGLE", **kw) == {"FINISHED"}
    by_gizmo = local_positions(obj)
    stored = {k: getattr(obj.tailor_piece, k) for k in ("bend_angle", "bend_radius", "bend_taper", "bend_threshold")}
    bpy.ops.tailor.bend(angle=0.0)
    assert bpy.ops.tailor.bend(**kw) == {"FINISHED"}
    np.testing.assert_array_equal(local_positions(obj), by_gizmo)
    assert stored == {k: getattr(obj.tailor_piece, k) for k in stored}
    # The gizmo group: registered, shown only with the toggle on and a piece active.
    group = addon.bend.gizmo_group.TAILOR_GGT_bend
    assert "bl_rna" in group.__dict__  # registered
    wm = bpy.context.window_manager
    assert not group.poll(bpy.context)
    wm.tailor_bend_gizmo = True
    try:
        assert group.poll(bpy.context)
        h, angle = addon.bend.gizmo_group.placement(obj)
        assert angle == pytest.approx(math.radians(150))
        np.testing.assert_allclose(h.centre, kw["axis_point"], atol=1e-6)
        # The radius arrow is as long as the radius the angle rolls the piece onto.
        reach = c[0] + 0.02 - rest[:, 0].min()
        reach = max(reach, rest[:, 0].max() - c[0] - 0.02) - 0.01
        assert h.radius == pytest.approx(reach / math.radians(150), rel=1e-5)
        bpy.context.view_layer.objects.active = None
        assert not group.poll(bpy.context)
    finally:
        wm.tailor_bend_gizmo = False
