"""The add-on folder loaded directly (the legacy add-on path of Blender 3.4 to 4.1): it unpacks
its bundled wheel and registers, in a fresh process where `tailor` is not installed."""

import os
import shutil
import subprocess
import sys
import textwrap

from conftest import ROOT

SCRIPT = textwrap.dedent("""
    import sys
    # Any development install (a .pth entry to native/python, maybe another worktree's) goes.
    sys.path[:] = [p for p in sys.path if not (p.startswith({dev!r}) or p.rstrip("/").endswith("native/python"))]
    sys.path.insert(0, {folder!r})
    import bpy
    import tailor_addon
    assert "tailor" not in sys.modules
    tailor_addon.register()
    import tailor
    print("TAILOR", tailor.__file__)
    assert tailor.__file__.startswith({folder!r})
    assert bpy.ops.tailor.import_pattern(filepath={pattern!r}) == {{"FINISHED"}}
    print("PIECES", len([o for o in bpy.data.objects if o.tailor_piece.is_piece]))
    tailor_addon.unregister()
    """)


def test_legacy_folder_unpacks_its_wheel_and_imports(tmp_path):
    staged = ROOT / "build" / "addon" / "tailor_addon"
    assert (staged / "wheels").is_dir(), "build the add-on first: make addon"
    shutil.copytree(staged, tmp_path / "tailor_addon")
    pattern = ROOT / "native/tailor-core/tests/data/svg/skirt_two_panels.svg"
    code = SCRIPT.format(dev=str(ROOT / "native" / "python"), folder=str(tmp_path), pattern=str(pattern))
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user"))
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "PIECES 2" in run.stdout
    assert (tmp_path / "tailor_addon" / "_vendor").is_dir()
