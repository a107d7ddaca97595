"""Mesh and point-cache files through the Python module."""

from pathlib import Path

import numpy as np
import pytest

import tailor



def test_obj_and_ply_read(tmp_path):
    obj = tmp_path / "quad.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
    v, t = tailor.read_mesh(obj)
    assert v.shape == (4, 3) and v.dtype == np.float32
    assert t.shape == (2, 3)
    ply = tmp_path / "tri.ply"
    ply.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                   "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    v, t = tailor.read_mesh(ply)
    assert v.shape == (3, 3) and t.tolist() == [[0, 1, 2]]


def test_missing_and_malformed_files_name_the_file(tmp_path):
    with pytest.raises(tailor.TailorIOError, match="nope.obj"):
        tailor.read_mesh(tmp_path / "nope.obj")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nf 1 2 9\n")
    with pytest.raises(tailor.PatternError, match="bad.obj"):
        tailor.read_mesh(bad)
    with pytest.raises(tailor.PatternError, match="extension"):
        tailor.read_mesh(tmp_path / "x.stl")


def test_pc2_round_trip(tmp_path):
    frames = np.random.default_rng(1).random((5, 7, 3), dtype=np.float32)
    path = tmp_path / "cache.pc2"
    tailor.write_pc2(path, frames, start_frame=1.0, sample_rate=1.0)
    back = tailor.read_pc2(path)
    np.testing.assert_array_equal(back["frames"], frames)
    assert back["start_frame"] == 1.0
    with pytest.raises(tailor.InvalidParameterError, match=r"\(k, n, 3\)"):
        tailor.write_pc2(path, frames[0])


# Khronos' Cesium Man (CC-BY 4.0, its licence beside it), copied from ../shared so that the test
# runs without it.
CESIUM_MAN = Path(__file__).resolve().parents[1] / "native/tailor-core/tests/data/bodies/khronos-cesiumman/CesiumMan.glb"


def test_gltf_skin_animation_plays():
    m = tailor.AnimatedMesh(CESIUM_MAN)
    assert m.num_vertices == 3273 and m.triangles.shape == (4672, 3)
    (name, duration), = m.animations[:1]
    a, b = m.positions_at(0.0), m.positions_at(duration / 2)
    assert a.shape == (3273, 3) and np.abs(a - b).max() > 0.01
