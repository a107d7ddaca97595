"""Installing the zip and importing a pattern with it."""

import numpy as np
import pytest

import bpy

from conftest import DATA, MODULE, ROOT, import_pattern


def test_zip_installs_and_imports_a_garmentcode_pattern(scene, addon):
    import tailor

    assert addon.__name__ == MODULE and hasattr(bpy.types, "TAILOR_OT_import_pattern")
    path = DATA / "garmentcode/shirt_mean_specification.json"
    objs = import_pattern(path, edge_length=0.03)
    # The stored resolution is a float32 property: the exact value the pieces were meshed at.
    edge = objs[0].tailor_piece.edge_length
    g = tailor.Garment.from_pattern(str(path), edge=edge)
    assert [o.name for o in objs] == sorted(p.name for p in g.pieces)
    assert len(scene.tailor.seams) == len(g.seams) == 18
    sim, offsets = g.build_simulation()
    # GarmentCode is Y-up: the pieces are turned to Blender's Z-up as the OBJ importer turns bodies.
    placed = np.asarray(sim.positions) @ addon.core.layout.Y_UP_TO_Z_UP.T
    for i, (piece, mesh) in enumerate(zip(g.pieces, g.meshes())):
        obj = bpy.data.objects[piece.name]
        assert obj.tailor_piece.is_piece and obj.tailor_piece.piece_name == piece.name
        assert len(obj.data.vertices) == len(mesh.rest) and len(obj.data.polygons) == len(mesh.triangles)
        # The object's transform is the GarmentCode placement: world positions match the module's.
        assert obj.rotation_mode == "ZYX"
        world = addon.scene_data.vertex_positions(obj)
        np.testing.assert_allclose(world, placed[offsets[i] : offsets[i] + len(mesh.rest)], atol=1e-5)
        np.testing.assert_array_equal(addon.scene_data.rest_of(obj), mesh.rest)


def test_placements_as_in_the_file_with_z_up(scene, addon):
    import tailor

    path = DATA / "garmentcode/flare_skirt_specification.json"
    objs = import_pattern(path, edge_length=0.05, up_axis="Z")
    g = tailor.Garment.from_pattern(str(path), edge=objs[0].tailor_piece.edge_length)
    sim, offsets = g.build_simulation()
    world = np.concatenate([addon.scene_data.vertex_positions(bpy.data.objects[p.name]) for p in g.pieces])
    np.testing.assert_allclose(world, sim.positions, atol=1e-5)


# The GarmentCode mean body, in the repository with its licence (`sample_blends/sources/`).
BODY = ROOT / "sample_blends/sources/mean_all.obj"


def test_garmentcode_shirt_sits_on_its_body_imported_by_blender(scene, addon):
    """The body through Blender's own OBJ importer (Y-up file -> Z-up) and the shirt through ours
    end up in the same frame: the shirt's box is around the body's chest."""
    bpy.ops.wm.obj_import(filepath=str(BODY))
    body = bpy.context.selected_objects[0]
    objs = import_pattern(DATA / "garmentcode/shirt_mean_specification.json", edge_length=0.05)
    bv = addon.scene_data.vertex_positions(body)
    sv = np.concatenate([addon.scene_data.vertex_positions(o) for o in objs])
    assert bv[:, 2].max() > 1.6 and bv[:, 2].min() == pytest.approx(0.0, abs=0.01)  # standing, Z up
    lo, hi = sv.min(axis=0), sv.max(axis=0)
    assert 0.9 < lo[2] and hi[2] < 1.5  # shoulders to hips
    centre = bv[(bv[:, 2] > lo[2]) & (bv[:, 2] < hi[2])].mean(axis=0)
    assert lo[0] < centre[0] < hi[0] and lo[1] < centre[1] < hi[1]


def test_scene_exports_a_garment_file_the_module_simulates_alike(scene, addon, tmp_path):
    """scene_data.garment_file: placements from the object transforms (moved, turned Y-up to
    Z-up) and bends in world space give the module the same cloth as the scene."""
    import math

    import tailor

    import_pattern(DATA / "garmentcode/shirt_mean_specification.json", edge_length=0.05)
    sleeve = bpy.data.objects["left_sleeve_f"]
    sleeve.location.x += 0.1
    sleeve.rotation_euler.z += 0.2
    bpy.context.view_layer.objects.active = sleeve
    bpy.ops.tailor.bend(angle=math.radians(40), axis_point=(0.0, 0.0, -0.1), axis_direction=(1, 0, 0))
    bpy.context.view_layer.update()
    g = addon.scene_data.garment_file(scene)
    g.save(str(tmp_path / "shirt.json"))
    g = tailor.Garment.load(str(tmp_path / "shirt.json"))
    sim, offsets = g.build_simulation()
    sg = addon.scene_data.build_garment(scene)
    assert list(offsets) == list(sg.offsets)
    np.testing.assert_allclose(sim.positions, sg.positions, atol=2e-5)
    assert len(g.seams) == len(sg.seams) == 18
    sleeve.scale.x = 2.0
    bpy.context.view_layer.update()
    with pytest.raises(addon.core.AddonError, match="is scaled"):
        addon.scene_data.garment_file(scene)


def test_export_operator_writes_a_garment_file(scene, addon, tmp_path):
    import tailor

    import_pattern(DATA / "svg/skirt_two_panels.svg", edge_length=0.05)
    # Fabric, a painted pin line, simulation settings: the file carries them for the module.
    front = bpy.data.objects["skirt front"]
    front.tailor_piece.stretch = 1234.0
    front.vertex_groups.new(name="tailor_pin").add([0, 1, 2], 1.0, "REPLACE")
    s = scene.tailor_simulate
    s.thickness, s.self_collision, s.self_collision_radius = 0.005, True, 0.007
    s.friction_static, s.friction_kinetic = 0.6, 0.4
    out = tmp_path / "skirt.json"
    assert bpy.ops.tailor.export_garment(filepath=str(out)) == {"FINISHED"}
    g = tailor.Garment.load(str(out))
    assert sorted(p.name for p in g.pieces) == ["skirt back", "skirt front"] and (tmp_path / "skirt.bin").exists()
    stored = g.setup
    params = {}
    for name, piece, values in g.particle_params:
        params.setdefault(name, {})[piece] = values
    k = [p.name for p in g.pieces].index("skirt front")
    assert stored["fabrics"][k]["stretch"] == pytest.approx(1234.0)
    assert stored["thickness"] == pytest.approx(0.005) and stored["self_collision"]
    assert stored["self_collision_radius"] == pytest.approx(0.007)
    assert stored["friction"] == {"static": pytest.approx(0.6), "kinetic": pytest.approx(0.4)}
    pin = params["pin"][k]
    assert len(pin) == len(front.data.vertices) and np.flatnonzero(pin).tolist() == [0, 1, 2]
    bpy.ops.wm.read_homefile(use_empty=True)
    with pytest.raises(RuntimeError, match="Exporting the garment failed: the scene has no garment pieces"):
        bpy.ops.tailor.export_garment(filepath=str(out))
