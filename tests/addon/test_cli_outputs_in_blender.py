"""What `tailor simulate` writes, read by Blender (the bpy wheel) as a studio would: the USD
through Blender's USD importer, frame by frame, and an OBJ of the sequence through its OBJ
importer, each against the welded cache the same run wrote (issue 24: the files are what other
programs read, so they are tested by being read)."""

from __future__ import annotations

import subprocess
import sys

import bpy
import numpy as np

from conftest import DATA, evaluated_world

SKIRT = DATA / "garmentcode" / "flare_skirt_specification.json"
FRAMES = 3


def plate_obj(path, height: float = 0.9, half: float = 0.6) -> None:
    """A square plate at `height` (Y up, as OBJ files are), for the skirt to fall on."""
    path.write_text(f"v {-half} {height} {-half}\nv {half} {height} {-half}\nv {half} {height} {half}\n"
                    f"v {-half} {height} {half}\nf 1 3 2\nf 1 4 3\n")


def y_up_to_z_up(p: np.ndarray) -> np.ndarray:
    """Blender's importers turn a Y-up file into its Z-up world: (x, y, z) -> (x, -z, y)."""
    return np.stack([p[:, 0], -p[:, 2], p[:, 1]], axis=1)


def imported_mesh(op, path, **kw):
    before = set(bpy.data.objects)
    assert op(filepath=str(path), **kw) == {"FINISHED"}
    meshes = [o for o in set(bpy.data.objects) - before if o.type == "MESH"]
    assert len(meshes) == 1, meshes
    return meshes[0]


def test_blender_reads_the_command_lines_usd_and_obj_as_the_cache_says(scene, tmp_path):
    import tailor

    garment, body = tmp_path / "skirt.json", tmp_path / "plate.obj"
    r = subprocess.run([sys.executable, "-m", "tailor", "import", str(SKIRT), "--edge", "0.06", "-o", str(garment)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    plate_obj(body)
    r = subprocess.run([sys.executable, "-m", "tailor", "simulate", str(garment), "--collider", str(body),
                        "--frames", str(FRAMES), "--preset", "preview", "--report", str(tmp_path / "r.json"),
                        "-o", str(tmp_path / "skirt.pc2"), "--usd", str(tmp_path / "skirt.usdc"),
                        "--obj-dir", str(tmp_path / "objs")], capture_output=True, text=True)
    assert r.returncode in (0, 3), r.stderr  # a skirt on a plate may fail a check; not an error
    frames = tailor.read_pc2(str(tmp_path / "skirt.pc2"))["frames"]
    assert frames.shape[0] == FRAMES and np.abs(frames[-1] - frames[0]).max() > 1e-3  # it moved
    scene.render.fps, scene.render.fps_base = 30, 1.0
    usd = imported_mesh(bpy.ops.wm.usd_import, tmp_path / "skirt.usdc")
    assert len(usd.data.vertices) == frames.shape[1]
    assert len(usd.data.polygons) == len(tailor.read_mesh(str(tmp_path / "skirt.obj"))[1])
    for f in range(1, FRAMES + 1):  # USD time code f is the cache's frame f
        scene.frame_set(f)
        np.testing.assert_allclose(evaluated_world(usd), y_up_to_z_up(frames[f - 1]), atol=1e-5, err_msg=f"frame {f}")
    obj = imported_mesh(bpy.ops.wm.obj_import, tmp_path / "objs" / "skirt.0002.obj")
    # Blender's OBJ importer splits vertices where their UVs differ (a seam's two sides keep their
    # own): every imported vertex is one of frame 2's points, and every point is imported.
    got = evaluated_world(obj)
    want = y_up_to_z_up(frames[1])
    d = np.linalg.norm(got[:, None, :] - want[None, :, :], axis=2)
    assert d.min(axis=1).max() < 1e-5 and d.min(axis=0).max() < 1e-5
    assert obj.data.uv_layers, "the OBJ's UVs were not read"
