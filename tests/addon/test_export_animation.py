"""Export Garment Animation: the baked shirt welded into one animated object, written by
Blender's Alembic and USD exporters and read back by Blender's importers: as many frames, as
many vertices, and the same positions as the welded cache the scene plays."""

from __future__ import annotations

import numpy as np
import pytest

import bpy

from conftest import evaluated_world
from simulate_scene import shirt_on_character

FRAMES = (1, 4)


@pytest.fixture
def baked(addon, tmp_path):
    sc = shirt_on_character(tmp_path / "scene.blend", frames=FRAMES, preroll=0)
    sc["scene"].tailor_simulate.transition = 0
    assert bpy.ops.tailor.bake() == {"FINISHED"}
    return sc


def export(**kw):
    before = set(bpy.data.objects)
    assert bpy.ops.tailor.export_animation(**kw) == {"FINISHED"}
    (obj,) = set(bpy.data.objects) - before
    return obj


def imported(op, path) -> bpy.types.Object:
    before = set(bpy.data.objects)
    assert op(filepath=str(path)) == {"FINISHED"}
    meshes = [o for o in set(bpy.data.objects) - before if o.type == "MESH"]
    assert len(meshes) == 1, meshes
    return meshes[0]


@pytest.mark.parametrize("fmt", ["ABC", "USD"])
def test_the_welded_animation_reads_back_frame_by_frame(baked, addon, tmp_path, fmt):
    import tailor

    scene = baked["scene"]
    path = tmp_path / f"shirt.{'abc' if fmt == 'ABC' else 'usdc'}"
    obj = export(export_format=fmt, filepath=str(path))
    assert path.is_file() and obj.name.endswith("(animated)")
    cache = tailor.read_pc2(str(tmp_path / "tailor_cache" / f"{bpy.path.clean_name(obj.name)}.pc2"))
    frames = cache["frames"]
    assert len(frames) == FRAMES[1] - FRAMES[0] + 1 and frames.shape[1] == len(obj.data.vertices)
    # Welded: fewer vertices than the pieces (the seams' two sides are one vertex).
    assert len(obj.data.vertices) < sum(len(p.data.vertices) for p in baked["pieces"])
    read = imported(bpy.ops.wm.alembic_import if fmt == "ABC" else bpy.ops.wm.usd_import, path)
    assert len(read.data.vertices) == len(obj.data.vertices)
    moved = 0.0
    for k, f in enumerate(range(FRAMES[0], FRAMES[1] + 1)):
        scene.frame_set(f)
        np.testing.assert_allclose(evaluated_world(obj), frames[k], atol=1e-5)
        np.testing.assert_allclose(evaluated_world(read), frames[k], atol=1e-4)
        moved = max(moved, float(np.abs(frames[k] - frames[0]).max()))
    assert moved > 1e-3, "the exported garment does not move over the frames"
    if fmt == "USD":  # the thickness the cloth kept from the body, as `tailor simulate --usd` writes it
        from pxr import Usd, UsdGeom

        stage = Usd.Stage.Open(str(path))
        (mesh,) = [p for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)]
        primvar = UsdGeom.PrimvarsAPI(mesh).GetPrimvar("tailor_thickness")
        assert primvar.GetInterpolation() == UsdGeom.Tokens.constant
        assert primvar.Get() == pytest.approx(scene.tailor_simulate.thickness)
    # A second export is an object of its own with a cache of its own: the first plays on.
    again = export(export_format="NONE")
    assert again.name != obj.name and (tmp_path / "tailor_cache" / f"{bpy.path.clean_name(again.name)}.pc2").is_file()
    scene.frame_set(FRAMES[1])
    np.testing.assert_allclose(evaluated_world(obj), frames[-1], atol=1e-5)


@pytest.mark.parametrize("fmt", ["ABC", "USD"])
def test_per_piece_writes_the_pieces_as_the_bake_plays_them(baked, addon, tmp_path, fmt):
    """Per Piece: each piece object its own mesh in the file, frame by frame as it plays the
    bake, and nothing added to the scene; Object Only per piece is refused (nothing to do)."""
    scene, pieces = baked["scene"], baked["pieces"]
    path = tmp_path / f"pieces.{'abc' if fmt == 'ABC' else 'usdc'}"
    before = set(bpy.data.objects)
    assert bpy.ops.tailor.export_animation(export_format=fmt, filepath=str(path), per_piece=True) == {"FINISHED"}
    assert set(bpy.data.objects) == before and path.is_file()
    expected = {}
    for f in FRAMES:
        scene.frame_set(f)
        expected[f] = {p.name: evaluated_world(p) for p in pieces}
    op = bpy.ops.wm.alembic_import if fmt == "ABC" else bpy.ops.wm.usd_import
    assert op(filepath=str(path)) == {"FINISHED"}
    read = [o for o in set(bpy.data.objects) - before if o.type == "MESH"]
    assert len(read) == len(pieces)
    by_count = {}
    for o in read:
        by_count.setdefault(len(o.data.vertices), []).append(o)
    for f in FRAMES:
        scene.frame_set(f)
        for p in pieces:
            # Matched by name (the importers keep the object's or its mesh's), else by vertex count.
            twin = next((o for o in read if p.name in o.name or p.data.name in o.name), None)
            twin = twin or by_count[len(p.data.vertices)][0]
            np.testing.assert_allclose(evaluated_world(twin), expected[f][p.name], atol=1e-4)
    with pytest.raises(RuntimeError, match="Per Piece with Object Only"):
        bpy.ops.tailor.export_animation(export_format="NONE", per_piece=True)


def test_an_unbaked_garment_is_refused(addon, tmp_path):
    shirt_on_character(tmp_path / "scene.blend", frames=FRAMES, preroll=0)
    before = set(bpy.data.objects)
    with pytest.raises(RuntimeError, match="the garment is not baked"):
        bpy.ops.tailor.export_animation(export_format="NONE")
    assert set(bpy.data.objects) == before
