"""Arrange on Body (issue 25) through the installed add-on: the GarmentCode shirt imported,
the GarmentCode body (Blender's OBJ importer: Z up) marked as the collider, the operator run."""

from __future__ import annotations

from pathlib import Path

import bpy
import numpy as np
import pytest

from conftest import DATA, import_pattern

ROOT = Path(__file__).resolve().parents[2]
BODY = ROOT / "sample_blends/sources/mean_all.obj"
SHIRT = DATA / "garmentcode/shirt_mean_specification.json"


def shirt_and_body(addon, collider: bool = True):
    bpy.ops.wm.obj_import(filepath=str(BODY))
    body = bpy.context.selected_objects[0]
    if collider:
        for o in bpy.context.scene.objects:
            o.select_set(o == body)
        bpy.context.view_layer.objects.active = body
        assert bpy.ops.tailor.mark_collider() == {"FINISHED"}
    pieces = import_pattern(SHIRT, edge_length=0.03)
    for o in bpy.context.scene.objects:
        o.select_set(False)
    bpy.context.view_layer.objects.active = None
    return body, {o.tailor_piece.piece_name: o for o in pieces}


def world(addon, obj) -> np.ndarray:
    return addon.scene_data.vertex_positions(obj)


def body_arrays(body):
    import tailor  # noqa: F401  (the wheel's, installed by the add-on)

    from bl_ext.user_default.tailor_addon.simulate import gather

    dg = bpy.context.evaluated_depsgraph_get()
    return gather.evaluated_positions(body, dg), gather.evaluated_triangles(body, dg)


def test_arrange_puts_the_shirt_round_the_body(scene, addon):
    import tailor

    body, pieces = shirt_and_body(addon)
    # The pieces moved and turned off the body first: the arrangement does not depend on it.
    pieces["left_ftorso"].location.x += 0.7
    pieces["left_ftorso"].rotation_euler.z += 0.5
    bpy.context.view_layer.update()
    assert bpy.ops.tailor.arrange_on_body() == {"FINISHED"}
    bpy.context.view_layer.update()
    bv, bt = body_arrays(body)
    for name, o in pieces.items():
        co = world(addon, o)
        assert tailor.penetration(co, bv, bt)["count"] == 0, name
        c = co.mean(axis=0)
        p = o.tailor_piece
        if "ftorso" in name:
            assert p.arranged_place == "torso_front" and c[1] < -0.05, (name, c)
        elif "btorso" in name:
            assert p.arranged_place == "torso_back" and c[1] > 0.05, (name, c)
        elif name.startswith("left_sleeve"):
            assert p.arranged_place == "left_arm" and c[0] > 0.25, (name, c)
        else:
            assert p.arranged_place == "right_arm" and c[0] < -0.25, (name, c)
        assert 0.9 < c[2] < 1.5, (name, c)
    # The halves of the front meet at the centre line (their seam starts level).
    assert min(world(addon, pieces["left_ftorso"])[:, 0]) == pytest.approx(
        -max(world(addon, pieces["right_ftorso"])[:, 0]), abs=0.01)


def test_arrange_selected_pieces_with_a_chosen_place_and_clearance(scene, addon):
    import tailor

    body, pieces = shirt_and_body(addon)
    before = {n: world(addon, o) for n, o in pieces.items()}
    piece = pieces["left_btorso"]
    piece.tailor_piece.place = "torso_front"
    piece.select_set(True)
    bpy.context.view_layer.objects.active = piece
    assert bpy.ops.tailor.arrange_on_body(clearance=0.05) == {"FINISHED"}
    bpy.context.view_layer.update()
    co = world(addon, piece)
    assert piece.tailor_piece.arranged_place == "torso_front"
    assert co[:, 1].mean() < -0.05  # in front, as chosen, not at the back
    bv, bt = body_arrays(body)
    assert tailor.penetration(co, bv, bt)["count"] == 0
    # Only the selected piece moved.
    for n, o in pieces.items():
        if n != "left_btorso":
            np.testing.assert_array_equal(world(addon, o), before[n])
    # Undo-safe redo: the rest shape (the flat piece) is kept.
    rest = addon.scene_data.rest_of(piece)
    assert rest is not None and len(rest) == len(co)


def test_arrange_reports_a_missing_collider_and_a_body_that_is_no_humanoid(scene, addon):
    shirt_and_body(addon, collider=False)
    with pytest.raises(RuntimeError, match="Arranging on the body failed: the scene has no collider"):
        bpy.ops.tailor.arrange_on_body()
    bpy.ops.mesh.primitive_cube_add()
    cube = bpy.context.active_object
    assert bpy.ops.tailor.mark_collider() == {"FINISHED"}
    bpy.context.view_layer.objects.active = None
    with pytest.raises(RuntimeError, match=f"the collider '{cube.name}' is not a standing humanoid"):
        bpy.ops.tailor.arrange_on_body()


def test_show_places_finds_the_places(scene, addon):
    body, _pieces = shirt_and_body(addon)
    from bl_ext.user_default.tailor_addon.arrange import draw, operators

    operators.last_places.clear()
    bpy.context.window_manager.tailor_show_places = True
    try:
        assert operators.last_places["collider"] == body.name
        lines = draw.place_lines(operators.last_places["places"])
        assert len(lines) == 9 and all(segs.shape[1] == 3 for _, segs in lines)
    finally:
        bpy.context.window_manager.tailor_show_places = False
