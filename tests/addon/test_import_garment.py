"""File > Import > Tailor Garment through the operator's exec path: a garment exported from a
scene (placed, one piece bent and one moved by hand, seams with their own factors, painted maps,
a non-default fabric and settings, the collider's painted levels) is imported into an empty
scene and exported again, and the two files hold the same garment. A bad file is a report and
changes nothing."""

from __future__ import annotations

import json
import math
import shutil

import numpy as np
import pytest

import bpy

from conftest import DATA, import_pattern

SHIRT = DATA / "garmentcode/shirt_mean_specification.json"


def add_collider(name: str = "Body"):
    """A small closed mesh (a box, 8 vertices) marked as the scene's collider."""
    me = bpy.data.meshes.new(name)
    v = [(x, y, z) for x in (-0.2, 0.2) for y in (-0.15, 0.15) for z in (0.0, 1.6)]
    f = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    me.from_pydata(v, [], f)
    obj = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(obj)
    obj.tailor_collider.is_collider = True
    return obj


def paint(obj, group: str, indices, weight: float) -> None:
    vg = obj.vertex_groups.get(group) or obj.vertex_groups.new(name=group)
    vg.add([int(i) for i in indices], weight, "REPLACE")


def levels_on(obj, levels) -> None:
    attr = obj.data.attributes.new("tailor_collision_level", "INT", "POINT")
    attr.data.foreach_set("value", np.asarray(levels, np.int32))


def garment_scene(addon) -> list:
    """The shirt at 6 cm with everything a garment file carries set away from its default."""
    pieces = import_pattern(SHIRT, edge_length=0.06)
    scene = bpy.context.scene
    # A bend (kept as the piece's stored bend, its axis taken to world space in the file).
    sleeve = next(o for o in pieces if "sleeve" in o.name)
    bpy.context.view_layer.objects.active = sleeve
    rest = addon.scene_data.rest_of(sleeve)
    c = (rest.min(axis=0) + rest.max(axis=0)) / 2
    assert bpy.ops.tailor.bend(angle=math.radians(60), axis_point=(c[0], c[1], -0.12), axis_direction=(0, 1, 0),
                               use_symmetry=True, symmetry_point=tuple(c), symmetry_direction=(0, 1),
                               threshold=0.01, use_radius=True, radius=0.09, taper=math.radians(2.0)) == {"FINISHED"}
    # A piece moved and turned by hand, one of its vertices dragged (the file keeps the shape).
    moved = pieces[0]
    moved.rotation_euler = (0.3, -0.2, 0.7)
    moved.location = (0.05, -0.02, 0.1)
    moved.data.vertices[3].co.z += 0.02
    bpy.context.view_layer.update()
    # Fabric, seam factors and the Simulate panel's settings.
    pieces[1].tailor_piece.stretch, pieces[1].tailor_piece.density = 1234.0, 0.21
    scene.tailor.seams[0].stiffness, scene.tailor.seams[1].bend_stiffness = 2.5, 0.5
    s = scene.tailor_simulate
    s.thickness, s.self_collision, s.self_collision_radius = 0.006, True, 0.007
    s.friction_static, s.friction_kinetic = 0.6, 0.4
    s.pin_mode, s.pin_stiffness, s.seam_stiffness, s.seam_bend_stiffness = "FIXED", 250.0, 5e3, 2e-5
    # Painted maps: pins (hard and soft), friction, mass and bend scale, collision levels.
    n = len(pieces[2].data.vertices)
    paint(pieces[2], "tailor_pin", range(0, 6), 1.0)
    paint(pieces[2], "tailor_pin", range(6, 9), 0.5)
    paint(pieces[3], "tailor_friction_static", range(0, 10), 0.8)
    paint(pieces[3], "tailor_friction_kinetic", range(0, 10), 0.7)
    paint(pieces[4], "tailor_mass_scale", range(0, 12), 0.75)
    paint(pieces[4], "tailor_bend_scale", range(5, 15), 0.9)
    levels_on(pieces[2], np.arange(n) % 3)
    levels_on(add_collider(), [0, 1, 2, 1, 0, 1, 2, 2])
    return pieces


def manifest(path) -> dict:
    return json.loads(path.read_text())


def rotation(placement: dict) -> np.ndarray:
    from mathutils import Euler

    return np.array(Euler([math.radians(a) for a in placement["rotation_deg"]], "ZYX").to_matrix())


def params_of(g) -> dict:
    return {(name, piece): np.asarray(values) for name, piece, values in g.particle_params}


def assert_same_setup(a: dict, b: dict) -> None:
    assert a.keys() == b.keys()
    for k in a:
        if isinstance(a[k], float):
            assert b[k] == pytest.approx(a[k], rel=1e-6), k
        elif k == "fabrics":
            assert len(a[k]) == len(b[k])
            for fa, fb in zip(a[k], b[k]):
                assert fb == pytest.approx(fa, rel=1e-6)
        elif k == "friction":
            assert b[k] == pytest.approx(a[k], rel=1e-6)
        else:
            assert b[k] == a[k], k


def assert_same_garment_files(first, second, with_collider_levels: bool = True) -> None:
    """The two garment files hold the same garment: pieces (and their meshes to 1e-6),
    resolutions and meshers, placements, bends, seams, setup and painted maps."""
    import tailor

    a, b = tailor.Garment.load(str(first)), tailor.Garment.load(str(second))
    assert [p.to_json() for p in a.pieces] == [p.to_json() for p in b.pieces]
    assert a.edge_lengths == b.edge_lengths
    for ma, mb in zip(a.meshes(), b.meshes()):
        np.testing.assert_array_equal(ma.triangles, mb.triangles)
        np.testing.assert_allclose(ma.rest, mb.rest, atol=1e-6)
    ja, jb = manifest(first), manifest(second)
    for pa, pb in zip(ja["pieces"], jb["pieces"]):
        assert pa["options"] == pb["options"]
        np.testing.assert_allclose(pb["placement"]["translation"], pa["placement"]["translation"], atol=1e-6)
        np.testing.assert_allclose(rotation(pb["placement"]), rotation(pa["placement"]), atol=1e-6)
        assert pb["placement"]["flipped"] == pa["placement"]["flipped"]
        assert (pa["bend"] is None) == (pb["bend"] is None)
        if pa["bend"] is not None:
            ba, bb = pa["bend"], pb["bend"]
            np.testing.assert_allclose(bb["axis_point"], ba["axis_point"], atol=1e-6)
            np.testing.assert_allclose(bb["axis_direction"], ba["axis_direction"], atol=1e-6)
            assert bb["angle_deg"] == pytest.approx(ba["angle_deg"], abs=1e-5)
            assert (bb["symmetry"], bb["threshold"], bb["mode"]) == (ba["symmetry"], pytest.approx(ba["threshold"]),
                                                                     ba["mode"])
            assert bb.get("radius") == pytest.approx(ba.get("radius"))
            assert bb.get("taper_deg", 0.0) == pytest.approx(ba.get("taper_deg", 0.0))
    assert [(s.name, s.a, s.b, s.mode, s.stiffness, s.bend_stiffness) for s in a.seams] == [
        (s.name, s.a, s.b, s.mode, s.stiffness, s.bend_stiffness) for s in b.seams]
    sa, sb = a.setup, b.setup
    if not with_collider_levels:
        assert sa.pop("collider_levels") is not None and sb.pop("collider_levels") is None
    assert_same_setup(sa, sb)
    pa, pb = params_of(a), params_of(b)
    assert pa.keys() == pb.keys()
    for key, values in pa.items():
        if values.dtype.kind == "f":
            np.testing.assert_allclose(pb[key], values, rtol=1e-6, atol=1e-6, err_msg=str(key))
        else:
            np.testing.assert_array_equal(pb[key], values, err_msg=str(key))


def export(path) -> None:
    path.parent.mkdir(exist_ok=True)
    assert bpy.ops.tailor.export_garment(filepath=str(path)) == {"FINISHED"}


def test_an_exported_garment_imports_and_exports_again_the_same(scene, addon, tmp_path):
    import tailor

    garment_scene(addon)
    first = tmp_path / "a" / "shirt.json"
    export(first)
    painted = {name for name, _, _ in tailor.Garment.load(str(first)).particle_params}
    assert painted == set(tailor.PAINTED_MAPS)  # every map the file can carry is in the test
    bends = [b for b in tailor.Garment.load(str(first)).bends if b is not None]
    assert [(b["radius"], b["taper_deg"]) for b in bends] == [(pytest.approx(0.09), pytest.approx(2.0))]

    bpy.ops.wm.read_homefile(use_empty=True)
    collider = add_collider()  # the mesh the levels were painted on, in the new scene too
    assert bpy.ops.tailor.import_garment(filepath=str(first)) == {"FINISHED"}
    pieces = addon.scene_data.piece_objects(bpy.context.scene)
    assert len(pieces) == 8 and len(bpy.context.scene.tailor.seams) == 18
    # As Import Sewing Pattern makes them: in a collection named after the file, each piece
    # with its pattern piece and resolution, so the module's mesh is rebuilt from them.
    assert {o.users_collection[0].name for o in pieces} == {"shirt"}
    for o in pieces:
        p = o.tailor_piece
        assert p.garment == "shirt" and p.source_path == str(first) and p.mesher == tailor.MESHER_VERSION
        assert len(addon.core.mesh_of(p).rest) == len(o.data.vertices)
    assert addon.paint.maps.collision_levels(collider).tolist() == [0, 1, 2, 1, 0, 1, 2, 2]
    assert bpy.context.scene.tailor_simulate.pin_mode == "FIXED"

    second = tmp_path / "b" / "shirt.json"  # the same name: the setup's name is the file's
    export(second)
    assert_same_garment_files(first, second)

    # The imported pieces are ordinary pieces: a new resolution re-bends the bent one and keeps the seams.
    bent = next(o for o in pieces if o.tailor_piece.bend_angle != 0.0)
    for o in pieces:
        o.select_set(o == bent)
    bpy.context.view_layer.objects.active = bent
    assert bpy.ops.tailor.set_resolution(edge_length=0.05) == {"FINISHED"}
    co = np.empty(3 * len(bent.data.vertices), np.float32)
    bent.data.vertices.foreach_get("co", co)
    assert np.ptp(co.reshape(-1, 3)[:, 2]) > 0.02  # bent again, not flat
    p = bent.tailor_piece  # onto the file's cone, radius and taper kept (issue 25)
    assert (p.bend_radius, math.degrees(p.bend_taper)) == (pytest.approx(0.09), pytest.approx(2.0))
    assert len(addon.scene_data.build_garment(bpy.context.scene).seams) == 18


def test_collider_levels_for_another_mesh_are_left_out_with_a_warning(scene, addon, tmp_path, capfd):
    garment_scene(addon)
    first = tmp_path / "a" / "shirt.json"
    export(first)
    bpy.ops.wm.read_homefile(use_empty=True)
    other = add_collider()
    other.data.vertices.add(1)  # not the mesh the levels were painted on
    capfd.readouterr()
    assert bpy.ops.tailor.import_garment(filepath=str(first)) == {"FINISHED"}
    out = capfd.readouterr()
    assert "collider collision levels were not applied" in out.out + out.err
    assert addon.paint.maps.collision_levels(other) is None
    second = tmp_path / "b" / "shirt.json"
    export(second)
    assert_same_garment_files(first, second, with_collider_levels=False)


def scene_state() -> tuple:
    scene = bpy.context.scene
    return (len(bpy.data.objects), len(bpy.data.meshes), len(bpy.data.collections), len(scene.tailor.seams),
            scene.tailor_simulate.thickness)


@pytest.mark.parametrize("damage", ["missing", "not json", "truncated", "no bin"])
def test_a_bad_file_is_reported_and_changes_nothing(scene, addon, tmp_path, damage):
    import_pattern(DATA / "svg/skirt_two_panels.svg", edge_length=0.05)
    good = tmp_path / "skirt.json"
    export(good)
    bad = tmp_path / "bad" / "skirt.json"
    bad.parent.mkdir()
    shutil.copy(good, bad)
    shutil.copy(tmp_path / "skirt.bin", bad.with_suffix(".bin"))
    if damage == "missing":
        bad = tmp_path / "nowhere.json"
    elif damage == "not json":
        bad.write_text("this is not a garment")
    elif damage == "truncated":
        bad.write_text(good.read_text()[: len(good.read_text()) // 2])
    else:
        bad.with_suffix(".bin").unlink()
    before = scene_state()
    with pytest.raises(RuntimeError, match="Importing the garment failed: "):
        bpy.ops.tailor.import_garment(filepath=str(bad))
    assert scene_state() == before
