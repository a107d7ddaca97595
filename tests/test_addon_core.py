"""The add-on's bpy-free half (`addon/tailor_addon/core`), against the module, without Blender."""

import sys
from pathlib import Path

import numpy as np
import pytest

import tailor

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "addon"))
from tailor_addon import core  # noqa: E402
from tailor_addon.core.garment import PieceData, SeamData  # noqa: E402

DATA = ROOT / "native/tailor-core/tests/data"
SHIRT = DATA / "garmentcode/shirt_mean_specification.json"


def test_core_imports_without_blender():
    assert "bpy" not in sys.modules


def test_mesh_arrays_mark_contour_and_corners():
    m = tailor.triangulate(tailor.read_pattern(str(SHIRT)).pieces[0], 0.03)
    a = core.mesh_arrays(m)
    assert a.co.shape == (len(m.rest), 3) and not a.co[:, 2].any()
    np.testing.assert_array_equal(a.co[:, :2], m.rest)
    assert np.array_equal(np.nonzero(a.contour >= 0)[0], np.sort(m.contour))
    assert np.array_equal(a.contour[m.contour], np.arange(len(m.contour)))
    assert np.array_equal(np.nonzero(a.corner)[0], np.sort(np.asarray(m.contour)[m.corners]))
    assert a.uv.shape == (3 * len(m.triangles), 2)
    np.testing.assert_array_equal(a.uv[:3], m.rest[m.triangles[0]])


def test_errors_say_what_to_do():
    with pytest.raises(tailor.PatternError) as e:
        tailor.read_pattern(str(DATA / "dxf/README.md"))
    text = core.describe(e.value, "Importing the pattern")
    assert text.startswith("Importing the pattern failed: ") and "DXF (AAMA/ASTM or plain)" in text
    assert core.describe(core.AddonError("no piece selected", "Select a piece")) == "no piece selected. Select a piece."


def scene_from_garment(g: tailor.Garment, edge: float):
    """What the add-on reads from a scene after importing `g`: pieces where the module places
    them, and the seams."""
    sim, offsets = g.build_simulation()
    pos = np.asarray(sim.positions)
    ends = list(offsets[1:]) + [len(pos)]
    pieces = [
        PieceData(p.name, p.to_json(), edge, pos[o:e], m.rest)
        for p, m, o, e in zip(g.pieces, g.meshes(), offsets, ends)
    ]
    return pieces, [SeamData.from_tailor(s) for s in g.seams], sim


def test_scene_garment_builds_the_same_simulation_as_the_module():
    g = tailor.Garment.from_pattern(str(SHIRT), edge=0.04)
    pieces, seams, reference = scene_from_garment(g, 0.04)
    sg = core.garment_from_scene(pieces, seams)
    assert sg.num_particles == reference.num_particles
    np.testing.assert_array_equal(sg.positions, reference.positions)
    sim = sg.build_simulation()
    assert sim.seam_gaps() == pytest.approx(reference.seam_gaps())
    # The seams' stiffness factors multiply the solver's seam stiffness.
    stiff = [SeamData(s.name, s.a, s.b, s.mode, 3.0, 1.0) for s in seams]
    assert (
        core.garment_from_scene(pieces, stiff).build_simulation(seam_stiffness=100.0).num_particles == sim.num_particles
    )


def test_scene_garment_with_darts_builds_like_the_module():
    """The jumpsuit's trouser panels have darts: a dart's tip is sewn to itself, which the
    module's garment build leaves out; the add-on's build must too (the solver refuses it)."""
    g = tailor.Garment.from_pattern(str(DATA / "garmentcode/js_mean_all_specification.json"), edge=0.04)
    pieces, seams, reference = scene_from_garment(g, 0.04)
    sg = core.garment_from_scene(pieces, seams)
    tips = sum(
        int(((r["pair_a_vertices"][:, 0] == r["pair_b_vertices"][:, 0]) & (s.a.piece == s.b.piece)).sum())
        for s, r in zip(sg.seams, sg.resolved)
    )
    assert tips > 0  # the case this test is about
    sim = sg.build_simulation()
    assert sum(len(p["a_vertices"]) for p in sim.seam_pairs()) == sum(
        len(p["a_vertices"]) for p in reference.seam_pairs()
    )
    assert sim.seam_gaps() == pytest.approx(reference.seam_gaps())


def test_edited_mesh_is_refused_with_what_to_do():
    g = tailor.Garment.from_pattern(str(SHIRT), edge=0.04)
    pieces, seams, _ = scene_from_garment(g, 0.04)
    pieces[2].positions = pieces[2].positions[:-1]
    with pytest.raises(core.AddonError, match="vertices but its pattern") as e:
        core.garment_from_scene(pieces, seams)
    assert "resolution" in e.value.hint
    with pytest.raises(core.AddonError, match="no garment pieces"):
        core.garment_from_scene([], [])


def test_flip_and_remap_after_a_change_of_resolution():
    g = tailor.Garment.from_pattern(str(SHIRT), edge=0.04)
    pieces, seams, _ = scene_from_garment(g, 0.04)
    meshes = [core.mesh_of(p) for p in pieces]
    long = [len(x.to_tailor().resolve(meshes)["a_vertices"]) >= 5 for x in seams]
    k = next(i for i, s in enumerate(seams) if s.mode == "equal" and s.a.piece != s.b.piece and long[i])
    s = seams[k]
    r = s.to_tailor().resolve(meshes)
    f = s.flipped()
    rf = f.to_tailor().resolve(meshes)
    assert rf["b_vertices"] == r["b_vertices"][::-1] and rf["a_vertices"] == r["a_vertices"]
    assert f.flipped() == s
    # Re-triangulate side A's piece much finer: the seam becomes unequal, as Garment.set_resolution does.
    changed = list(meshes)
    changed[s.a.piece] = core.piece_mesh(pieces[s.a.piece].piece_json, 0.015, tailor.MESHER_VERSION)
    remapped = core.remap_seam_modes(seams, changed, {s.a.piece})
    g.set_resolution(s.a.piece, 0.015)
    assert [x.mode for x in remapped] == [x.mode for x in g.seams]
    assert remapped[k].mode == "unequal"


def test_side_by_side_layout():
    rests = [np.array([[0, 0], [1, 0], [1, 2]], np.float32), np.array([[-1, -1], [0, -1], [0, 0]], np.float32)]
    assert core.side_by_side(rests, gap=0.5) == [(0.0, 0.0, 0.0), (2.5, 1.0, 0.0)]


def test_scene_garment_welds_as_the_module_welds_the_garment():
    g = tailor.Garment.from_pattern(str(SHIRT), edge=0.04)
    pieces, seams, sim = scene_from_garment(g, 0.04)
    sg = core.garment_from_scene(pieces, seams)
    w = core.welded.weld(sg)
    ref = g.welded(sim.positions)
    np.testing.assert_array_equal(w.triangles, ref.triangles)
    np.testing.assert_array_equal(w.positions, ref.positions)
    assert w.stats["merged"] > 0 and w.num_vertices < sg.num_particles
    # UVs per corner (the rest shape, as the pieces' TailorRest map holds it) onto the weld.
    uv = core.welded.welded_corner_values(w, sg.rest[sg.triangles.reshape(-1)])
    assert uv.shape == (3 * len(w.triangles), 2)
    text = core.welded.summary(w)
    assert text.startswith(f"{sg.num_particles} vertices welded into {w.num_vertices} ({w.stats['merged']} merged")
    with pytest.raises(core.AddonError, match="positions for a garment of"):
        core.welded.weld(sg, sg.positions[:-1])


def test_painted_level_groups_override_the_level_attribute():
    from tailor_addon.core.paint import level_group_name, level_of_group, painted_levels

    assert level_group_name(3) == "tailor_level_3" and level_of_group("tailor_level_3") == 3
    assert level_of_group("tailor_level_-2") == -2 and level_of_group("tailor_pin") is None
    assert level_of_group("tailor_level_3b") is None
    assert painted_levels(None, 4, {}) is None
    base = np.array([1, 1, 1, 1, 1], np.int32)
    painted = np.array([True, True, True, True, False])
    groups = {
        3: (np.array([1.0, 0.4, 0.7, 0.9, 1.0], np.float32), painted),  # vertex 4 unpainted
        2: (np.array([0.5, 0.9, 0.7, 0.2, 0.0], np.float32), np.ones(5, bool)),
    }
    # 0: 3 heavier; 1: 3 under a half, 2 over; 2: a tie, the higher level; 3: 3 alone over a
    # half; 4: only level 2 painted there, at 0: the attribute's.
    assert painted_levels(base, 5, groups).tolist() == [3, 2, 3, 3, 1]
    # The same whatever order the groups come in, and the attribute left as it was.
    assert painted_levels(base, 5, dict(reversed(list(groups.items())))).tolist() == [3, 2, 3, 3, 1]
    assert base.tolist() == [1] * 5
    assert painted_levels(None, 5, groups).tolist() == [3, 2, 3, 3, 0]


def test_fit_map_colours_run_blue_to_red_over_stated_ranges():
    from tailor_addon.core import fit_maps

    blue, red = fit_maps._RAMP[0], fit_maps._RAMP[-1]
    c = fit_maps.colours("STRAIN", np.array([0.0, 0.1, 0.2, 0.5, np.nan], np.float32))
    assert c.shape == (5, 4) and c.dtype == np.float32 and (c[:, 3] == 1).all()
    assert np.allclose(c[0, :3], blue) and np.allclose(c[2, :3], red) and np.allclose(c[3, :3], red)
    assert np.allclose(c[4, :3], blue)  # NaN reads as 0, not as a colour that means something
    # Pressure on a square-root scale: a quarter of the red pressure is half way along.
    assert fit_maps.unit("PRESSURE", np.array([500.0]))[0] == pytest.approx(0.5)
    # Distance runs the other way: touching is red, 5 cm off is blue.
    d = fit_maps.colours("DISTANCE", np.array([0.0, 0.05, 0.2], np.float32))
    assert np.allclose(d[0, :3], red) and np.allclose(d[1, :3], blue) and np.allclose(d[2, :3], blue)
    with pytest.raises(ValueError, match="no fit map"):
        fit_maps.unit("TENSION", np.zeros(1))
