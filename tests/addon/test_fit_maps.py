"""Fit maps in a bake (issue 28): with a Fit Map chosen, the bake keeps every frame's
`Simulation.fit_maps`, writes them beside its caches (`GARMENT.maps.npz`) and the report names
the file; playing the timeline writes the frame's maps onto the pieces as point attributes and
the chosen map's colours as the active colour attribute. Without a Fit Map, none of it."""

from __future__ import annotations

import os

import numpy as np

import bpy

from simulate_scene import shirt_on_character

FRAMES = (1, 4)


def attribute(obj, name) -> np.ndarray:
    out = np.empty(len(obj.data.vertices), np.float32)
    obj.data.attributes[name].data.foreach_get("value", out)
    return out


def test_a_bake_keeps_its_fit_maps_and_the_timeline_shows_them(addon, tmp_path):
    sc = shirt_on_character(tmp_path / "scene.blend", frames=FRAMES, preroll=0)
    scene, pieces = sc["scene"], sc["pieces"]
    scene.tailor_simulate.transition = 0
    scene.tailor_simulate.fit_map = "STRAIN"
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    path = bpy.path.abspath(scene.tailor_simulate.baked_fit_maps)
    assert path.endswith(".maps.npz") and os.path.isfile(path)
    z = np.load(path)
    n = sum(len(o.data.vertices) for o in pieces)
    assert z["frames"].tolist() == list(range(FRAMES[0], FRAMES[1] + 1))
    assert {k: z[k].shape for k in ("strain", "pressure", "distance")} == {k: (4, n) for k in ("strain", "pressure", "distance")}
    names, offsets = [str(x) for x in z["piece_names"]], z["offsets"]
    assert offsets[-1] == n and sorted(names) == sorted(o.name for o in pieces)
    fit = addon.core.fit_maps
    for frame in (3, 1):
        scene.frame_set(frame)
        row = frame - FRAMES[0]
        for k, name in enumerate(names):
            obj = bpy.data.objects[name]
            a, b = offsets[k], offsets[k + 1]
            for key, attr in fit.ATTRIBUTES.items():
                np.testing.assert_array_equal(attribute(obj, attr), z[key][row][a:b])
            col = obj.data.color_attributes.active_color
            assert col is not None and col.name == fit.COLOUR_ATTRIBUTE
            rgba = np.empty(len(obj.data.vertices) * 4, np.float32)
            col.data.foreach_get("color", rgba)
            np.testing.assert_allclose(rgba.reshape(-1, 4), fit.colours("STRAIN", z["strain"][row][a:b]), atol=1e-6)
            # The overlay draws the frame as played (the Mesh Cache modifier's evaluated mesh)
            # in the map's colours, one triangle per loop triangle.
            drawn = addon.simulate.fit_map_draw.fit_map_triangles(obj, bpy.context.evaluated_depsgraph_get())
            assert drawn is not None
            pos, nrm, colours, tris = drawn
            ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
            co = np.empty(len(ev.vertices) * 3, np.float32)
            ev.vertices.foreach_get("co", co)
            obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh_clear()
            m = np.array(obj.matrix_world, np.float32)
            np.testing.assert_allclose(pos, co.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3], atol=1e-6)
            np.testing.assert_allclose(colours, rgba.reshape(-1, 4), atol=1e-6)
            np.testing.assert_allclose(np.linalg.norm(nrm, axis=1), 1.0, atol=1e-4)
            obj.data.calc_loop_triangles()
            assert tris.shape == (len(obj.data.loop_triangles), 3) and tris.max() < len(pos)
    body = next(o for o in scene.objects if o.type == "MESH" and o not in pieces)
    assert addon.simulate.fit_map_draw.fit_map_triangles(body) is None  # no map written onto it
    # The report names the maps; a bake without a Fit Map keeps none and forgets the old file.
    import json

    report = json.load(open(os.path.join(os.path.dirname(path), os.path.basename(path).replace(".maps.npz", ".report.json"))))
    assert report["fit_maps"] == os.path.basename(path)
    # A new bake forgets the old maps from its start (the handler then writes nothing while the
    # bake sets its frames), and one without a Fit Map keeps none.
    addon.simulate.job.BakeJob(scene)
    assert scene.tailor_simulate.baked_fit_maps == ""
    scene.tailor_simulate.fit_map = "NONE"
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    assert scene.tailor_simulate.baked_fit_maps == ""
