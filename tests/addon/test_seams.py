"""Seams through the operators' exec paths: create, flip, rename, delete, check, unequal counts,
drawing, and survival across save/reload and re-triangulation."""

import numpy as np
import pytest

import bpy

from conftest import DATA, import_pattern

SKIRT_SVG = DATA / "svg/skirt_two_panels.svg"
SHIRT = DATA / "garmentcode/shirt_mean_specification.json"


def two_panels(edge=0.05):
    import_pattern(SKIRT_SVG, edge_length=edge)
    return bpy.data.objects["skirt front"], bpy.data.objects["skirt back"]


def meshes(addon, *objs):
    return [addon.core.mesh_of(o.tailor_piece) for o in objs]


def corner_run(mesh):
    """The first two corners of a piece: a side of the panel."""
    return mesh.corners[0], mesh.corners[1]


def test_add_seam_from_contour_positions(scene, addon):
    import tailor

    front, back = two_panels()
    mf, mb = meshes(addon, front, back)
    a1, an = corner_run(mf)
    b1 = mb.corners[1]
    assert bpy.ops.tailor.seam_add(
        name="side",
        piece_a=front.name,
        a_start=a1,
        a_end=an,
        a_direction="CCW",
        piece_b=back.name,
        b_start=b1,
        b_end=-1,
        b_direction="CW",
        stiffness=2.0,
    ) == {"FINISHED"}
    (item,) = scene.tailor.seams
    path_a = tailor.candidate_paths(mf, a1, (an - a1) % len(mf.contour) + 1)[0]
    path_b = tailor.candidate_paths(mb, b1, len(path_a))[1]
    ref = tailor.Seam.from_paths("side", 0, mf, path_a, 1, mb, path_b)
    assert item.name == "side" and item.piece_a == front and item.piece_b == back
    assert tuple(item.a_start) == pytest.approx(ref.a["start"]) and tuple(item.a_end) == pytest.approx(ref.a["end"])
    assert tuple(item.b_start) == pytest.approx(ref.b["start"]) and tuple(item.b_end) == pytest.approx(ref.b["end"])
    assert (item.a_direction, item.b_direction, item.mode) == ("CCW", "CW", "EQUAL")
    assert item.a_count == item.b_count == len(path_a) and item.stiffness == 2.0
    sg = addon.scene_data.build_garment(scene)
    assert sg.seams[0].stiffness == 2.0 and len(sg.resolved[0]["a_vertices"]) == len(path_a)
    sim = sg.build_simulation()
    assert sim.num_particles == sg.num_particles
    # A second seam with the same name gets a unique one.
    bpy.ops.tailor.seam_add(
        name="side",
        piece_a=front.name,
        a_start=mf.corners[2],
        a_end=mf.corners[3],
        a_direction="CCW",
        piece_b=back.name,
        b_start=mb.corners[3],
        b_direction="CW",
    )
    assert [s.name for s in scene.tailor.seams] == ["side", "side.001"] and scene.tailor.seam_index == 1


def test_equal_seam_of_unequal_counts_is_refused_then_sewn_unequal(scene, addon):
    front, back = two_panels()
    for o in (front, back):
        o.select_set(o == back)
    bpy.context.view_layer.objects.active = back
    bpy.ops.tailor.set_resolution(edge_length=0.025)
    mf, mb = meshes(addon, front, back)
    a1, an = corner_run(mf)
    b1, bn = corner_run(mb)
    kw = dict(
        piece_a=front.name,
        a_start=a1,
        a_end=an,
        a_direction="CCW",
        piece_b=back.name,
        b_start=bn,
        b_end=b1,
        b_direction="CW",
    )
    with pytest.raises(RuntimeError, match="Adding the seam failed: .*set the seam's mode to Unequal"):
        bpy.ops.tailor.seam_add(mode="EQUAL", **kw)
    assert len(scene.tailor.seams) == 0
    assert bpy.ops.tailor.seam_add(mode="UNEQUAL", **kw) == {"FINISHED"}
    (item,) = scene.tailor.seams
    assert item.mode == "UNEQUAL" and item.a_count < item.b_count
    assert addon.scene_data.build_garment(scene).build_simulation().num_particles == len(front.data.vertices) + len(
        back.data.vertices
    )


def test_flip_rename_check_delete(scene, addon):
    front, back = two_panels()
    mf, mb = meshes(addon, front, back)
    bpy.ops.tailor.seam_add(
        piece_a=front.name,
        a_start=mf.corners[0],
        a_end=mf.corners[1],
        a_direction="CCW",
        piece_b=back.name,
        b_start=mb.corners[1],
        b_direction="CW",
    )
    item = scene.tailor.seams[0]
    before = (tuple(item.b_start), tuple(item.b_end), item.b_direction)
    r0 = addon.scene_data.build_garment(scene).resolved[0]
    assert bpy.ops.tailor.seam_flip() == {"FINISHED"}
    assert (tuple(item.b_start), tuple(item.b_end), item.b_direction) == (before[1], before[0], "CCW")
    r1 = addon.scene_data.build_garment(scene).resolved[0]
    assert r1["b_vertices"] == r0["b_vertices"][::-1] and r1["a_vertices"] == r0["a_vertices"]
    bpy.ops.tailor.seam_flip()
    assert (tuple(item.b_start), tuple(item.b_end), item.b_direction) == before

    assert bpy.ops.tailor.seam_rename(new_name="left side") == {"FINISHED"}
    assert scene.tailor.seams[0].name == "left side"
    with pytest.raises(RuntimeError, match="cannot be empty"):
        bpy.ops.tailor.seam_rename(new_name="  ")
    assert bpy.ops.tailor.seams_update() == {"FINISHED"}

    bpy.data.objects.remove(back)
    with pytest.raises(RuntimeError, match="lost one of its pieces"):
        bpy.ops.tailor.seams_update()
    assert addon.scene_data.build_garment(scene).warnings == ["seam 'left side' lost a piece and is ignored"]
    with pytest.raises(RuntimeError, match="there is no seam 5"):
        bpy.ops.tailor.seam_remove(index=5)
    assert bpy.ops.tailor.seam_remove() == {"FINISHED"} and len(scene.tailor.seams) == 0


def test_seam_lines_follow_the_pieces(scene, addon):
    front, back = two_panels()
    mf, mb = meshes(addon, front, back)
    bpy.ops.tailor.seam_add(
        piece_a=front.name,
        a_start=mf.corners[0],
        a_end=mf.corners[1],
        a_direction="CCW",
        piece_b=back.name,
        b_start=mb.corners[1],
        b_direction="CW",
    )
    item = scene.tailor.seams[0]
    ((colour, segs, active),) = addon.seams.draw.seam_lines(scene)
    assert active
    n = item.a_count
    assert colour[:3] == pytest.approx(tuple(item.color)) and segs.shape == (2 * n + 2 * (n - 1) * 2, 3)
    # Pair lines join the world positions of the sewn vertices; moving a piece moves them.
    pa = addon.scene_data.vertex_positions(front)
    r = addon.scene_data.build_garment(scene).resolved[0]
    np.testing.assert_allclose(segs[0], pa[r["pair_a_vertices"][0, 0]], atol=1e-6)
    back.location.z += 1.0
    bpy.context.view_layer.update()
    moved = addon.seams.draw.seam_lines(scene)[0][1]
    assert moved[1, 2] == pytest.approx(segs[1, 2] + 1.0)
    item.show = False
    assert addon.seams.draw.seam_lines(scene) == []
    item.show = True
    scene.tailor.show_seams = False
    assert addon.seams.draw.seam_lines(scene) == []


def test_seams_survive_save_reload_and_retriangulation(scene, addon, tmp_path):
    import_pattern(SHIRT, edge_length=0.04)
    stored = [(s.name, tuple(s.a_start), tuple(s.b_end), s.mode, s.piece_a.name) for s in scene.tailor.seams]
    gaps = addon.scene_data.build_garment(scene).build_simulation().seam_gaps()
    path = tmp_path / "shirt.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.read_homefile(use_empty=True)
    assert len(bpy.context.scene.tailor.seams) == 0
    bpy.ops.wm.open_mainfile(filepath=str(path))
    scene = bpy.context.scene
    assert [(s.name, tuple(s.a_start), tuple(s.b_end), s.mode, s.piece_a.name) for s in scene.tailor.seams] == stored
    assert addon.scene_data.build_garment(scene).build_simulation().seam_gaps() == pytest.approx(gaps)
    # Re-triangulate every piece, save and reload again: the seams still resolve.
    for o in bpy.data.objects:
        o.select_set(True)
    bpy.context.view_layer.objects.active = bpy.data.objects["left_ftorso"]
    bpy.ops.tailor.set_resolution(edge_length=0.03)
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.open_mainfile(filepath=str(path))
    sg = addon.scene_data.build_garment(bpy.context.scene)
    assert len(sg.resolved) == len(stored) and sg.build_simulation().num_particles == sg.num_particles


def test_suggested_segments_sew_corner_to_corner(scene, addon):
    """The automatic suggestion's exec path: the segment nearest each point, B reversed."""
    import tailor

    front, back = two_panels()
    mf, mb = meshes(addon, front, back)
    # A point just outside the middle of front's first corner-to-corner run, and of back's.
    cf = tailor.find_corners(mf, 150.0)
    cb = tailor.find_corners(mb, 150.0)
    pf = np.mean([mf.contour_point(cf[0]), mf.contour_point(cf[1])], axis=0)
    pb = np.mean([mb.contour_point(cb[0]), mb.contour_point(cb[1])], axis=0)
    assert (
        bpy.ops.tailor.seam_add_segments(piece_a=front.name, a_point=pf, piece_b=back.name, b_point=pb)
        == {"FINISHED"}
    )
    (item,) = scene.tailor.seams
    seg_a = tailor.nearest_corner_segment(mf, cf, tuple(pf))
    seg_b = tailor.nearest_corner_segment(mb, cb, tuple(pb))
    assert item.a_count == len(seg_a) and item.b_count == len(seg_b)
    assert tuple(item.a_start) == pytest.approx(mf.contour_point(seg_a.positions[0]))
    assert tuple(item.b_start) == pytest.approx(mb.contour_point(seg_b.positions[-1]))  # reversed
    assert item.mode == ("EQUAL" if len(seg_a) == len(seg_b) else "UNEQUAL")
    with pytest.raises(RuntimeError, match="fewer than two corners"):
        bpy.ops.tailor.seam_add_segments(
            piece_a=front.name, a_point=pf, piece_b=back.name, b_point=pb, corner_angle=0.01
        )
    assert len(scene.tailor.seams) == 1
