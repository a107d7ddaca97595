"""tailor.motion: a collider's vertices per frame from a static mesh, a PC2 cache or a glTF skin."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import tailor
from tailor.motion import ColliderMotion

CHARACTER = Path(__file__).resolve().parents[1] / "sample_blends" / "character.glb"


def write_box_obj(path: Path) -> np.ndarray:
    v = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], np.float32)
    t = [[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
         [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]]
    with open(path, "w") as fh:
        fh.writelines(f"v {a} {b} {c}\n" for a, b, c in v)
        fh.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in t)
    return v


def test_a_static_mesh_is_its_vertices_at_every_frame(tmp_path):
    v = write_box_obj(tmp_path / "box.obj")
    m = ColliderMotion(tmp_path / "box.obj")
    assert m.kind == "static" and m.num_vertices == 8 and m.triangles.shape == (12, 3)
    assert m.triangles.dtype == np.uint32 and m.animation is None and m.animations == [] and m.duration == 0.0
    np.testing.assert_array_equal(m.rest, v)
    for f in (0, 1, 1000):
        np.testing.assert_array_equal(m.at(f), v)
    with pytest.raises(tailor.InvalidParameterError, match="frame -1"):
        m.at(-1)
    with pytest.raises(tailor.InvalidParameterError, match="not glTF"):
        ColliderMotion(tmp_path / "box.obj", animation="walk")


def test_a_pc2_cache_plays_one_frame_per_frame_and_must_fit_the_mesh(tmp_path):
    v = write_box_obj(tmp_path / "box.obj")
    frames = np.stack([v + np.float32([0.0, 0.1 * k, 0.0]) for k in range(4)])
    tailor.write_pc2(tmp_path / "box.pc2", frames)
    m = ColliderMotion(tmp_path / "box.obj", tmp_path / "box.pc2")
    assert m.kind == "cache" and m.frames == 4
    np.testing.assert_array_equal(m.rest, v)  # the mesh as stored, not the cache's first frame
    for f in range(4):
        np.testing.assert_array_equal(m.at(f), frames[f])
    np.testing.assert_array_equal(m.at(9), frames[3])  # past its end the last frame holds
    looped = ColliderMotion(tmp_path / "box.obj", tmp_path / "box.pc2", loop=True)
    np.testing.assert_array_equal(looped.at(5), frames[1])
    tailor.write_pc2(tmp_path / "short.pc2", frames[:, :7])
    with pytest.raises(tailor.InvalidParameterError, match=r"short\.pc2: the cache has 7 points but .*box\.obj has 8 "
                                                           "vertices"):
        ColliderMotion(tmp_path / "box.obj", tmp_path / "short.pc2")


def test_a_gltf_clip_plays_by_name_and_the_rest_pose_stays_available():
    skin = tailor.AnimatedMesh(CHARACTER)
    names = [n for n, _ in skin.animations]
    assert names == ["run", "walk"]
    first = ColliderMotion(CHARACTER)  # the first clip by default
    assert first.kind == "skin" and first.animation == "run" and first.animations == names
    walk = ColliderMotion(CHARACTER, animation="walk", fps=30.0)
    assert walk.animation == "walk" and walk.duration == pytest.approx(skin.animations[1][1])
    np.testing.assert_array_equal(walk.rest, skin.positions_at(0.0, None))
    np.testing.assert_array_equal(walk.at(5), skin.positions_at(5 / 30.0, 1))
    np.testing.assert_array_equal(first.at(5), skin.positions_at(5 / 30.0, 0))
    assert np.abs(walk.at(5) - first.at(5)).max() > 0.01  # another clip, another pose
    assert np.abs(walk.at(5) - walk.rest).max() > 0.01  # the rest pose is not the clip's
    # Past the clip's end the last pose holds, or with `loop` the clip starts over.
    np.testing.assert_array_equal(walk.at(100), walk.at(200))
    looped = ColliderMotion(CHARACTER, animation="walk", loop=True)
    np.testing.assert_allclose(looped.pose(walk.duration + 0.1), walk.pose(0.1), atol=1e-5)


def test_an_unknown_clip_is_an_error_naming_the_clips(tmp_path):
    with pytest.raises(tailor.InvalidParameterError, match=r"no animation 'dance' \(its animations: 'run', 'walk'\)"):
        ColliderMotion(CHARACTER, animation="dance")
    v = write_box_obj(tmp_path / "box.obj")
    tailor.write_pc2(tmp_path / "c.pc2", np.stack([v]))
    with pytest.raises(tailor.InvalidParameterError, match="one motion at a time"):
        ColliderMotion(CHARACTER, tmp_path / "c.pc2", animation="walk")
