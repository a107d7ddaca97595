"""Export Welded Garment through the operator's exec path: one mesh object merged along the
seams (equal and unequal), at the evaluated positions, UVs and materials kept, written as OBJ or
glTF; a
piece whose modifiers change its vertex count is refused with a report and nothing added."""

import numpy as np
import pytest

import bpy

from conftest import DATA, import_pattern

SKIRT_SVG = DATA / "svg/skirt_two_panels.svg"


def two_panels_sewn(addon, back_edge=None):
    import_pattern(SKIRT_SVG, edge_length=0.05)
    front, back = bpy.data.objects["skirt front"], bpy.data.objects["skirt back"]
    if back_edge is not None:
        for o in (front, back):
            o.select_set(o == back)
        bpy.context.view_layer.objects.active = back
        assert bpy.ops.tailor.set_resolution(edge_length=back_edge) == {"FINISHED"}
    mf, mb = (addon.core.mesh_of(o.tailor_piece) for o in (front, back))
    mode = "EQUAL" if back_edge is None else "UNEQUAL"
    assert bpy.ops.tailor.seam_add(
        name="side", mode=mode, piece_a=front.name, a_start=mf.corners[0], a_end=mf.corners[1], a_direction="CCW",
        piece_b=back.name, b_start=mb.corners[1], b_end=mb.corners[0] if back_edge else -1, b_direction="CW",
    ) == {"FINISHED"}
    return front, back


def faces(obj) -> np.ndarray:
    me = obj.data
    loops = np.empty(len(me.loops), np.int32)
    me.loops.foreach_get("vertex_index", loops)
    assert all(len(p.vertices) == 3 for p in me.polygons)
    return loops.reshape(-1, 3)


def boundary_edges(tris: np.ndarray) -> int:
    e = np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    _, counts = np.unique(e, axis=0, return_counts=True)
    assert (counts <= 2).all()
    return int(np.count_nonzero(counts == 1))


def export(**kw):
    before = set(bpy.data.objects)
    assert bpy.ops.tailor.export_welded(**kw) == {"FINISHED"}
    (obj,) = set(bpy.data.objects) - before
    return obj


def test_an_equal_seam_welds_its_vertices_at_the_evaluated_positions(scene, addon):
    front, back = two_panels_sewn(addon)
    (item,) = scene.tailor.seams
    # A modifier that moves the front (as a Mesh Cache playing a baked frame would).
    mod = front.modifiers.new("lift", "DISPLACE")
    mod.direction, mod.strength, mod.mid_level = "Z", 0.2, 0.0
    obj = export()
    assert obj.name.endswith("(welded)")
    pieces = len(front.data.vertices) + len(back.data.vertices)
    # Fewer vertices by one per seam pair; the seam is no longer a border.
    assert len(obj.data.vertices) == pieces - item.a_count
    tris = faces(obj)
    assert len(tris) == len(front.data.polygons) + len(back.data.polygons)
    piece_borders = boundary_edges(faces(front)) + boundary_edges(faces(back))
    assert boundary_edges(tris) == piece_borders - 2 * (item.a_count - 1)
    co = np.empty(3 * len(obj.data.vertices), np.float32)
    obj.data.vertices.foreach_get("co", co)
    z = co.reshape(-1, 3)[:, 2]
    # Front-only vertices are lifted 20 cm, back-only ones are not, seam vertices half way.
    assert np.isclose(z, 0.2, atol=1e-5).sum() == len(front.data.vertices) - item.a_count
    assert np.isclose(z, 0.0, atol=1e-5).sum() == len(back.data.vertices) - item.a_count
    assert np.isclose(z, 0.1, atol=1e-5).sum() == item.a_count
    # UVs (the rest shape) are kept per corner: every welded corner's UV is a piece's.
    uv = obj.data.uv_layers["TailorRest"]
    values = np.empty(2 * len(obj.data.loops), np.float32)
    uv.data.foreach_get("uv", values)
    rest = np.concatenate([addon.scene_data.rest_of(o) for o in (front, back)])
    d = np.abs(values.reshape(-1, 1, 2) - rest[None]).max(axis=2).min(axis=1)
    assert d.max() < 1e-5
    # The pieces are untouched.
    assert "(welded)" not in front.name and len(front.modifiers) == 1


def test_an_unequal_seam_welds_watertight_and_writes_obj_and_glb(scene, addon, tmp_path):
    front, back = two_panels_sewn(addon, back_edge=0.03)
    (item,) = scene.tailor.seams
    assert item.a_count != item.b_count
    path = tmp_path / "skirt.obj"
    obj = export(export_format="OBJ", filepath=str(path))
    w = addon.core.welded.weld(addon.scene_data.build_garment(scene))
    s = w.stats
    pieces = len(front.data.vertices) + len(back.data.vertices)
    assert s["inserted_points"] > 0
    assert len(obj.data.vertices) == pieces - s["merged"] + s["inserted_points"] + s["centroids"]
    # Watertight: both sides' seam edges are interior now, every other border is kept.
    piece_borders = boundary_edges(faces(front)) + boundary_edges(faces(back))
    assert boundary_edges(faces(obj)) == piece_borders - (item.a_count - 1) - (item.b_count - 1)
    text = path.read_text()
    assert sum(line.startswith("v ") for line in text.splitlines()) == len(obj.data.vertices)
    assert any(line.startswith("vt ") for line in text.splitlines())
    glb = tmp_path / "skirt.glb"
    export(export_format="GLB", filepath=str(glb))
    assert glb.read_bytes()[:4] == b"glTF"


def face_materials(obj) -> np.ndarray:
    index = np.empty(len(obj.data.polygons), np.int32)
    obj.data.polygons.foreach_get("material_index", index)
    return np.array([obj.data.materials[i].name for i in index]) if len(obj.data.materials) else np.array([])


def test_the_pieces_materials_are_kept_face_by_face(scene, addon, tmp_path):
    front, back = two_panels_sewn(addon)
    denim, lining, trim = (bpy.data.materials.new(n) for n in ("denim", "lining", "trim"))
    front.data.materials.append(denim)
    back.data.materials.append(lining)
    back.data.materials.append(trim)
    # The back's first ten faces in its second slot.
    index = np.zeros(len(back.data.polygons), np.int32)
    index[:10] = 1
    back.data.polygons.foreach_set("material_index", index)
    order = addon.scene_data.piece_objects(scene, None)  # the garment's piece order
    obj = export()
    first_met = list(dict.fromkeys(m.name for o in order for m in o.data.materials))
    assert [m.name for m in obj.data.materials] == first_met and set(first_met) == {"denim", "lining", "trim"}
    got = face_materials(obj)
    want = np.concatenate([face_materials(o) for o in order])
    # Equal seam: the welded faces are the pieces' faces in garment order.
    assert len(got) == len(want) and (got == want).all()


def test_an_unequal_seam_keeps_each_split_face_in_its_pieces_material(scene, addon, tmp_path):
    front, back = two_panels_sewn(addon, back_edge=0.03)
    front.data.materials.append(bpy.data.materials.new("denim"))
    back.data.materials.append(bpy.data.materials.new("lining"))
    path = tmp_path / "skirt.obj"
    obj = export(export_format="OBJ", filepath=str(path))
    got = face_materials(obj)
    assert set(got) == {"denim", "lining"}
    assert (got == "denim").sum() >= len(front.data.polygons) and (got == "lining").sum() >= len(back.data.polygons)
    assert "usemtl denim" in path.read_text() and (tmp_path / "skirt.mtl").exists()


def test_a_modifier_that_changes_the_vertex_count_is_refused(scene, addon):
    front, _ = two_panels_sewn(addon)
    front.modifiers.new("subdivide", "SUBSURF")
    before = set(bpy.data.objects), len(bpy.data.meshes)
    failed = "Exporting the welded garment failed: piece 'skirt front' has .* after its modifiers"
    with pytest.raises(RuntimeError, match=failed):
        bpy.ops.tailor.export_welded()
    assert (set(bpy.data.objects), len(bpy.data.meshes)) == before
