"""The add-on benchmarks' start (`bench_simulate.py`, `bench_garments.py`): Blender's user
directory in a throw-away folder and the add-on installed there from `dist/tailor_addon.zip`
with Blender's own extension installer, as `conftest.py` does for the tests. Import this
before `bpy`: the user directory is read when `bpy` loads, and the development `tailor`
(maturin develop's `native/python` path) is taken off `sys.path` so that the add-on uses the
wheel bundled in the zip."""

from __future__ import annotations

import atexit
import os
import shutil
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
MODULE = "bl_ext.user_default.tailor_addon"

# As conftest.py: maturin develop's .pth entry may point at another git worktree's native/python.
sys.path[:] = [p for p in sys.path if Path(p).parts[-2:] != ("native", "python")]
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))
USER_DIR = Path(tempfile.mkdtemp(prefix="tailor-bench-user-"))
os.environ["BLENDER_USER_RESOURCES"] = str(USER_DIR)
atexit.register(shutil.rmtree, USER_DIR, ignore_errors=True)


def install(zip_path: Path | None = None) -> None:
    """Installs and enables the add-on from `zip_path` (default `dist/tailor_addon.zip`)."""
    import bpy

    zip_path = Path(zip_path or ROOT / "dist" / "tailor_addon.zip").resolve()
    if not zip_path.is_file():
        sys.exit(f"{zip_path} is missing: make addon")
    bpy.ops.extensions.package_install_files(filepath=str(zip_path), repo="user_default", enable_on_install=True)
