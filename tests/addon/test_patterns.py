"""Importing every pattern of the test data and changing a piece's resolution, through the
operators' exec paths."""

import numpy as np
import pytest

import bpy

from conftest import DATA, MODULE, import_pattern

FILES = sorted(
    p
    for d in ("dxf", "svg", "garmentcode")
    for p in (DATA / d).iterdir()
    if p.suffix.lower() in (".dxf", ".svg", ".json")
)
SHIRT = DATA / "garmentcode/shirt_mean_specification.json"
SKIRT_SVG = DATA / "svg/skirt_two_panels.svg"


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_import_every_test_pattern(scene, addon, path):
    import tailor

    objs = import_pattern(path, edge_length=0.04)
    edge = objs[0].tailor_piece.edge_length
    g = tailor.Garment.from_pattern(str(path), edge=edge)
    assert sorted(o.tailor_piece.piece_name for o in objs) == sorted(p.name for p in g.pieces)
    assert len(scene.tailor.seams) == len(g.seams)
    coll = objs[0].users_collection[0]
    assert coll.name == path.stem and all(o.tailor_piece.garment == coll.name for o in objs)
    for piece, mesh in zip(g.pieces, g.meshes()):
        obj = next(o for o in objs if o.tailor_piece.piece_name == piece.name)
        me = obj.data
        assert len(me.vertices) == len(mesh.rest) and len(me.polygons) == len(mesh.triangles)
        tris = np.empty(3 * len(me.polygons), np.int32)
        me.polygons.foreach_get("vertices", tris)
        np.testing.assert_array_equal(tris.reshape(-1, 3), mesh.triangles)
        contour = addon.scene_data.point_attribute(me, "tailor_contour", np.int32)
        assert np.array_equal(contour[mesh.contour], np.arange(len(mesh.contour)))
        assert (contour >= 0).sum() == len(mesh.contour)
        assert me.uv_layers.get("TailorRest") is not None
        assert tailor.Piece.from_json(obj.tailor_piece.piece_json).name == piece.name
    # Pieces without a placement are laid side by side: their boxes do not overlap.
    flat = [o for o in objs if tailor.Piece.from_json(o.tailor_piece.piece_json).placement is None]
    boxes = sorted(
        (min(v[0] for v in o.bound_box) + o.location.x, max(v[0] for v in o.bound_box) + o.location.x) for o in flat
    )
    assert all(a[1] < b[0] for a, b in zip(boxes, boxes[1:]))
    # The scene's garment is what the module builds.
    sg = addon.scene_data.build_garment(scene)
    assert sg.num_particles == sum(len(m.rest) for m in g.meshes())


def test_unfold_halves_imports_a_piece_cut_on_the_fold_whole_or_as_drawn(scene, addon):
    fold = DATA / "dxf/synthetic_fold.dxf"
    whole = import_pattern(fold, edge_length=0.03)[0]
    drawn = import_pattern(fold, edge_length=0.03, use_unfold=False)[0]
    assert len(whole.data.vertices) > len(drawn.data.vertices)
    xs = [v.co.x for v in whole.data.vertices]
    assert min(xs) == pytest.approx(-max(xs), abs=1e-6)  # mirrored about the fold


def test_cut_quantities_imports_a_pair_as_two_mirrored_pieces_or_each_piece_once(scene, addon):
    path = DATA / "dxf/synthetic_cut.dxf"
    cut = {o.name: o for o in import_pattern(path, edge_length=0.03)}
    assert sorted(cut) == ["PANEL", "SLEEVE L", "SLEEVE R"]
    assert cut["SLEEVE L"].dimensions.x == pytest.approx(cut["SLEEVE R"].dimensions.x, abs=1e-6)
    drawn = import_pattern(path, edge_length=0.03, use_quantities=False)
    assert sorted(o.name.split(".")[0] for o in drawn) == ["ALT", "PANEL", "SLEEVE"]


def test_import_menu_entry_and_bad_file_changes_nothing(scene, addon, tmp_path):
    draw_funcs = bpy.types.TOPBAR_MT_file_import._dyn_ui_initialize()
    assert any(getattr(f, "__module__", "").startswith(MODULE) for f in draw_funcs)
    junk = tmp_path / "junk.svg"
    junk.write_text("<svg but not really")
    before = (len(bpy.data.objects), len(bpy.data.collections), len(bpy.data.meshes))
    with pytest.raises(RuntimeError, match=r"Importing the pattern failed: .*junk.svg.*Check that the file is"):
        bpy.ops.tailor.import_pattern(filepath=str(junk))
    with pytest.raises(RuntimeError, match="no pattern file at"):
        bpy.ops.tailor.import_pattern(filepath=str(tmp_path / "missing.dxf"))
    assert (len(bpy.data.objects), len(bpy.data.collections), len(bpy.data.meshes)) == before


def test_set_resolution_retriangulates_in_place_and_remaps_seams(scene, addon):
    import tailor

    objs = import_pattern(SHIRT, edge_length=0.04)
    edge = objs[0].tailor_piece.edge_length
    g = tailor.Garment.from_pattern(str(SHIRT), edge=edge)
    names = [p.name for p in g.pieces]
    target = bpy.data.objects["right_ftorso"]
    i = names.index(target.name)
    # Something painted on the piece follows the new vertices.
    vg = target.vertex_groups.new(name="tailor_pin")
    vg.add(list(range(len(target.data.vertices))), 0.75, "REPLACE")
    me_before, n_before = target.data, len(target.data.vertices)
    for o in objs:
        o.select_set(o == target)
    bpy.context.view_layer.objects.active = target
    assert bpy.ops.tailor.set_resolution(edge_length=0.015) == {"FINISHED"}
    new_edge = target.tailor_piece.edge_length
    mesh = tailor.triangulate(tailor.Piece.from_json(target.tailor_piece.piece_json), new_edge)
    assert target.data == me_before and len(target.data.vertices) == len(mesh.rest) > n_before
    np.testing.assert_array_equal(addon.scene_data.rest_of(target), mesh.rest)
    w, painted = addon.paint.maps.group_weights(target, "tailor_pin")
    assert painted.all() and np.allclose(w, 0.75)
    # Seams: the same modes as the module's own remapping, and every one resolves.
    g.set_resolution(i, new_edge)
    by_name = {s.name: s for s in g.seams}
    for item in scene.tailor.seams:
        assert item.mode == by_name[item.name].mode.upper()
    sg = addon.scene_data.build_garment(scene)
    meshes = g.meshes()
    for k, item in enumerate(scene.tailor.seams):
        r = by_name[item.name].resolve(meshes)
        assert (item.a_count, item.b_count) == (len(r["a_vertices"]), len(r["b_vertices"]))
        assert sg.resolved[k]["a_vertices"] == r["a_vertices"]
    assert any(item.mode == "UNEQUAL" for item in scene.tailor.seams)


def test_set_resolution_error_changes_nothing(scene, addon):
    objs = import_pattern(SKIRT_SVG, edge_length=0.05)
    a, b = objs
    b.tailor_piece.piece_json = '{"name": "broken"}'  # another piece is damaged: the rebuild must fail first
    n = len(a.data.vertices)
    bpy.context.view_layer.objects.active = a
    for o in objs:
        o.select_set(o == a)
    with pytest.raises(RuntimeError, match="Changing the resolution failed: .*piece JSON"):
        bpy.ops.tailor.set_resolution(edge_length=0.02)
    assert len(a.data.vertices) == n and a.tailor_piece.edge_length == pytest.approx(0.05)
    bpy.ops.object.mode_set(mode="EDIT")
    with pytest.raises(RuntimeError, match="in Edit Mode"):
        bpy.ops.tailor.set_resolution(edge_length=0.02)
    bpy.ops.object.mode_set(mode="OBJECT")
