"""Installing the zip and importing a pattern with it."""

import numpy as np

import bpy

from conftest import DATA, MODULE, import_pattern


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
    placed = np.asarray(sim.positions)
    for i, (piece, mesh) in enumerate(zip(g.pieces, g.meshes())):
        obj = bpy.data.objects[piece.name]
        assert obj.tailor_piece.is_piece and obj.tailor_piece.piece_name == piece.name
        assert len(obj.data.vertices) == len(mesh.rest) and len(obj.data.polygons) == len(mesh.triangles)
        # The object's transform is the GarmentCode placement: world positions match the module's.
        world = addon.scene_data.vertex_positions(obj)
        np.testing.assert_allclose(world, placed[offsets[i] : offsets[i] + len(mesh.rest)], atol=1e-5)
        np.testing.assert_array_equal(addon.scene_data.rest_of(obj), mesh.rest)
