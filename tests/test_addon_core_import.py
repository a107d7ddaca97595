"""File > Import > Tailor Garment's bpy-free half (`core.garment_import` and the inverses it
uses in `core.layout`, `core.paint` and `core.simulate`), against the module, without Blender.
The round trip through Blender itself is tests/addon/test_import_garment.py."""

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

import tailor

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "addon"))
from tailor_addon.core import garment_import, layout, paint  # noqa: E402
from tailor_addon.core.simulate import SimSettings, setup_settings  # noqa: E402

SKIRT_SVG = ROOT / "native/tailor-core/tests/data/svg/skirt_two_panels.svg"
SAMPLE_SKIRT = ROOT / "sample_blends/skirt.json"


def test_imports_without_blender():
    assert "bpy" not in sys.modules


def test_euler_of_inverts_rotation_matrix_also_at_gimbal_lock():
    rng = np.random.default_rng(3)
    angles = [rng.uniform(-3, 3, 3) for _ in range(200)] + [(0.3, math.pi / 2, 0.2), (-0.4, -math.pi / 2, 1.0)]
    for e in angles:
        r = layout.rotation_matrix(e)
        np.testing.assert_allclose(layout.rotation_matrix(layout.euler_of(r)), r, atol=1e-12)


def test_weights_invert_values_and_count_what_does_not_fit():
    w = np.linspace(0.0, 1.0, 21, dtype=np.float32)
    for m in paint.WEIGHT_MAPS:
        back, clipped = paint.weights(m.key, paint.values(m.key, w))
        assert clipped == 0, m.key
        lo = 0.025 if m.key == "mass_scale" else 0.0  # `values` gives the minimum mass scale below
        np.testing.assert_allclose(back, np.maximum(w, lo), atol=1e-6, err_msg=m.key)
    assert paint.weights("friction_static", [1.5, 0.5])[1] == 1
    assert paint.weights("mass_scale", [3.0, 0.01, 1.0])[1] == 2
    assert paint.weights("bend_scale", [1e3, 1e-3, 1.0])[1] == 2


def test_setup_settings_invert_the_panels_setup():
    s = SimSettings(thickness=0.006, self_collision=True, self_collision_radius=0.007, friction_static=0.6,
                    friction_kinetic=0.4, pin_mode="FIXED", pin_stiffness=250.0, seam_stiffness=5e3,
                    seam_bend_stiffness=2e-5)
    back = setup_settings(s.setup("x", []))
    assert back == {k: getattr(s, k) for k in back}


def test_up_axis_from_the_file_or_as_chosen():
    assert garment_import.turns_up("AUTO", None) and garment_import.turns_up("AUTO", "y")
    assert not garment_import.turns_up("AUTO", "z") and not garment_import.turns_up("Z", "y")
    assert garment_import.turns_up("Y", "z")


@pytest.mark.parametrize("sample", ["skirt", "layered"])
def test_a_sample_garment_is_placed_and_bent_as_the_module_places_it(sample):
    """The sample garments (GarmentCode placements, Y up; the layered one's pieces bent, with
    the paper's rotation): each piece's vertices, through its object transform, land where the
    module places and bends them, turned to Z up."""
    path = ROOT / f"sample_blends/{sample}.json"
    g = tailor.Garment.load(str(path))
    sim, offsets = g.build_simulation()
    placed = np.asarray(sim.positions) @ layout.Y_UP_TO_Z_UP.T
    imported = garment_import.read_garment_file(str(path))
    assert imported.warnings == [] and len(imported.seams) == len(g.seams)
    assert any(p.bend is not None for p in imported.pieces) == (sample == "layered")
    ends = list(offsets[1:]) + [len(placed)]
    for piece, start, end in zip(imported.pieces, offsets, ends):
        world = piece.arrays.co @ layout.rotation_matrix(piece.rotation).T + piece.location
        np.testing.assert_allclose(world, placed[start:end], atol=1e-5)
    assert imported.settings["friction_static"] == pytest.approx(g.setup["friction"]["static"])


def test_z_up_keeps_the_placements_as_they_are():
    t = json.loads(SAMPLE_SKIRT.read_text())["pieces"][0]["placement"]["translation"]
    as_is = garment_import.read_garment_file(str(SAMPLE_SKIRT), "Z")
    np.testing.assert_allclose(as_is.pieces[0].location, t, atol=1e-6)
    turned = garment_import.read_garment_file(str(SAMPLE_SKIRT))
    np.testing.assert_allclose(turned.pieces[0].location, layout.Y_UP_TO_Z_UP @ t, atol=1e-6)

def test_a_file_meshed_otherwise_is_meshed_again_with_its_paint_carried_over(tmp_path):
    """A garment written by the module at a resolution a float32 cannot hold: the add-on meshes
    it again and carries the painted pins to the nearest vertices, with a warning."""
    edge = 0.05  # not a float32: the add-on's mesh differs from the file's
    g = tailor.Garment.from_pattern(str(SKIRT_SVG), edge=edge)
    rest = g.meshes()[0].rest
    pins = (rest[:, 1] > rest[:, 1].max() - 0.02).astype(np.float32)
    g.set_painted("pin", 0, pins)
    g.save(str(tmp_path / "skirt.json"))
    imported = garment_import.read_garment_file(str(tmp_path / "skirt.json"))
    assert len(imported.warnings) == 1 and "meshed again" in imported.warnings[0]
    piece = imported.pieces[0]
    new_rest = piece.arrays.rest
    idx, w = piece.groups["tailor_pin"]
    assert (w == 1.0).all() and len(idx) > 0
    assert (new_rest[idx, 1] > rest[:, 1].max() - 0.03).all()  # the top band, on the new mesh
