"""Patterns, triangulation, contour picking, seams, bend and garments through the Python API."""

from pathlib import Path

import numpy as np
import pytest

import tailor

DATA = Path(__file__).resolve().parents[1] / "native/tailor-core/tests/data"
SHIRT = DATA / "garmentcode/shirt_mean_specification.json"
SKIRT = DATA / "garmentcode/flare_skirt_specification.json"


def test_read_pattern_garmentcode():
    p = tailor.read_pattern(str(SHIRT))
    assert len(p.pieces) == 8 and len(p.stitches) == 18
    piece = p.pieces[0]
    assert piece.name == "right_sleeve_b"
    assert piece.outline.ndim == 2 and piece.outline.shape[1] == 2 and piece.outline.dtype == np.float64
    assert set(piece.placement) == {"translation", "rotation_deg", "flipped"}
    assert all(0 <= s < len(piece.outline) and 0 <= e < len(piece.outline) for s, e in piece.edges)
    (pa, ea), (pb, eb) = p.stitches[0]
    assert ea < len(p.pieces[pa].edges) and eb < len(p.pieces[pb].edges)
    assert tailor.list_sizes(str(SHIRT)) == []


def test_triangulate_and_quality():
    piece = tailor.read_pattern(str(SKIRT)).pieces[0]
    m = tailor.triangulate(piece, edge=0.03)
    assert m.rest.shape[1] == 2 and m.rest.dtype == np.float32
    assert m.triangles.shape[1] == 3 and m.triangles.max() < len(m.rest)
    assert m.quality["vertices"] == len(m.rest) and m.quality["min_angle_deg"] > 20
    assert len(m.contour) == len(m.contour_param) and m.contour_length > 0
    assert m.corners == sorted(m.corners)
    with pytest.raises(tailor.InvalidParameterError):
        tailor.triangulate(piece, edge=-1.0)


def test_five_steps_and_seam_resolution_through_python():
    g = tailor.Garment.from_pattern(str(SHIRT), edge=0.03)
    meshes = g.meshes()
    for seam in g.seams:
        r = seam.resolve(meshes)
        ma, mb = meshes[seam.a["piece"]], meshes[seam.b["piece"]]
        long_enough = len(r["a_vertices"]) >= 4 and 2 * r["a"].length(ma) < ma.contour_length
        if seam.mode == "equal" and seam.a["piece"] != seam.b["piece"] and long_enough:
            break
    else:
        pytest.fail("no equal-count stitch")
    off = np.array([0.004, -0.003])
    a1 = tailor.nearest_contour_position(ma, tuple(np.add(seam.a["start"], off)))
    path_a = tailor.shortest_path(ma, a1, tailor.nearest_contour_position(ma, tuple(np.add(seam.a["end"], off))))
    b1 = tailor.nearest_contour_position(mb, tuple(np.add(seam.b["start"], off)))
    path_b = tailor.nearer_candidate(mb, b1, len(path_a), tuple(np.add(seam.b["end"], off)))
    assert path_b in tailor.candidate_paths(mb, b1, len(path_a))
    picked = tailor.Seam.from_paths("picked", seam.a["piece"], ma, path_a, seam.b["piece"], mb, path_b)
    rp = picked.resolve(meshes)
    assert rp["a_vertices"] == r["a_vertices"] and rp["b_vertices"] == r["b_vertices"]
    assert rp["mode"] == "equal" and rp["pair_a_vertices"].shape == (len(path_a), 2)
    assert np.allclose(rp["pair_a_weights"].sum(axis=1), 1.0)
    # A side of another length cannot be sewn one-to-one.
    short = tailor.ContourPath(path_b.positions[:-1], path_b.direction)
    with pytest.raises(tailor.SeamError):
        tailor.Seam.from_paths("bad", seam.a["piece"], ma, path_a, seam.b["piece"], mb, short)
    corners = tailor.find_corners(ma, 150.0)
    seg = tailor.nearest_corner_segment(ma, corners, tuple(ma.contour_point(corners[0] + 1)))
    assert seg.positions[0] in corners and seg.positions[-1] in corners


def test_set_resolution_keeps_seam_endpoints_within_one_edge():
    g = tailor.Garment.from_pattern(str(SKIRT), edge=0.03)
    old = g.meshes()
    before = [s.resolve(old) for s in g.seams]
    piece = g.seams[0].a["piece"]
    new_mesh = g.set_resolution(piece, 0.02)
    assert g.edge_lengths[piece] == pytest.approx(0.02) and len(new_mesh.rest) > len(old[piece].rest)
    new = g.meshes()
    modes = set()
    for s, b in zip(g.seams, before):
        r = s.resolve(new)
        modes.add(r["mode"])
        for side, key in (("a", "a_vertices"), ("b", "b_vertices")):
            p = s.a["piece"] if side == "a" else s.b["piece"]
            for k in (0, -1):
                q_old = old[p].rest[b[key][k]]
                q_new = new[p].rest[r[key][k]]
                assert np.linalg.norm(q_old - q_new) <= max(old[p].edge_length, new[p].edge_length)
    assert "unequal" in modes
    with pytest.raises(tailor.InvalidParameterError):
        g.set_resolution(99, 0.02)
    with pytest.raises(tailor.InvalidParameterError):
        g.set_resolution(piece, float("nan"))
    assert g.edge_lengths[piece] == pytest.approx(0.02)


def test_garmentcode_skirt_closes_in_the_solver_with_unequal_seams():
    g = tailor.Garment.from_pattern(str(SKIRT), edge=0.03)
    g.set_resolution(0, 0.022)  # some seams now join different vertex counts
    assert any(s.mode == "unequal" for s in g.seams)
    # 10⁴ N/m seams: at the default 10³ N/m the eased waistband seam (9 % longer than the
    # skirt's top edge) settles around 1.0-1.4 mm.
    no_gravity = tailor.Settings(gravity=(0.0, 0.0, 0.0))
    sim, offsets = g.build_simulation(settings=no_gravity, seam_stiffness=1e4)
    assert offsets[0] == 0 and len(offsets) == len(g.pieces)
    assert sim.num_particles == sum(len(m.rest) for m in g.meshes())
    gap0 = sim.seam_gaps()[0]
    for _ in range(90):
        sim.step(1.0 / 30.0)
        if sim.seam_gaps()[0] < 1e-3:
            break
    assert np.isfinite(sim.positions).all()
    assert sim.seam_gaps()[0] < 1e-3 < gap0
    sim.step(1.0 / 30.0, frames=30)
    assert np.isfinite(sim.positions).all() and sim.seam_gaps()[0] < 2e-3, "the seams stay closed"


def test_garment_file_round_trip(tmp_path):
    g = tailor.Garment.from_pattern(str(SHIRT), edge=0.04)
    g.set_resolution(1, 0.03)
    g.set_bend(0, (0.0, 1.4, 0.0), (1.0, 0.0, 0.0), 30.0)
    path = tmp_path / "shirt.json"
    g.save(str(path))
    assert path.exists() and path.with_suffix(".bin").exists()
    h = tailor.Garment.load(str(path))
    assert [p.name for p in h.pieces] == [p.name for p in g.pieces]
    assert h.edge_lengths == g.edge_lengths
    assert [(s.name, s.mode, s.a, s.b) for s in h.seams] == [(s.name, s.mode, s.a, s.b) for s in g.seams]
    for m, n in zip(g.meshes(), h.meshes()):
        assert np.array_equal(m.rest, n.rest) and np.array_equal(m.triangles, n.triangles)
    sa, _ = g.build_simulation()
    sb, _ = h.build_simulation()
    assert np.array_equal(sa.positions, sb.positions)


def test_bend_rolls_a_piece_without_stretching_it():
    """`tailor.bend` rolls the skirt panel onto a cylinder: every edge keeps its length up to
    its chord (0.1 % at this resolution and radius); `radius` sets the cylinder; bad input
    is a typed error."""
    piece = tailor.read_pattern(str(SKIRT)).pieces[0]
    m = tailor.triangulate(piece, edge=0.01)
    pos = np.concatenate([m.rest, np.zeros((len(m.rest), 1), np.float32)], axis=1)
    centre = m.rest.mean(axis=0)
    axis = (float(centre[0]), 0.0, -0.1)
    edges = np.unique(np.sort(np.concatenate([m.triangles[:, [0, 1]], m.triangles[:, [1, 2]],
                                              m.triangles[:, [2, 0]]]), axis=1), axis=0)

    def lengths(p):
        return np.linalg.norm(p[edges[:, 0]].astype(np.float64) - p[edges[:, 1]], axis=1)

    sym = ((float(centre[0]), 0.0), (0.0, 1.0))
    bent = tailor.bend(pos, m.rest, axis, (0.0, 1.0, 0.0), 90.0, symmetry=sym)
    assert bent.shape == pos.shape and bent[:, 2].min() < -0.05
    assert np.abs(lengths(bent) / lengths(pos) - 1.0).max() < 1e-3
    on = tailor.bend(pos, m.rest, axis, (0.0, 1.0, 0.0), 0.0, symmetry=sym, radius=0.1)
    # Rolled from the centre line onto a 10 cm cylinder tangent to the panel there.
    r = np.hypot(on[:, 0] - centre[0], on[:, 2] + 0.1)
    assert np.allclose(r, 0.1, atol=1e-5)
    with pytest.raises(tailor.InvalidParameterError):
        tailor.bend(pos, m.rest, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), 10.0)
    with pytest.raises(tailor.InvalidParameterError):
        tailor.bend(pos, m.rest, axis, (0.0, 1.0, 0.0), 10.0, radius=-1.0)
    with pytest.raises(tailor.InvalidParameterError):
        tailor.bend(pos, m.rest, axis, (0.0, 1.0, 0.0), 10.0, mode="fold")
    # The paper's rotation, kept for older files: it stretches, and bending back undoes it.
    turned = tailor.bend(pos, m.rest, axis, (0.0, 1.0, 0.0), 90.0, symmetry=sym, mode="rotate")
    assert np.abs(lengths(turned) / lengths(pos) - 1.0).max() > 0.05
    back = tailor.bend(turned, m.rest, axis, (0.0, 1.0, 0.0), -90.0, symmetry=sym, mode="rotate")
    assert np.allclose(back, pos, atol=1e-5)


def test_bend_onto_a_cone_keeps_lengths_and_names_a_bad_taper():
    """`taper_deg` rolls the panel onto a cone (issue 25): lengths kept as on the cylinder, the
    shape different from the cylinder's; a cone whose apex falls inside the piece, or NaN, is an
    error naming `taper_deg`."""
    piece = tailor.read_pattern(str(SKIRT)).pieces[0]
    m = tailor.triangulate(piece, edge=0.01)
    pos = np.concatenate([m.rest, np.zeros((len(m.rest), 1), np.float32)], axis=1)
    centre = m.rest.mean(axis=0)
    axis = (float(centre[0]), float(centre[1]), -0.1)
    sym = ((float(centre[0]), 0.0), (0.0, 1.0))
    edges = np.unique(np.sort(np.concatenate([m.triangles[:, [0, 1]], m.triangles[:, [1, 2]],
                                              m.triangles[:, [2, 0]]]), axis=1), axis=0)

    def lengths(p):
        return np.linalg.norm(p[edges[:, 0]].astype(np.float64) - p[edges[:, 1]], axis=1)

    for taper in (4.0, -4.0):
        cone = tailor.bend(pos, m.rest, axis, (0.0, 1.0, 0.0), 90.0, symmetry=sym, taper_deg=taper)
        assert np.abs(lengths(cone) / lengths(pos) - 1.0).max() < 1e-3
        cylinder = tailor.bend(pos, m.rest, axis, (0.0, 1.0, 0.0), 90.0, symmetry=sym)
        assert np.abs(cone - cylinder).max() > 1e-3
    for bad in (45.0, float("nan")):
        with pytest.raises(tailor.InvalidParameterError, match="taper_deg"):
            # (a 1 cm radius at 45 degrees: the apex 1.4 cm from the axis point, inside the 6.5 cm band)
            tailor.bend(pos, m.rest, axis, (0.0, 1.0, 0.0), 90.0, symmetry=sym, radius=0.01, taper_deg=bad)


def test_a_garment_files_bend_keeps_its_mode_and_older_files_rotate(tmp_path):
    """A bend saved in a garment file comes back with its mode; a file written before the roll
    (no `mode`) builds the paper's rotation, as it did."""
    import json

    g = tailor.Garment.from_pattern(str(SKIRT), edge=0.05)
    g.set_bend(0, (0.0, 0.5, -0.1), (0.0, 1.0, 0.0), 60.0)
    path = tmp_path / "g.json"
    g.save(str(path))
    rolled, _ = tailor.Garment.load(str(path)).build_simulation()
    ref, _ = g.build_simulation()
    np.testing.assert_array_equal(rolled.positions, ref.positions)
    doc = json.loads(path.read_text())
    bends = [p["bend"] for p in doc["pieces"] if p.get("bend")]
    assert [b["mode"] for b in bends] == ["roll"]
    for p in doc["pieces"]:
        if p.get("bend"):
            del p["bend"]["mode"]
    old = tmp_path / "old.json"
    old.write_text(json.dumps(doc))
    turned, _ = tailor.Garment.load(str(old)).build_simulation()
    g.set_bend(0, (0.0, 0.5, -0.1), (0.0, 1.0, 0.0), 60.0, mode="rotate")
    want, _ = g.build_simulation()
    np.testing.assert_array_equal(turned.positions, want.positions)
    assert not np.allclose(turned.positions, rolled.positions, atol=1e-3)


def test_file_errors_are_typed_and_name_the_file(tmp_path):
    missing = tmp_path / "nope.dxf"
    with pytest.raises(tailor.TailorIOError, match="nope.dxf"):
        tailor.read_pattern(str(missing))
    with pytest.raises(tailor.TailorIOError, match="nope.json"):
        tailor.Garment.load(str(tmp_path / "nope.json"))
    junk = tmp_path / "junk.svg"
    junk.write_text("<svg but not really")
    with pytest.raises(tailor.PatternError, match="junk.svg"):
        tailor.read_pattern(str(junk))
    with pytest.raises(tailor.InvalidParameterError):
        tailor.read_pattern(str(SHIRT), units="furlongs")


def test_piece_json_round_trip_rebuilds_the_same_mesh():
    piece = tailor.read_pattern(str(SHIRT)).pieces[1]
    again = tailor.Piece.from_json(piece.to_json())
    assert again.name == piece.name and np.array_equal(again.outline, piece.outline)
    assert again.placement == piece.placement and again.edges == piece.edges
    m1, m2 = tailor.triangulate(piece, 0.03), tailor.triangulate(again, 0.03)
    assert np.array_equal(m1.rest, m2.rest) and np.array_equal(m1.triangles, m2.triangles)
    with pytest.raises(tailor.PatternError, match="piece JSON"):
        tailor.Piece.from_json('{"name": "x"}')


def test_seam_from_stored_sides_resolves_like_the_original():
    g = tailor.Garment.from_pattern(str(SHIRT), edge=0.03)
    meshes = g.meshes()
    s = g.seams[0]
    stored = tailor.Seam(s.name, s.a, s.b, mode=s.mode, stiffness=2.5, bend_stiffness=0.5)
    assert (stored.stiffness, stored.bend_stiffness, stored.a, stored.b) == (2.5, 0.5, s.a, s.b)
    r1, r2 = s.resolve(meshes), stored.resolve(meshes)
    assert r1["a_vertices"] == r2["a_vertices"] and r1["b_vertices"] == r2["b_vertices"]
    with pytest.raises(tailor.InvalidParameterError, match="direction"):
        tailor.Seam("bad", dict(s.a, direction="up"), s.b)
    with pytest.raises(tailor.InvalidParameterError, match="stiffness"):
        tailor.Seam("bad", s.a, s.b, stiffness=-1.0)
    with pytest.raises(tailor.InvalidParameterError, match="needs the key"):
        tailor.Seam("bad", {"start": [0, 0]}, s.b)


def test_garment_from_parts_rebuilds_the_same_garment(tmp_path):
    g = tailor.Garment.from_pattern(str(SHIRT), edge=0.04)
    bend = {
        "axis_point": [0.0, 1.2, 0.0],
        "axis_direction": [0, 1, 0],
        "angle_deg": 30.0,
        "symmetry": ((0.0, 0.0), (0.0, 1.0)),
        "threshold": 0.0,
    }
    g.set_bend(2, bend["axis_point"], bend["axis_direction"], 30.0, symmetry=bend["symmetry"])
    pieces = g.pieces
    moved = dict(pieces[0].placement, translation=[0.1, 0.2, 0.3])
    g2 = tailor.Garment.from_parts(
        pieces,
        g.edge_lengths,
        g.seams,
        placements=[moved] + [None] * (len(pieces) - 1),
        bends=[None, None, bend] + [None] * (len(pieces) - 3),
    )
    (s1, o1), (s2, o2) = g.build_simulation(), g2.build_simulation()
    n0 = o1[1]
    np.testing.assert_array_equal(s1.positions[n0:], s2.positions[n0:])
    shift = np.array([0.1, 0.2, 0.3]) - np.array(pieces[0].placement["translation"])
    np.testing.assert_allclose(s2.positions[:n0] - s1.positions[:n0], np.tile(shift, (n0, 1)), atol=1e-5)
    g2.save(str(tmp_path / "g.json"))
    assert len(tailor.Garment.load(str(tmp_path / "g.json")).seams) == len(g.seams)
    with pytest.raises(tailor.InvalidParameterError, match="3 pieces but 2 edge lengths"):
        tailor.Garment.from_parts(pieces[:3], [0.04, 0.04], [])
    with pytest.raises(tailor.InvalidParameterError, match="angle_deg"):
        tailor.Garment.from_parts(pieces[:1], [0.04], [], bends=[{"axis_point": [0, 0, 0], "axis_direction": [0, 1, 0]}])
    with pytest.raises(tailor.SeamError):
        tailor.Garment.from_parts(pieces[:1], [0.04], [g.seams[0]])


def test_garment_gives_back_its_placements_bends_and_meshers(tmp_path):
    """What `from_parts` takes, a saved and loaded garment gives back (`placements`, `bends`,
    `meshers`): a piece without its own placement has its pattern piece's, a bend keeps its
    radius, symmetry and mode, and `from_parts` with them builds the same simulation."""
    g = tailor.Garment.from_pattern(str(SHIRT), edge=0.04)
    pieces = g.pieces
    moved = dict(pieces[0].placement, translation=[0.1, 0.2, 0.3])
    bend = {"axis_point": [0.0, 1.2, 0.0], "axis_direction": [0.0, 1.0, 0.0], "angle_deg": -30.0,
            "symmetry": ((0.0, 0.0), (0.0, 1.0)), "threshold": 0.01, "radius": 0.08, "mode": "roll",
            "taper_deg": 2.0}
    n = len(pieces)
    g2 = tailor.Garment.from_parts(pieces, g.edge_lengths, g.seams, placements=[moved] + [None] * (n - 1),
                                   bends=[None, None, bend] + [None] * (n - 3), meshers=[1] + [g.meshers[1]] * (n - 1))
    g2.save(str(tmp_path / "g.json"))
    g3 = tailor.Garment.load(str(tmp_path / "g.json"))
    placements = g3.placements
    assert placements[0]["translation"] == pytest.approx(moved["translation"])
    assert placements[0]["rotation_deg"] == pytest.approx(moved["rotation_deg"])
    for p, source in zip(placements[1:], pieces[1:]):
        assert p["translation"] == pytest.approx(source.placement["translation"])
    bends = g3.bends
    assert bends[:2] == [None, None] and all(b is None for b in bends[3:])
    assert {k: bends[2][k] for k in ("angle_deg", "threshold", "radius", "mode", "taper_deg")} == \
        {k: bend[k] for k in ("angle_deg", "threshold", "radius", "mode", "taper_deg")}
    assert bends[3] is None or bends[3]["taper_deg"] == 0.0
    assert bends[2]["axis_point"] == bend["axis_point"] and bends[2]["symmetry"] == bend["symmetry"]
    assert g3.meshers == [1] + [g.meshers[1]] * (n - 1)
    g4 = tailor.Garment.from_parts(g3.pieces, g3.edge_lengths, g3.seams, placements=placements, bends=bends,
                                   meshers=g3.meshers)
    np.testing.assert_array_equal(g3.build_simulation()[0].positions, g4.build_simulation()[0].positions)


def test_a_pair_is_read_as_the_piece_and_its_mirror_image():
    """`Quantity: 2` (`dxf/synthetic_cut.dxf`'s SLEEVE) reads as the piece as drawn (`R`) and its
    mirror image (`L`) across its bounding box's middle; `Quantity: 0` is left out;
    `quantities=False` reads each piece once."""
    path = str(DATA / "dxf" / "synthetic_cut.dxf")
    pieces = tailor.read_pattern(path).pieces
    assert [p.name for p in pieces] == ["SLEEVE R", "SLEEVE L", "PANEL"]
    r, l = (np.asarray(p.outline) for p in pieces[:2])
    mirrored = np.stack([r[:, 0].min() + r[:, 0].max() - r[:, 0], r[:, 1]], axis=1)
    assert np.allclose(np.sort(l, axis=0), np.sort(mirrored, axis=0))
    assert [p.name for p in tailor.read_pattern(path, quantities=False).pieces] == ["SLEEVE", "PANEL", "ALT"]
    g = tailor.Garment.from_pattern(path, edge=0.03)
    assert [p.name for p in g.pieces] == ["SLEEVE R", "SLEEVE L", "PANEL"]
    def mesh_area(m):
        a, b, c = (m.rest[m.triangles[:, k]] for k in range(3))
        return 0.5 * np.abs(np.cross(b - a, c - a)).sum()

    # The same cloth (the mirror's Delaunay mesh need not be the mirror of the mesh).
    assert mesh_area(g.meshes()[0]) == pytest.approx(mesh_area(g.meshes()[1]), rel=1e-9)
    assert len(tailor.Garment.from_pattern(path, edge=0.03, quantities=False).pieces) == 3


def test_a_piece_cut_on_the_fold_is_read_whole_unless_asked_not_to():
    """A DXF piece drawn as a half with a mirror line (AAMA layer 6) is mirrored into the whole
    piece by `read_pattern` and `Garment.from_pattern`; `unfold=False` reads it as drawn."""
    path = str(DATA / "dxf" / "synthetic_fold.dxf")

    def area(piece):
        o = np.asarray(piece.outline, np.float64)
        return 0.5 * abs(np.sum(o[:, 0] * np.roll(o[:, 1], -1) - np.roll(o[:, 0], -1) * o[:, 1]))

    whole, drawn = tailor.read_pattern(path).pieces[0], tailor.read_pattern(path, unfold=False).pieces[0]
    assert area(drawn) == pytest.approx(0.0481) and area(whole) == pytest.approx(0.0962)
    g, half = tailor.Garment.from_pattern(path, edge=0.03), tailor.Garment.from_pattern(path, edge=0.03, unfold=False)
    assert len(g.meshes()[0].rest) > len(half.meshes()[0].rest)
