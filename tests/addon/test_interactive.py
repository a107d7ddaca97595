"""The interactive tools' region-free parts on the bpy wheel (no window, so no modal loop: that
runs in tests/gui): rays onto placed and bent pieces give rest points, picks made by rays drive
the tools' state machines to the exec-path operators, and highlights land on the contour."""

import math

import numpy as np
import pytest

import bpy

from conftest import DATA, import_pattern

SKIRT_SVG = DATA / "svg/skirt_two_panels.svg"


def two_panels():
    import_pattern(SKIRT_SVG, edge_length=0.05)
    return bpy.data.objects["skirt front"], bpy.data.objects["skirt back"]


def world(obj, local):
    m = np.array(obj.matrix_world, np.float64)
    return np.asarray(local, np.float64) @ m[:3, :3].T + m[:3, 3]


def ray_down_at(addon, obj, local_point):
    """pick_ray straight down onto the world point of `local_point` (flat pieces in the xy plane)."""
    p = world(obj, local_point)
    return addon.seams.viewport.pick_ray(bpy.context, p + (0, 0, 1.0), (0, 0, -1.0))


def test_ray_onto_a_placed_bent_piece_gives_its_rest_point(scene, addon):
    front, _ = two_panels()
    front.location = (0.3, -0.2, 0.4)
    front.rotation_euler = (0.3, 0.1, 0.7)
    bpy.context.view_layer.objects.active = front
    rest = addon.scene_data.rest_of(front).astype(np.float64)
    c = (rest.min(axis=0) + rest.max(axis=0)) / 2
    assert bpy.ops.tailor.bend(
        axis_point=(c[0], c[1], -0.15), axis_direction=(0, 1, 0), angle=math.radians(50), use_symmetry=True,
        symmetry_point=(c[0], c[1]), symmetry_direction=(0, 1),
    ) == {"FINISHED"}
    bpy.context.view_layer.update()
    mesh = addon.seams.viewport.mesh_for(front.name)
    co = addon.scene_data.vertex_positions(front, world=False).astype(np.float64)
    tris = np.asarray(mesh.triangles, np.int64)
    axis_world = world(front, (c[0], c[1], -0.15))
    for k in (0, len(tris) // 3, len(tris) // 2, len(tris) - 1):
        local = co[tris[k]]
        centroid = local.mean(axis=0)
        n = world(front, centroid + np.cross(local[1] - local[0], local[2] - local[0])) - world(front, centroid)
        n /= np.linalg.norm(n)
        p = world(front, centroid)
        if n @ (p - axis_world) < 0:
            n = -n  # from the convex side, away from the axis: nothing else in the way
        piece, got = addon.seams.viewport.pick_ray(bpy.context, p + 0.05 * n, -n)
        assert piece == front.name
        np.testing.assert_allclose(got, rest[tris[k]].mean(axis=0), atol=2e-4)
    assert addon.seams.viewport.pick_ray(bpy.context, (50.0, 50.0, 1.0), (0, 0, -1.0)) == (None, None)
    # Only the pieces asked for are picked (the bend tool's active piece).
    p = world(front, co[tris[0]].mean(axis=0))
    assert addon.seams.viewport.pick_ray(bpy.context, p + (0, 0, 2.0), (0, 0, -1.0), only={"other"}) == (None, None)


def test_manual_tool_picks_by_ray_sew_through_the_exec_path(scene, addon):
    import tailor

    front, back = two_panels()
    bpy.context.view_layer.update()
    vp = addon.seams.viewport
    mf, mb = vp.mesh_for(front.name), vp.mesh_for(back.name)
    tool = addon.core.seam_tools.ManualSeamTool(vp.mesh_for)

    def at(obj, mesh, position, inward=0.005):
        p = np.array([*mesh.contour_point(position), 0.0])
        c = np.array([*np.asarray(mesh.rest).mean(axis=0), 0.0])
        return ray_down_at(addon, obj, p + inward * (c - p) / np.linalg.norm(c - p))

    a1, an = mf.corners[0], mf.corners[1]
    b1, target = mb.corners[1], mb.corners[0]
    for obj, mesh, pos in ((front, mf, a1), (front, mf, an), (back, mb, b1)):
        piece, point = at(obj, mesh, pos)
        assert piece == obj.name and tool.click(piece, point).accepted
    piece, point = at(back, mb, target)
    highlight = tool.highlight(piece, point)
    batches = vp.highlight_batches(highlight)
    lines = [co for kind, role, co in batches if kind == "LINES" and role == "preview"]
    expected = tailor.nearer_candidate(mb, b1, len(tool.path_a.positions), tuple(point))
    run = np.asarray(mb.rest)[np.asarray(mb.contour)[expected.positions]]
    ends = world(back, np.c_[run, np.zeros(len(run))])
    np.testing.assert_allclose(lines[0][0], ends[0], atol=1e-5)
    np.testing.assert_allclose(lines[0][-1], ends[-1], atol=1e-5)
    request = tool.click(piece, point).request
    assert bpy.ops.tailor.seam_add(**request.operator_kwargs()) == {"FINISHED"}
    (item,) = scene.tailor.seams
    assert (item.piece_a, item.piece_b, item.mode) == (front, back, "EQUAL")
    assert tuple(item.a_start) == pytest.approx(mf.contour_point(a1)) and tuple(item.a_end) == pytest.approx(
        mf.contour_point(an)
    )
    assert tuple(item.b_end) == pytest.approx(mb.contour_point(expected.positions[-1]))
    assert item.a_count == item.b_count == len(expected.positions)


def test_suggestion_tool_by_ray_sews_facing_sides(scene, addon):
    front, back = two_panels()
    bpy.context.view_layer.update()
    vp = addon.seams.viewport
    mf, mb = vp.mesh_for(front.name), vp.mesh_for(back.name)
    tool = addon.core.seam_tools.SuggestSeamTool(vp.mesh_for, vp.locate, math.degrees(scene.tailor.corner_angle))

    def side(obj, mesh, rightmost):
        cs = list(mesh.corners)
        runs = list(zip(cs, cs[1:] + cs[:1]))
        x = lambda r: (vp.locate(obj.name, r[0])[0] + vp.locate(obj.name, r[1])[0]) / 2  # noqa: E731
        return max(runs, key=x) if rightmost else min(runs, key=x)

    def middle(obj, mesh, run):
        p = (np.asarray(mesh.contour_point(run[0])) + np.asarray(mesh.contour_point(run[1]))) / 2
        c = np.asarray(mesh.rest).mean(axis=0)
        return ray_down_at(addon, obj, np.r_[p + 0.01 * (c - p) / np.linalg.norm(c - p), 0.0])

    ra, rb = side(front, mf, True), side(back, mb, False)
    assert tool.click(*middle(front, mf, ra)).accepted
    request = tool.click(*middle(back, mb, rb)).request
    assert bpy.ops.tailor.seam_add(**request.operator_kwargs()) == {"FINISHED"}
    (item,) = scene.tailor.seams
    a1 = vp.locate(front.name, ra[0])
    near = min(rb, key=lambda p: np.linalg.norm(vp.locate(back.name, p) - a1))
    assert tuple(item.b_start) == pytest.approx(mb.contour_point(near))
    assert item.mode == ("EQUAL" if item.a_count == item.b_count else "UNEQUAL")


def test_bend_tool_parameters_are_the_bend_operators(scene, addon):
    import tailor

    front, _ = two_panels()
    bpy.context.view_layer.objects.active = front
    rest = addon.scene_data.rest_of(front)
    tool = addon.core.bend_tool.BendTool((rest.min(axis=0) + rest.max(axis=0)) / 2)
    tool.hover(rest.mean(axis=0))
    tool.fix_axis(100)
    tool.drag(220)
    p = tool.params()
    assert bpy.ops.tailor.bend(**p.operator_kwargs()) == {"FINISHED"}
    co = np.zeros((len(rest), 3), np.float32)
    co[:, :2] = rest
    ref = tailor.bend(co, rest, p.axis_point, p.axis_direction, 60.0, symmetry=p.symmetry())
    np.testing.assert_allclose(addon.scene_data.vertex_positions(front, world=False), ref, atol=1e-5)
    assert math.degrees(front.tailor_piece.bend_angle) == pytest.approx(60.0)
