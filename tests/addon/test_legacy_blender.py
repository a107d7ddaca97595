"""The legacy add-on in a real Blender (Debian's `blender`, 3.4.1), headless: it loads from its
folder, unpacks its wheel, and the exec paths run. Skips when no `blender` is installed (the
interactive tools' tests install it and drive its window under Xvfb)."""

import shutil
import subprocess
import textwrap

import pytest

from conftest import DATA, ROOT

BLENDER = shutil.which("blender")

SCRIPT = textwrap.dedent("""
    import math, sys
    try:
        import numpy
    except ImportError:
        print("NO_NUMPY")
        sys.exit(0)
    sys.path.insert(0, {folder!r})
    import bpy, tailor_addon
    tailor_addon.register()
    from tailor_addon import core, scene_data
    from tailor_addon.seams import draw
    print("VERSION", bpy.app.version_string)
    assert bpy.ops.tailor.import_pattern(filepath={shirt!r}, edge_length=0.05) == {{"FINISHED"}}
    assert bpy.ops.tailor.import_pattern(filepath={skirt!r}, edge_length=0.05) == {{"FINISHED"}}
    front, back = bpy.data.objects["skirt front"], bpy.data.objects["skirt back"]
    mf = core.mesh_of(front.tailor_piece)
    mb = core.mesh_of(back.tailor_piece)
    assert bpy.ops.tailor.seam_add(piece_a=front.name, a_start=mf.corners[0], a_end=mf.corners[1],
        a_direction="CCW", piece_b=back.name, b_start=mb.corners[1], b_direction="CW") == {{"FINISHED"}}
    assert bpy.ops.tailor.seam_flip() == {{"FINISHED"}}
    bpy.context.view_layer.objects.active = front
    for o in bpy.data.objects:
        o.select_set(o == front)
    assert bpy.ops.tailor.set_resolution(edge_length=0.03) == {{"FINISHED"}}
    assert bpy.ops.tailor.bend(angle=math.radians(60)) == {{"FINISHED"}}
    assert bpy.ops.tailor.collision_level_set(level=2, only_selected=False) == {{"FINISHED"}}
    assert bpy.ops.tailor.paint_set(map="PIN", value=1.0, only_selected=False) == {{"FINISHED"}}
    g = scene_data.build_garment(bpy.context.scene)
    sim = g.build_simulation()
    print("SEAMS", len(g.seams), "LINES", len(draw.seam_lines(bpy.context.scene)))
    try:
        bpy.ops.tailor.import_pattern(filepath="/nonexistent.svg")
        raise AssertionError("no error")
    except RuntimeError as e:
        assert "no pattern file at" in str(e)
    tailor_addon.unregister()
    print("LEGACY_OK")
    """)


@pytest.mark.skipif(BLENDER is None, reason="no `blender` executable (Debian's blender package)")
def test_legacy_addon_in_blender_headless(tmp_path):
    staged = ROOT / "build" / "addon" / "tailor_addon"
    assert (staged / "wheels").is_dir(), "build the add-on first: make addon"
    shutil.copytree(staged, tmp_path / "tailor_addon")
    script = tmp_path / "run.py"
    script.write_text(
        SCRIPT.format(
            folder=str(tmp_path),
            shirt=str(DATA / "garmentcode/shirt_mean_specification.json"),
            skirt=str(DATA / "svg/skirt_two_panels.svg"),
        )
    )
    run = subprocess.run(
        [BLENDER, "-b", "--factory-startup", "--python-exit-code", "1", "--python", str(script)],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=tmp_path,
    )
    if "NO_NUMPY" in run.stdout:
        pytest.skip("Blender's Python has no numpy (install python3-numpy)")
    assert run.returncode == 0 and "LEGACY_OK" in run.stdout, run.stdout[-3000:] + run.stderr[-3000:]
    assert "SEAMS 19 LINES 19" in run.stdout
