"""Issue 25: arrangement round the body. Places found on the GarmentCode mean body from its shape
(`tailor.body_places`), pieces put on them (`tailor.place_on_body`), and the GarmentCode shirt
with its own placements replaced by the automatic arrangement (`tailor.arrange.arrange_garment`:
pieces assigned to places by their names) assembling on the body with default settings.

Measured (2026-11-27, `tailor simulate` 60 frames, CPU): the arranged shirt closes its seams by
frame 30 (0.26 mm at frame 60; GarmentCode's own placement 0.34 mm), nothing inside the body, all
of it on the body, and every piece ends within 2.5 cm (centroid) of where the shirt placed by
GarmentCode ends.
"""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import tailor
from tailor.arrange import arrange_garment

REPO = Path(__file__).resolve().parents[1]
BODY = REPO / "sample_blends/sources/mean_all.obj"
SHIRT = REPO / "native/tailor-core/tests/data/garmentcode/shirt_mean_specification.json"
HOODY = REPO / "native/tailor-core/tests/data/garmentcode/hoody_mean_specification.json"
SPECS = REPO / "native/tailor-core/tests/data/garmentcode"
FRAMES = 60  # as tests/test_assembly.py: the seams meet by frame 30, then a second on the body


@pytest.fixture(scope="module")
def body():
    return tailor.read_mesh(str(BODY))


@pytest.fixture(scope="module")
def places(body):
    return {p["name"]: p for p in tailor.body_places(*body, up="y")}


def cli(*args):
    return subprocess.run([sys.executable, "-m", "tailor", *map(str, args)], capture_output=True, text=True)


def test_the_places_are_where_the_body_parts_are(places):
    assert list(places) == list(tailor.PLACE_NAMES)
    front, back = places["torso_front"], places["torso_back"]
    # Facing +z (found from the feet), down the torso from the neck's base, round its middle.
    assert front["facing"][2] > 0.95 and back["facing"][2] < -0.95
    assert 1.40 < front["origin"][1] < 1.48 and abs(front["origin"][0]) < 0.02
    assert 0.95 < places["waist"]["origin"][1] < 1.15
    for side, sign in (("left", 1), ("right", -1)):
        arm, leg = places[f"{side}_arm"], places[f"{side}_leg"]
        assert arm["axis"][0] * sign > 0.6 and arm["axis"][1] < -0.5, arm["axis"]
        assert 0.12 < arm["origin"][0] * sign < 0.30
        assert leg["axis"][1] < -0.98 and 0.04 < leg["origin"][0] * sign < 0.14
    assert front["reach"]["values"].shape[1] == 36
    for name in ("neck", "head"):  # up from the neck's base
        assert places[name]["axis"][1] > 0.99 and places[name]["origin"] == pytest.approx(front["origin"])


def test_a_placed_piece_keeps_its_lengths_and_clears_the_body(body, places):
    mesh = tailor.Garment.from_pattern(str(SHIRT), edge=0.02).meshes()[5]  # left_ftorso
    assert mesh.name == "left_ftorso"
    placed = tailor.place_on_body(mesh.rest, places["torso_front"], clearance=0.03, side="left")
    p, r = placed["positions"], mesh.rest
    for a, b in ((0, 1), (1, 2), (2, 0)):
        i, j = mesh.triangles[:, a], mesh.triangles[:, b]
        rest_len = np.linalg.norm(r[i] - r[j], axis=1)
        change = np.abs(np.linalg.norm(p[i] - p[j], axis=1) - rest_len) / rest_len
        assert change.max() < 1e-3, change.max()
    assert tailor.penetration(p, *body)["count"] == 0
    # On the character's left, in front, its top at the neck's base.
    assert p[:, 0].min() > -0.01 and p[:, 2].min() > 0.05
    assert abs(p[:, 1].max() - places["torso_front"]["origin"][1]) < 0.01
    assert placed["bend"]["mode"] == "roll" and placed["radius"] > places["torso_front"]["radius"]


def test_names_say_where_the_pieces_go():
    square = np.array([[0, 0], [0.3, 0], [0.3, 0.4], [0, 0.4]], dtype=np.float32)
    expect = {
        "left_ftorso": ("torso_front", "left", 0.0),
        "right_btorso": ("torso_back", "right", 0.0),
        "left_sleeve_f": ("left_arm", "centre", 0.0),
        "right_sleeve_b": ("right_arm", "centre", 180.0),
        "pant_b_l": ("left_leg", "centre", 180.0),
        "skirt_front": ("waist", "centre", 0.0),
        "REGULAR TEECO": ("neck", "centre", 0.0),
        "left_hood": ("head", "centre", 90.0),
    }
    for name, want in expect.items():
        s = tailor.suggest_place(name, square)
        assert (s["place"], s["side"], s["around_deg"]) == want, name


def test_a_pattern_is_read_without_its_style_name_and_a_band_goes_round(places):
    """A drafting system's legging (as `ORILEGWB_AAMA.DXF` names it, cut as its quantities say):
    every name starts with the style, `ORILEG WB`, which alone reads as a waistband; over the
    pattern the style is left out, so the band goes round the waist and the legs on their legs
    (each whole leg's middle outside), and the band, put on the waist, is 5 cm tall."""
    band = np.array([[0, 0], [0.05, 0], [0.05, 0.87], [0, 0.87]], dtype=np.float32)
    leg = np.array([[0, 0], [0.95, 0.1], [0.95, 0.5], [0, 0.6]], dtype=np.float32)
    names = ["ORILEG WB WB", "ORILEG WB LL R", "ORILEG WB LL L"]
    got = tailor.suggest_places(names, [band, leg, leg])
    assert [(s["place"], s["along"], s["around_deg"]) for s in got] == [
        ("waist", "shortest", 0.0), ("right_leg", "longest", 90.0), ("left_leg", "longest", -90.0)]
    assert tailor.suggest_place(names[1], leg)["place"] == "waist"
    placed = tailor.place_on_body(band, places["waist"], along="shortest")
    height = placed["positions"][:, 1].max() - placed["positions"][:, 1].min()
    assert height == pytest.approx(0.05, abs=0.005)
    with pytest.raises(tailor.InvalidParameterError, match="shortest"):
        tailor.place_on_body(band, places["waist"], along="sideways")
    with pytest.raises(tailor.InvalidParameterError, match="one shape per name"):
        tailor.suggest_places(names, [band])
    # A cuff starts where its sleeve ends; numbered panels go round the waist.
    sleeve = np.array([[0, 0], [0.6, 0], [0.6, 0.4], [0, 0.4]], dtype=np.float32)
    cuff = np.array([[0, 0], [0.12, 0], [0.12, 0.04], [0, 0.04]], dtype=np.float32)
    got = tailor.suggest_places(["right_sleeve_f", "sl_right_cuff_f"], [sleeve, cuff])
    assert got[0]["offset"] == 0.0 and got[1]["offset"] == pytest.approx(0.6)
    assert (got[1]["place"], got[1]["along"]) == ("right_arm", "shortest")
    panels = tailor.suggest_places([f"skirt_panel_{k}" for k in range(4)], [sleeve] * 4)
    assert [p["around_deg"] for p in panels] == [0.0, -90.0, 180.0, 90.0]


def test_a_bodice_laid_on_its_side_goes_up_its_grain(places):
    """`synthetic_cut.dxf`'s PANEL has no grain line; its SLEEVE's runs up the drawing. A bodice
    a marker laid on its side (grain along x) goes with x down the torso, its narrower end (the
    shoulders) at the neck's base; `arrange_garment` passes each piece's grain line."""
    pieces = tailor.read_pattern(str(REPO / "native/tailor-core/tests/data/dxf/synthetic_cut.dxf")).pieces
    assert pieces[2].grain is None
    (x0, y0), (x1, y1) = pieces[0].grain
    assert (x1 - x0) == pytest.approx(0.0) and (y1 - y0) == pytest.approx(0.18)
    bodice = np.array([[0, -0.25], [0.6, -0.18], [0.6, 0.18], [0, 0.25]], dtype=np.float32)
    front = places["torso_front"]
    laid = tailor.place_on_body(bodice, front, grain=(1.0, 0.0))["positions"]
    drawn = tailor.place_on_body(bodice, front)["positions"]
    assert np.ptp(laid[:, 1]) == pytest.approx(0.6, abs=0.01) and np.ptp(drawn[:, 1]) == pytest.approx(0.5, abs=0.01)
    assert laid[1:3, 1].min() > laid[[0, 3], 1].max()  # the shoulders above the hem
    with pytest.raises(tailor.InvalidParameterError, match="grain"):
        tailor.place_on_body(bodice, front, grain=(0.0, 0.0))


def test_bad_input_is_a_typed_error(places):
    cube_v = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=np.float32)
    cube_t = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                       [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]], dtype=np.uint32)
    with pytest.raises(tailor.InvalidMeshError, match="not a standing humanoid"):
        tailor.body_places(cube_v, cube_t)
    with pytest.raises(tailor.InvalidParameterError, match="up"):
        tailor.body_places(cube_v, cube_t, up="w")
    square = np.array([[0, 0], [0.3, 0], [0.3, 0.4], [0, 0.4]], dtype=np.float32)
    broken = dict(places["torso_front"])
    del broken["axis"]
    with pytest.raises(tailor.InvalidParameterError, match="axis"):
        tailor.place_on_body(square, broken)
    with pytest.raises(tailor.InvalidParameterError, match="side"):
        tailor.place_on_body(square, places["torso_front"], side="middle")
    with pytest.raises(tailor.InvalidParameterError, match="clearance"):
        tailor.place_on_body(square, places["torso_front"], clearance=-1.0)


def simulated(arranged, tmp_path, label):
    """`arranged` through `tailor simulate` with default settings on the body, `FRAMES` frames:
    the command's result, its report's summary and last record, and the cache it wrote."""
    path, report, cache = tmp_path / f"{label}.json", tmp_path / "report.json", tmp_path / "cloth.pc2"
    arranged.save(str(path))
    r = cli("simulate", path, "--collider", BODY, "--frames", FRAMES, "--report", report, "-o", cache)
    rep = json.loads(report.read_text())
    return r, rep["summary"], rep["frames"][-1], cache


def assembles_where_its_own_placement_ends(garment, arranged, tmp_path, label):
    """`arranged` (``garment`` arranged on the body) through `tailor simulate` with default
    settings: assembled (verdict empty, seams under 1 mm, nothing inside, on the body), and each
    piece ending within 5 cm (centroid) of where ``garment``'s own placement ends it. Returns
    per piece its last frame's positions, arranged."""
    r, s, last, cache = simulated(arranged, tmp_path, label)
    print(f"arranged {label}: exit {r.returncode}, verdict {s['verdict']}, seam gap "
          f"{last['seam_gap_max_m'] * 1e3:.2f} mm, inside {last['penetration_count']}, "
          f"on body {last['on_body_fraction']:.2f}")
    assert r.returncode == 0 and s["verdict"] == [], (r.returncode, s["verdict"], r.stdout[-1500:])
    assert last["penetration_count"] == 0 and not s["nan"], last
    assert last["seam_gap_max_m"] < 1e-3, last
    assert last["on_body_fraction"] > 0.95, last
    # Worn as its own placement wears it: each piece ends near where that one does.
    base, base_report, base_cache = tmp_path / "base.json", tmp_path / "base_report.json", tmp_path / "base.pc2"
    garment.save(str(base))
    assert cli("simulate", base, "--collider", BODY, "--frames", FRAMES, "--report", base_report,
               "-o", base_cache).returncode == 0
    ours, theirs = tailor.read_pc2(str(cache))["frames"][-1], tailor.read_pc2(str(base_cache))["frames"][-1]
    offset, out = 0, {}
    for piece, mesh in zip(garment.pieces, garment.meshes()):
        n = len(mesh.rest)
        mine = ours[offset:offset + n]
        shift = np.linalg.norm(mine.mean(0) - theirs[offset:offset + n].mean(0))
        print(f"  {piece.name}: centroid {shift * 100:.1f} cm from its own placement's")
        assert shift < 0.05, (piece.name, shift)
        out[piece.name] = mine
        offset += n
    return out


def test_the_shirt_arranged_automatically_assembles_on_the_body(body, places, tmp_path):
    """No manual placement: the shirt's GarmentCode placements are dropped, each piece goes
    where its name says, and `tailor simulate` with default settings judges the result."""
    garment = tailor.Garment.from_pattern(str(SHIRT), edge=0.02)
    arranged, plan = arrange_garment(garment, *body, places=list(places.values()))
    assert all(p is None for p in arranged.placements)
    assert {e["name"]: e["place"] for e in plan} == {
        "left_ftorso": "torso_front", "right_ftorso": "torso_front",
        "left_btorso": "torso_back", "right_btorso": "torso_back",
        "left_sleeve_f": "left_arm", "left_sleeve_b": "left_arm",
        "right_sleeve_f": "right_arm", "right_sleeve_b": "right_arm",
    }
    start = arranged.build_simulation()[0].positions
    placed_by_garmentcode = garment.build_simulation()[0].positions
    assert np.linalg.norm(start - placed_by_garmentcode, axis=1).min() > 0.005  # not GarmentCode's placement
    assert tailor.penetration(start, *body)["count"] == 0
    assembles_where_its_own_placement_ends(garment, arranged, tmp_path, "shirt")


def test_the_hoody_arranged_automatically_wears_its_hood_on_the_head(body, places, tmp_path):
    """The GarmentCode hoody with its placements dropped: the hood's halves go on the head place,
    each on its side (GarmentCode draws them seen from the side: face opening to the front, the
    seam between them at the back), and the hoody assembles with default settings, the hood
    ending over the head where GarmentCode's own placement puts it. Before there was a head
    place the hood went to the torso and a seam stayed 22 cm open."""
    garment = tailor.Garment.from_pattern(str(HOODY), edge=0.02)
    arranged, plan = arrange_garment(garment, *body, places=list(places.values()))
    hoods = {e["name"]: (e["place"], e["around_deg"]) for e in plan if "hood" in e["name"]}
    assert hoods == {"left_hood": ("head", 90.0), "right_hood": ("head", -90.0)}
    assert tailor.penetration(arranged.build_simulation()[0].positions, *body)["count"] == 0
    ends = assembles_where_its_own_placement_ends(garment, arranged, tmp_path, "hoody")
    for name in hoods:
        assert ends[name][:, 1].max() > 1.65, (name, ends[name][:, 1].max())  # over the head (its top 1.72 m)


@pytest.mark.parametrize("name", ["asymm_circle_skirt_611_003", "tiered_dress_733_002"])
def test_a_skirt_sewn_up_round_the_waist_unfolds_and_is_not_taken_for_a_fall(name, body, places, tmp_path):
    """Two random GarmentCode designs nobody tuned (the design sampler's: an asymmetric circle
    skirt on a waistband, a fitted shirt over a four-tier circle skirt), arranged on the body.
    Their ring-shaped skirt pieces, rolled round the waist, are sewn up there and unfold to their
    length once the seams have met, the waistband and the shirt staying where they were sewn:
    the centroid drops about 20 cm while the top does not move. The verdict judged the centroid
    alone and called both a fall (2026-11-27: 22.7 and 20.8 cm), in reports of garments hanging
    from the waist as they should; the top's shift (3.1 cm and 0.6 cm) tells draping from
    falling. Seam gaps measured then: 0.48 and 1.01 mm."""
    garment = tailor.Garment.from_pattern(str(SPECS / f"{name}_specification.json"), edge=0.02)
    arranged, _ = arrange_garment(garment, *body, places=list(places.values()))
    r, s, last, _ = simulated(arranged, tmp_path, name)
    print(f"{name}: exit {r.returncode}, verdict {s['verdict']}, centroid moved {s['centroid_shift_m'] * 100:.1f} cm, "
          f"top {s['top_shift_m'] * 100:.1f} cm, seam gap {last['seam_gap_max_m'] * 1e3:.2f} mm, "
          f"on body {last['on_body_fraction']:.2f}")
    assert r.returncode == 0 and s["verdict"] == [], (r.returncode, s["verdict"], r.stdout[-1500:])
    assert s["centroid_shift_m"] > 0.15 and s["top_shift_m"] < 0.05, s  # unfolded below a top that stayed
    assert last["penetration_count"] == 0 and not s["nan"] and last["on_body_fraction"] > 0.75, last
    assert last["seam_gap_max_m"] < 2e-3, last
