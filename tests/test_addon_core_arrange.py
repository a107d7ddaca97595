"""The add-on's Arrange on Body logic (`addon/tailor_addon/core/arrange.py`), without Blender:
the GarmentCode shirt on the GarmentCode body turned Z up, as the add-on sees them."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

import tailor

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "addon"))
from tailor_addon.core import AddonError  # noqa: E402
from tailor_addon.core import arrange as ca  # noqa: E402

SHIRT = ROOT / "native/tailor-core/tests/data/garmentcode/shirt_mean_specification.json"
BODY = ROOT / "sample_blends/sources/mean_all.obj"
#: Y up -> Z up as Blender's OBJ importer turns it: (x, y, z) -> (x, -z, y).
Y_TO_Z = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], np.float32)


@pytest.fixture(scope="module")
def body():
    v, t = tailor.read_mesh(str(BODY))
    return (np.asarray(v, np.float32) @ Y_TO_Z.T).astype(np.float32), np.asarray(t, np.int32)


@pytest.fixture(scope="module")
def shirt():
    g = tailor.Garment.from_pattern(str(SHIRT), edge=0.03)
    return [p.name for p in g.pieces], [m.rest for m in g.meshes()]


def test_place_items_are_auto_and_the_module_places():
    items = ca.place_items()
    assert [i[0] for i in items] == [ca.AUTO, *tailor.PLACE_NAMES]
    assert all(label and desc for _, label, desc in items)


def test_find_places_on_a_z_up_body(body):
    places = ca.find_places(*body, up="z")
    assert [p["name"] for p in places] == tailor.PLACE_NAMES
    front = {p["name"]: p for p in places}["torso_front"]
    assert front["facing"][1] < -0.9  # Blender's front is -Y
    left = {p["name"]: p for p in places}["left_arm"]
    assert left["origin"][0] > 0.15 and left["axis"][2] < -0.5  # +X side, down the arm


def test_find_places_reports_a_body_that_is_no_humanoid():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], np.float32)
    t = np.array([[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]], np.int32)
    with pytest.raises(AddonError, match="the collider 'Cube' is not a standing humanoid") as e:
        ca.find_places(v, t, body="Cube")
    assert "humanoid" in e.value.hint
    with pytest.raises(AddonError, match="no faces"):
        ca.find_places(np.zeros((0, 3)), np.zeros((0, 3)), body="Empty")


def test_plan_entry_auto_and_chosen(shirt):
    names, rests = shirt
    i = names.index("left_btorso")
    assert ca.plan_entry(names[i], rests[i])["place"] == "torso_back"
    e = ca.plan_entry(names[i], rests[i], "torso_front")
    assert e["place"] == "torso_front" and e["side"] == "left" and e["along"] == "vertical"
    e = ca.plan_entry(names[i], rests[i], "right_arm")
    assert e["place"] == "right_arm" and e["side"] == "centre" and e["along"] == "longest"
    assert e["around_deg"] == 180.0  # a back half at the back of the arm
    with pytest.raises(AddonError, match="no place 'hand'"):
        ca.plan_entry(names[i], rests[i], "hand")
    # The module decides the chosen place's reading: a band put on the neck goes round it.
    rib = np.array([[0, 0], [0.04, 0], [0.04, 0.39], [0, 0.39]], np.float32)
    assert ca.plan_entry("RIB", rib, "neck")["along"] == "shortest"
    with pytest.raises(tailor.InvalidParameterError, match="torso_front"):
        tailor.suggest_place("RIB", rib, place="hand")


def test_arrange_shirt_on_z_up_body(body, shirt):
    names, rests = shirt
    places = ca.find_places(*body)
    out = ca.arrange(names, rests, places)
    assert [r.name for r in out] == names
    bv, bt = body
    for r, rest in zip(out, rests):
        assert r.positions.shape == (len(rest), 3)
        assert tailor.penetration(r.positions, bv, bt)["count"] == 0, r.name
        c = r.positions.mean(axis=0)
        if "ftorso" in r.name:
            assert r.entry["place"] == "torso_front" and c[1] < -0.05
        elif "btorso" in r.name:
            assert r.entry["place"] == "torso_back" and c[1] > 0.05
        elif r.name.startswith("left_sleeve"):
            assert r.entry["place"] == "left_arm" and c[0] > 0.25
        else:
            assert r.entry["place"] == "right_arm" and c[0] < -0.25
    # One cylinder round each axis: the torso's four halves share the largest radius.
    torso = {round(r.entry["radius"], 6) for r in out if "torso" in r.name}
    assert len(torso) == 1


def test_arrange_matches_the_modules_arrange_garment(body, shirt):
    """The same positions as `tailor.arrange.arrange_garment` on the Y-up body, turned Z up."""
    from tailor.arrange import arrange_garment

    names, rests = shirt
    out = ca.arrange(names, rests, ca.find_places(*body))
    v, t = tailor.read_mesh(str(BODY))
    g = tailor.Garment.from_pattern(str(SHIRT), edge=0.03)
    arranged, _plan = arrange_garment(g, v, t, up="y")
    sim, offsets = arranged.build_simulation()
    theirs = np.asarray(sim.positions) @ Y_TO_Z.T
    np.testing.assert_allclose(np.concatenate([r.positions for r in out]), theirs, atol=2e-3)


def test_arrange_uses_the_chosen_place(body, shirt):
    names, rests = shirt
    places = ca.find_places(*body)
    choices = [("torso_front" if n == "left_btorso" else ca.AUTO) for n in names]
    out = {r.name: r for r in ca.arrange(names, rests, places, choices)}
    assert out["left_btorso"].entry["place"] == "torso_front"
    assert out["left_btorso"].positions[:, 1].mean() < -0.05


def test_to_local_inverts_the_object_matrix():
    m = np.eye(4)
    m[:3, :3] = [[0, -2, 0], [2, 0, 0], [0, 0, 2]]
    m[:3, 3] = [1, 2, 3]
    local = np.array([[0.1, 0.2, 0.3], [1, 0, 0]], np.float32)
    world = local @ m[:3, :3].T + m[:3, 3]
    np.testing.assert_allclose(ca.to_local(world, m), local, atol=1e-6)


def test_axis_lines_span_each_place(body):
    places = ca.find_places(*body)
    lines = ca.axis_lines(places)
    for p in places:
        seg = lines[p["name"]]
        assert seg.shape == (2, 3)
        assert np.linalg.norm(seg[1] - seg[0]) == pytest.approx(p["length"], rel=1e-4)


def test_a_piece_s_grain_line_reaches_the_arrangement(body):
    """The grain line kept in a piece's JSON (`tailor_piece.piece_json`) turns a bodice a marker
    laid on its side: with it the piece runs 0.6 m down the torso, without it 0.5 m."""
    assert ca.grain_of("") is None
    bodice = {"name": "FRONT", "outline": [[0, -0.25], [0.6, -0.18], [0.6, 0.18], [0, 0.25]],
              "fixed_vertices": [0, 1, 2, 3], "holes": [], "internal_lines": [], "notches": [],
              "grain": [[0.1, 0.0], [0.5, 0.0]], "placement": None, "edges": []}
    text = tailor.Piece.from_json(json.dumps(bodice)).to_json()
    assert ca.grain_of(text) == pytest.approx((0.4, 0.0))
    rest = np.array(bodice["outline"], np.float32)
    places = ca.find_places(*body)
    laid = ca.arrange(["FRONT"], [rest], places, grains=[ca.grain_of(text)])[0].positions
    drawn = ca.arrange(["FRONT"], [rest], places)[0].positions
    assert np.ptp(laid[:, 2]) == pytest.approx(0.6, abs=0.01)  # Z up in Blender
    assert np.ptp(drawn[:, 2]) == pytest.approx(0.5, abs=0.01)
