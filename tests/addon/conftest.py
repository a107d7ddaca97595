"""The add-on as a user installs it: `dist/tailor_addon.zip` (built by `make addon`) installed
with Blender's own extension installer into a throw-away user directory, enabled, and used
from there through the `bpy` wheel (Blender headless: operators' exec paths, data).

Run in a process of its own (`make test-addon`, which passes `--confcutdir tests/addon` so
the module tests' conftest does not import the development `tailor` first): the add-on must
use the wheel bundled in the zip, and the session fixture checks that it does.
"""

from __future__ import annotations

import importlib
import os
import shutil
import sys
import tempfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
ZIP = ROOT / "dist" / "tailor_addon.zip"
DATA = ROOT / "native" / "tailor-core" / "tests" / "data"
MODULE = "bl_ext.user_default.tailor_addon"

# The development install of `tailor` (maturin develop: a .pth entry pointing at
# native/python, possibly another git worktree's) would shadow the wheel the extension installs.
_DEV = str(ROOT / "native" / "python")
sys.path[:] = [p for p in sys.path if not (p.startswith(_DEV) or Path(p).parts[-2:] == ("native", "python"))]
assert "tailor" not in sys.modules, "run the add-on tests in their own process: make test-addon"

USER_DIR = Path(tempfile.mkdtemp(prefix="tailor-blender-user-"))
os.environ["BLENDER_USER_RESOURCES"] = str(USER_DIR)

import bpy  # noqa: E402  (after BLENDER_USER_RESOURCES is set)


@pytest.fixture(scope="session")
def addon():
    """The installed, enabled add-on package (`bl_ext.user_default.tailor_addon`)."""
    if not ZIP.is_file():
        pytest.fail(f"{ZIP} is missing: build it with `make addon`")
    result = bpy.ops.extensions.package_install_files(filepath=str(ZIP), repo="user_default", enable_on_install=True)
    assert result == {"FINISHED"}
    enabled = [a.module for a in bpy.context.preferences.addons]
    assert MODULE in enabled, enabled
    import tailor

    assert Path(tailor.__file__).is_relative_to(USER_DIR), f"tailor imported from {tailor.__file__}"
    yield importlib.import_module(MODULE)
    # bpy 4.5 hangs at exit while operator classes are registered.
    bpy.ops.preferences.addon_disable(module=MODULE)
    shutil.rmtree(USER_DIR, ignore_errors=True)


@pytest.fixture
def scene(addon):
    """An empty scene with the add-on enabled."""
    bpy.ops.wm.read_homefile(use_empty=True)
    assert MODULE in [a.module for a in bpy.context.preferences.addons]
    return bpy.context.scene


def import_pattern(path: Path, **kwargs) -> list:
    """Imports through the operator's exec path; returns the new piece objects, by name."""
    before = set(bpy.data.objects)
    assert bpy.ops.tailor.import_pattern(filepath=str(path), **kwargs) == {"FINISHED"}
    return sorted((o for o in bpy.data.objects if o not in before), key=lambda o: o.name)


def evaluated_world(obj):
    """`obj`'s vertices after its modifiers (a Mesh Cache playing), in world space ((n, 3) float64)."""
    import numpy as np

    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    me = ev.to_mesh()
    co = np.empty(len(me.vertices) * 3, np.float32)
    me.vertices.foreach_get("co", co)
    world = np.array(ev.matrix_world, np.float64)
    ev.to_mesh_clear()
    return co.reshape(-1, 3).astype(np.float64) @ world[:3, :3].T + world[:3, 3]
