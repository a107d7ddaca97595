"""The interactive tools' bpy-free logic (`core.picking`, `core.seam_tools`, `core.bend_tool`):
hit -> rest conversions, the manual seam's pick state machine, the suggestion tool and the bend
tool's stages, against the module, without Blender."""

import ast
import math
import sys
from pathlib import Path

import numpy as np
import pytest

import tailor

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "addon"))
from tailor_addon.core import picking  # noqa: E402
from tailor_addon.core.bend_tool import BendTool  # noqa: E402
from tailor_addon.core.seam_tools import ManualSeamTool, SuggestSeamTool  # noqa: E402

SKIRT = ROOT / "native/tailor-core/tests/data/svg/skirt_two_panels.svg"
ADDON = ROOT / "addon/tailor_addon"


def test_tools_import_without_blender():
    assert "bpy" not in sys.modules


@pytest.fixture(scope="module")
def panels():
    """{name: PieceMesh} of the two skirt panels at 5 cm, and the back at 3 cm (unequal counts)."""
    pattern = tailor.read_pattern(str(SKIRT))
    front, back = pattern.pieces
    return {
        "front": tailor.triangulate(front, 0.05),
        "back": tailor.triangulate(back, 0.05),
        "fine back": tailor.triangulate(back, 0.03),
    }


def point(mesh, position):
    return np.asarray(mesh.contour_point(position), np.float64)


def inward(mesh, position, d=0.004):
    """A rest point just inside the piece near a contour vertex (where a click lands)."""
    c = np.asarray(mesh.rest, np.float64).mean(axis=0)
    p = point(mesh, position)
    return p + d * (c - p) / np.linalg.norm(c - p)


# ---- picking ------------------------------------------------------------------------------


def test_barycentric_and_hit_to_rest_on_a_bent_piece(panels):
    m = panels["front"]
    rest = np.asarray(m.rest, np.float64)
    co = np.zeros((len(rest), 3), np.float32)
    co[:, :2] = rest
    c = rest.mean(axis=0)
    bent = tailor.bend(co, co[:, :2], (c[0], c[1], -0.1), (0, 1, 0), 80.0, symmetry=((c[0], c[1]), (0, 1)))
    assert np.abs(bent[:, 2]).max() > 0.02  # really bent
    tri = np.asarray(m.triangles, np.int64)
    rng = np.random.default_rng(1)
    for face in rng.integers(0, len(tri), 20):
        w = rng.dirichlet(np.ones(3))
        hit = (w[:, None] * bent[tri[face]]).sum(axis=0)
        np.testing.assert_allclose(picking.barycentric(hit, *bent[tri[face]]), w, atol=1e-4)
        got = picking.hit_to_rest(hit, bent, tri, rest, int(face))
        np.testing.assert_allclose(got, (w[:, None] * rest[tri[face]]).sum(axis=0), atol=1e-5)
    # A hit just off the triangle (rounding at its border) is clamped onto it.
    a, b, cc = rest[tri[0]]
    outside = np.r_[a + 1.01 * (b - a), 0.0]
    np.testing.assert_allclose(picking.hit_to_rest(outside, co, tri, rest, 0), b, atol=1e-6)
    with pytest.raises(IndexError):
        picking.hit_to_rest(outside, co, tri, rest, len(tri))


def test_project_points_and_nearest_on_screen():
    # An orthographic top view of the square [-1, 1]^2 onto a 200x100 region; a perspective
    # view with w = -z sees points in front (z < 0) only.
    ortho = np.eye(4)
    xy, front = picking.project_points(np.array([[-1, -1, 0], [1, 1, 0], [0, 0, 5]]), ortho, 200, 100)
    np.testing.assert_allclose(xy, [[0, 0], [200, 100], [100, 50]])
    assert front.all()
    persp = np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, -1, 0]], np.float64)
    xy, front = picking.project_points(np.array([[0.5, 0, -1], [0.5, 0, 1]]), persp, 200, 100)
    assert front.tolist() == [True, False] and xy[0].tolist() == [150, 50]
    assert picking.nearest_on_screen(xy, front, (140, 50), 24) == 0
    assert picking.nearest_on_screen(xy, front, (100, 50), 24) is None  # too far
    assert picking.nearest_on_screen(xy, np.zeros(2, bool), (150, 50), 24) is None  # none in front
    assert picking.nearest_on_screen(np.zeros((0, 2)), np.zeros(0, bool), (0, 0), 24) is None


# ---- manual seam -----------------------------------------------------------------------------


def test_manual_seam_five_steps(panels):
    tool = ManualSeamTool(panels.__getitem__)
    mf, mb = panels["front"], panels["back"]
    c0, c1 = mf.corners[0], mf.corners[1]
    assert "1/4" in tool.prompt() and "a1" in tool.prompt() and "Esc" in tool.prompt()
    # Step 1: hovering shows the vertex a click would pick; the click takes a1.
    h = tool.highlight("front", inward(mf, c0))
    assert ("front", c0, "preview") in h.points and not h.paths
    assert tool.click("front", inward(mf, c0)).accepted and tool.picks == [("front", c0)]
    assert "2/4" in tool.prompt() and "an" in tool.prompt()
    # Steps 2-3: the shortest contour path from a1 to the hovered vertex is shown.
    h = tool.highlight("front", inward(mf, c1))
    assert ("front", tailor.shortest_path(mf, c0, c1).positions, "preview") in h.paths
    refused = tool.click("back", inward(mb, 3))
    assert not refused.accepted and "an must be on 'front'" in refused.message and len(tool.picks) == 1
    assert not tool.click("front", inward(mf, c0)).accepted  # an == a1
    assert not tool.click(None).accepted and len(tool.picks) == 1
    assert tool.click("front", inward(mf, c1)).accepted
    path_a = tailor.shortest_path(mf, c0, c1)
    n = len(path_a.positions)
    assert tool.path_a.positions == path_a.positions and f"({n} vertices)" in tool.prompt()
    # Step 4: b1 on the other piece; step 5: the n-vertex path whose end is nearer the cursor.
    b1 = mb.corners[1]
    assert tool.click("back", inward(mb, b1)).accepted
    assert "4/4" in tool.prompt() and "bn" in tool.prompt()
    for target in (mb.corners[0], mb.corners[2]):
        cursor = inward(mb, target)
        h = tool.highlight("back", cursor)
        expected = tailor.nearer_candidate(mb, b1, n, tuple(cursor))
        assert ("back", expected.positions, "preview") in h.paths
        assert ("front", path_a.positions, "picked") in h.paths
    cursor = inward(mb, mb.corners[0])
    expected = tailor.nearer_candidate(mb, b1, n, tuple(cursor))
    done = tool.click("back", cursor)
    assert done.accepted and done.request is not None
    r = done.request
    assert (r.piece_a, r.a_start, r.a_end, r.a_direction) == ("front", c0, c1, path_a.direction.upper())
    assert (r.piece_b, r.b_start, r.b_end, r.b_direction, r.mode) == (
        "back", b1, expected.positions[-1], expected.direction.upper(), "EQUAL"
    )
    # The request's sides are exactly the paths shown: sewing them pairs n vertices each.
    seam = tailor.Seam.from_paths("s", 0, mf, path_a, 1, mb, expected)
    res = seam.resolve([mf, mb])
    assert len(res["a_vertices"]) == len(res["b_vertices"]) == n


def test_manual_seam_backspace_undoes_one_pick_at_a_time(panels):
    tool = ManualSeamTool(panels.__getitem__)
    mf, mb = panels["front"], panels["back"]
    tool.click("front", inward(mf, mf.corners[0]))
    tool.click("front", inward(mf, mf.corners[1]))
    tool.click("back", inward(mb, mb.corners[1]))
    assert tool.step == "bn"
    assert tool.undo() and tool.step == "b1" and tool.path_a is not None
    assert tool.undo() and tool.step == "an" and tool.path_a is None
    assert tool.undo() and tool.step == "a1"
    assert not tool.undo() and tool.picks == []
    assert tool.highlight(None).paths == [] and tool.highlight(None).points == []


def test_manual_seam_refuses_a_side_longer_than_piece_b(panels):
    meshes = dict(panels, finest=tailor.triangulate(tailor.read_pattern(str(SKIRT)).pieces[1], 0.015))
    tool = ManualSeamTool(meshes.__getitem__)
    mb, fine = panels["back"], meshes["finest"]
    # Side A: half the finest back's contour; piece B (5 cm) has fewer contour vertices.
    a1 = 0
    an = len(fine.contour) // 2
    tool.click("finest", inward(fine, a1))
    tool.click("finest", inward(fine, an))
    n = len(tool.path_a.positions)
    assert n > len(mb.contour)
    tool.click("back", inward(mb, 0))
    res = tool.click("back", inward(mb, 2))
    assert not res.accepted and "contour vertices" in res.message
    assert tool.highlight("back", inward(mb, 2)).paths == [("finest", tool.path_a.positions, "picked")]


# ---- automatic suggestion --------------------------------------------------------------------


def side_by_side(panels, gap=0.05):
    """World positions as the importer lays pieces out: front at x=0, back to its right."""
    xmax = np.asarray(panels["front"].rest)[:, 0].max()
    offsets = {"front": 0.0}
    for name in ("back", "fine back"):
        offsets[name] = xmax + gap - np.asarray(panels[name].rest)[:, 0].min()

    def locate(piece, position):
        p = panels[piece].contour_point(position)
        return np.array([p[0] + offsets[piece], p[1], 0.0])

    return locate


def middle_of_run(mesh, start, end):
    return (point(mesh, start) + point(mesh, end)) / 2


def facing_sides(panels, a, b):
    """(A run, B run) of the corner runs of `a` and `b` that face each other side by side."""
    locate = side_by_side(panels)

    def runs(name):
        m = panels[name]
        cs = list(m.corners) + [m.corners[0]]
        return [(s, e) for s, e in zip(cs[:-1], cs[1:])]

    def mid_x(name, run):
        return (locate(name, run[0])[0] + locate(name, run[1])[0]) / 2

    ra = max(runs(a), key=lambda r: mid_x(a, r))  # A's rightmost side
    rb = min(runs(b), key=lambda r: mid_x(b, r))  # B's leftmost side
    return ra, rb


def test_suggestion_highlights_the_corner_segment_under_the_cursor(panels):
    tool = SuggestSeamTool(panels.__getitem__, side_by_side(panels), 150.0)
    mf = panels["front"]
    corners = tailor.find_corners(mf, 150.0)
    assert tool.corners("front") == corners and len(corners) >= 2
    s, e = corners[0], corners[1]
    cursor = middle_of_run(mf, s, e)
    expected = tailor.nearest_corner_segment(mf, corners, tuple(cursor)).positions
    assert expected[0] == s and expected[-1] == e
    h = tool.highlight("front", cursor)
    assert h.paths == [("front", expected, "preview")]
    assert ("front", s, "preview") in h.points and ("front", e, "preview") in h.points
    assert f"{len(expected)} vertices" in tool.prompt(("front", expected)) and "150°" in tool.prompt()


@pytest.mark.parametrize("b_piece, mode", [("back", "EQUAL"), ("fine back", "UNEQUAL")])
def test_suggested_seam_sews_facing_sides_edge_to_edge(panels, b_piece, mode):
    locate = side_by_side(panels)
    tool = SuggestSeamTool(panels.__getitem__, locate, 150.0)
    (a_s, a_e), (b_s, b_e) = facing_sides(panels, "front", b_piece)
    mf, mb = panels["front"], panels[b_piece]
    assert tool.click("front", middle_of_run(mf, a_s, a_e)).accepted
    assert "2/2" in tool.prompt()
    again = tool.click("front", middle_of_run(mf, a_s, a_e))
    assert not again.accepted and "side A" in again.message
    done = tool.click(b_piece, middle_of_run(mb, b_s, b_e))
    r = done.request
    assert r is not None and r.mode == mode and (r.piece_a, r.piece_b) == ("front", b_piece)
    assert (r.a_start, r.a_end, r.a_direction) == (a_s, a_e, "CCW")
    assert {r.b_start, r.b_end} == {b_s, b_e}
    # b1 is the end nearer a1: the seam joins the facing sides without crossing.
    d = lambda p: np.linalg.norm(locate(b_piece, p) - locate("front", a_s))  # noqa: E731
    assert d(r.b_start) < d(r.b_end)
    seam = tailor.Seam(
        "s",
        {"piece": 0, "start": list(mf.contour_point(r.a_start)), "end": list(mf.contour_point(r.a_end)),
         "direction": "ccw"},
        {"piece": 1, "start": list(mb.contour_point(r.b_start)), "end": list(mb.contour_point(r.b_end)),
         "direction": r.b_direction.lower()},
        r.mode.lower(),
    )
    res = seam.resolve([mf, mb])
    assert (len(res["a_vertices"]) == len(res["b_vertices"])) == (mode == "EQUAL")


def test_suggestion_without_corners_says_to_raise_the_angle(panels):
    tool = SuggestSeamTool(panels.__getitem__, side_by_side(panels), 0.0)
    mf = panels["front"]
    assert tool.segment("front", point(mf, 0)) is None and tool.highlight("front", point(mf, 0)).paths == []
    res = tool.click("front", point(mf, 0))
    assert not res.accepted and "raise the corner angle" in res.message
    assert not tool.undo()


# ---- bend tool --------------------------------------------------------------------------------


def test_bend_tool_stages_and_parameters(panels):
    tool = BendTool((0.2, 0.3), degrees_per_pixel=0.5)
    assert tool.stage == "axis" and "1/2" in tool.prompt() and "symmetry (on)" in tool.prompt()
    tool.hover((0.25, 0.1))
    tool.set_axis("X")
    tool.set_axis("Q")  # not an axis key: ignored
    tool.wheel(2)
    p = tool.params()
    assert p.axis_point == pytest.approx((0.25, 0.1, -0.1 * 1.25**2))
    assert p.axis_direction == (1.0, 0.0, 0.0) and p.symmetry() == ((0.25, 0.1), (1.0, 0.0))
    tool.set_axis("Y")
    tool.fix_axis(400)
    tool.hover((0.0, 0.0))  # the axis no longer follows the cursor
    tool.drag(460)
    assert tool.params().angle == pytest.approx(math.radians(30)) and "30°" in tool.prompt()
    assert tool.params().axis_point[:2] == pytest.approx((0.25, 0.1))
    tool.toggle_symmetry()
    assert tool.params().symmetry() is None
    assert tool.back() and tool.stage == "axis" and tool.angle == 0.0 and not tool.back()
    for _ in range(40):
        tool.wheel(-1)
    assert tool.depth >= 0.005
    a, b = tool.axis_segment((0.0, 0.0), (0.4, 1.0))
    assert a[0] == b[0] == pytest.approx(0.25) and a[1] < 0.0 < 1.0 < b[1]


def test_bend_tool_preview_is_the_module_bend(panels):
    m = panels["front"]
    rest = np.asarray(m.rest, np.float32)
    co = np.zeros((len(rest), 3), np.float32)
    co[:, :2] = rest
    tool = BendTool((rest.min(axis=0) + rest.max(axis=0)) / 2)
    tool.fix_axis(0)
    tool.drag(180)
    p = tool.params()
    bent = tailor.bend(co, rest, p.axis_point, p.axis_direction, math.degrees(p.angle), symmetry=p.symmetry())
    # The symmetric 90° bend wraps both halves towards the axis behind the piece.
    assert bent[:, 2].min() < -0.05 and abs(bent[:, 2].max()) < 1e-4


def operator_properties(path: Path, cls: str) -> set[str]:
    """Names of the annotated properties of operator class `cls` in an add-on source file."""
    tree = ast.parse(path.read_text())
    (node,) = [n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == cls]
    return {s.target.id for s in node.body if isinstance(s, ast.AnnAssign)}


def test_tool_results_are_the_exec_path_operators_arguments(panels):
    tool = ManualSeamTool(panels.__getitem__)
    mf, mb = panels["front"], panels["back"]
    for piece, pos in (("front", mf.corners[0]), ("front", mf.corners[1]), ("back", mb.corners[1])):
        tool.click(piece, inward(panels[piece], pos))
    request = tool.click("back", inward(mb, mb.corners[0])).request
    assert set(request.operator_kwargs()) <= operator_properties(ADDON / "seams/operators.py", "SeamAddProperties")
    bend = BendTool((0, 0)).params().operator_kwargs()
    assert set(bend) <= operator_properties(ADDON / "bend/operators.py", "BendProperties")
