"""A piece's Fabric menu (issue 28): the library's measured fabrics set the piece's four values,
which the bake and the exported garment file use; a value changed by hand makes it Custom."""

from __future__ import annotations

import json

import bpy
import pytest

from conftest import DATA, import_pattern

SKIRT = DATA / "svg" / "skirt_two_panels.svg"


def test_a_library_fabric_sets_the_piece_and_reaches_the_garment_file(scene, addon, tmp_path):
    import tailor

    pieces = import_pattern(SKIRT, edge_length=0.08)
    p = pieces[0].tailor_piece
    assert p.fabric == "CUSTOM" and p.stretch == pytest.approx(tailor.Fabric().stretch)
    names = [i.identifier for i in p.bl_rna.properties["fabric"].enum_items]
    assert names[0] == "CUSTOM" and set(names[1:]) == {f["name"] for f in tailor.fabric_library()}
    p.fabric = "11oz-black-denim"
    denim = tailor.Fabric.named("11oz-black-denim")
    for k in ("density", "stretch", "shear", "bend", "stretch_v", "bend_bias", "bend_v"):
        assert getattr(p, k) == pytest.approx(getattr(denim, k), rel=1e-6), k
    assert p.anisotropic  # the library's fabrics are measured by direction
    assert p.fabric == "11oz-black-denim"  # setting the values did not make it Custom
    # The other piece keeps the default; the garment file carries each piece's values.
    path = tmp_path / "skirt.json"
    assert bpy.ops.tailor.export_garment(filepath=str(path)) == {"FINISHED"}
    fabrics = json.loads(path.read_text())["setup"]["fabrics"]
    by_piece = dict(zip([o.name for o in sorted(pieces, key=lambda o: o.name)], fabrics))
    assert by_piece[pieces[0].name]["stretch"] == pytest.approx(denim.stretch, rel=1e-6)
    assert by_piece[pieces[0].name]["stretch_v"] == pytest.approx(denim.stretch_v, rel=1e-6)
    assert by_piece[pieces[1].name]["stretch"] == pytest.approx(tailor.Fabric().stretch, rel=1e-6)
    assert "stretch_v" not in by_piece[pieces[1].name]  # isotropic: the four values alone
    # Imported back, the piece is anisotropic with the same directions.
    assert bpy.ops.tailor.import_garment(filepath=str(path)) == {"FINISHED"}
    again = next(o for o in bpy.context.scene.objects
                 if o.tailor_piece.is_piece and o not in pieces and o.tailor_piece.piece_name == pieces[0].tailor_piece.piece_name)
    assert again.tailor_piece.anisotropic and again.tailor_piece.bend_v == pytest.approx(denim.bend_v, rel=1e-6)
    # A direction typed by hand: Custom; Anisotropic off: the fabric is the same every way.
    p.stretch_v = 500.0
    assert p.fabric == "CUSTOM"
    p.fabric = "11oz-black-denim"
    p.anisotropic = False
    assert p.fabric == "CUSTOM"
    # A value typed by hand: Custom, the typed value kept.
    p.bend = 1e-5
    assert p.fabric == "CUSTOM" and p.bend == pytest.approx(1e-5)
    p.fabric = "gray-interlock"
    assert p.bend == pytest.approx(tailor.Fabric.named("gray-interlock").bend, rel=1e-6)
