"""Mesh colliders, collision levels, friction, self-collision and quality metrics through the
Python bindings."""

import numpy as np
import pytest

import tailor


def grid(w=0.3, n=10, z=0.25, cx=0.0, cy=0.0):
    """A horizontal w x w cloth of n x n cells centred at (cx, cy), height z."""
    u = np.linspace(0.0, w, n + 1, dtype=np.float32)
    xx, yy = np.meshgrid(u, u)
    rest = np.stack([xx.ravel(), yy.ravel()], axis=1).astype(np.float32)
    pos = np.column_stack([rest[:, 0] - w / 2 + cx, rest[:, 1] - w / 2 + cy, np.full(len(rest), z)]).astype(np.float32)
    tris = []
    for j in range(n):
        for i in range(n):
            a, b, c, d = j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i
            tris += [[a, b, c], [a, c, d]]
    return pos, np.array(tris, dtype=np.int64), rest


def octahedron_sphere(r=0.2, subdiv=3):
    """A sphere mesh (subdivided octahedron) with outward triangles."""
    v = [np.array(p, dtype=np.float64) for p in [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]]
    f = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    for _ in range(subdiv):
        mid = {}

        def m(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                p = v[a] + v[b]
                v.append(p / np.linalg.norm(p))
                mid[key] = len(v) - 1
            return mid[key]

        nf = []
        for a, b, c in f:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    return (np.array(v) * r).astype(np.float32), np.array(f, dtype=np.int64)


def floor(size=2.0):
    v = np.array([[-size, -size, 0], [size, -size, 0], [size, size, 0], [-size, size, 0]], dtype=np.float32)
    return v, np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64)


def make_sim(**kw):
    pos, tris, rest = grid(**kw)
    return tailor.Simulation(pos, tris, rest, tailor.Fabric(density=0.2, stretch=60.0, shear=60.0))


def test_cloth_rests_on_a_sphere_mesh_and_metrics_report_it():
    sim = make_sim()
    v, f = octahedron_sphere()
    cid = sim.add_mesh_collider(v, f)
    assert cid == 0 and sim.num_mesh_colliders == 1
    stats = sim.step(1 / 30, frames=20)
    c = stats["collision"]
    assert c["mesh_contacts"] > 0 and c["rebuilds"] + c["reuses"] == 4
    centre = sim.positions[5 * 11 + 5]
    assert centre[2] > 0.19, centre
    m = sim.metrics(cid)
    assert m["penetration_count"] == 0 and m["penetration_max_depth"] == 0.0
    assert m["self_intersections"] == 0
    assert 0.0 < m["strain_mean"] <= m["strain_max"] < 1.0
    assert m["kinetic_energy"] >= 0.0 and m["seam_gap"] == 0.0
    # The module functions agree with the method.
    pen = tailor.penetration(sim.positions, v, f)
    assert pen == {"count": 0, "max_depth": 0.0}
    assert tailor.count_self_intersections(sim.positions, grid()[1]) == 0
    assert tailor.kinetic_energy(sim.velocities, sim.masses) == pytest.approx(m["kinetic_energy"], rel=1e-5)


def test_moving_collider_positions_are_interpolated_and_carry_the_cloth():
    sim = make_sim(z=0.003)
    v, f = floor()
    cid = sim.add_mesh_collider(v, f, static_friction=1.0, kinetic_friction=1.0)
    for k in range(1, 11):
        sim.set_collider_positions(cid, v + np.array([0.0, 0.0, 0.01 * k], dtype=np.float32))
        sim.step(1 / 30)
    np.testing.assert_allclose(sim.collider_positions(cid)[:, 2], 0.1, atol=1e-6)
    assert sim.positions[:, 2].min() > 0.1


def test_levels_both_ways():
    v, f = octahedron_sphere()
    for cloth, body, collides in [(1, 2, False), (1, 1, True), (0, 2, True)]:
        sim = make_sim()
        cid = sim.add_mesh_collider(v, f)
        sim.set_collider_levels(cid, np.full(len(f), body, dtype=np.int32))  # per triangle
        sim.set_particle_levels(np.full(sim.num_particles, cloth))
        assert sim.particle_levels.dtype == np.int32
        sim.step(1 / 30, frames=20)
        assert (sim.positions[5 * 11 + 5, 2] > 0.19) == collides, (cloth, body)


def test_friction_and_self_collision_settings():
    sim = make_sim(z=0.003)
    v, f = floor()
    cid = sim.add_mesh_collider(v, f)
    n = sim.num_particles
    sim.set_particle_friction(np.full(n, 0.4), np.full(n, 0.3))
    sim.set_particle_friction()
    sim.set_collider_friction(cid, 0.8, 0.6)
    sim.set_self_collision(enabled=False)
    assert sim.self_collision["enabled"] is False and sim.self_collision["radius_setting"] is None
    auto = sim.self_collision["radius"]
    assert auto == pytest.approx(0.5 * np.mean(np.linalg.norm(np.diff(sim.rest[sim.edges], axis=1)[:, 0], axis=1)),
                                 rel=1e-3)  # half the mean rest edge
    sim.set_self_collision(radius=0.01, static_friction=0.2, kinetic_friction=0.1)
    s = sim.self_collision
    assert s["enabled"] and s["radius"] == pytest.approx(0.01) and s["radius_setting"] == pytest.approx(0.01)
    assert s["contacts"] == "spheres"
    sim.step(1 / 30)
    # Triangle contacts: the radius is the distance kept from a triangle, 4 mm when automatic.
    sim.set_self_collision(contacts="triangles")
    s = sim.self_collision
    assert s["contacts"] == "triangles" and s["radius"] == pytest.approx(tailor.DEFAULT_THICKNESS)
    sim.step(1 / 30)


def test_bad_input_raises_typed_errors():
    sim = make_sim()
    v, f = octahedron_sphere(subdiv=1)
    with pytest.raises(tailor.InvalidMeshError, match="collider triangle 0"):
        sim.add_mesh_collider(v, np.array([[0, 1, 999]]))
    with pytest.raises(tailor.InvalidMeshError):
        sim.add_mesh_collider(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.int64))
    bad = v.copy()
    bad[3, 1] = np.nan
    with pytest.raises(tailor.InvalidMeshError):
        sim.add_mesh_collider(bad, f)
    with pytest.raises(tailor.InvalidParameterError):
        sim.add_mesh_collider(v, f, insertion="nope")
    with pytest.raises(tailor.InvalidParameterError):
        sim.add_mesh_collider(v, f, static_friction=-1.0)
    cid = sim.add_mesh_collider(v, f)
    with pytest.raises(tailor.InvalidParameterError):
        sim.set_collider_positions(cid, v[:3])
    with pytest.raises(tailor.InvalidMeshError):
        sim.set_collider_positions(5, v)
    with pytest.raises(tailor.InvalidMeshError):
        sim.set_collider_positions(-1, v)
    with pytest.raises(tailor.InvalidParameterError):
        sim.set_collider_levels(cid, [1, 2])
    with pytest.raises(tailor.InvalidParameterError):
        sim.set_particle_levels([1])
    with pytest.raises(tailor.InvalidParameterError):
        sim.set_particle_friction(np.full(sim.num_particles, 0.1))
    with pytest.raises(tailor.InvalidParameterError, match="particle 2"):
        sim.set_particle_friction(np.array([0.1, 0.1, -1.0] + [0.1] * (sim.num_particles - 3)), np.full(sim.num_particles, 0.1))
    with pytest.raises(tailor.InvalidParameterError):
        sim.set_self_collision(radius=-1.0)
    with pytest.raises(tailor.InvalidParameterError, match="self_collision.contacts.*spheres, triangles"):
        sim.set_self_collision(contacts="cubes")
    with pytest.raises(tailor.InvalidMeshError):
        sim.metrics(3)


def test_metric_functions_over_arrays():
    pos = np.array([[0, 0, 0], [1, 0, 0], [0, 2, 0]], dtype=np.float32)
    s = tailor.edge_strain(pos, [[0, 1], [0, 2]], [1.0, 1.0])
    assert s["max"] == pytest.approx(1.0) and s["mean"] == pytest.approx(0.5)
    assert tailor.max_seam_gap(pos, [[1, 2]]) == pytest.approx(np.sqrt(5.0))
    assert tailor.kinetic_energy(np.ones((2, 3), np.float32), [1.0, 2.0]) == pytest.approx(4.5)
    # Two triangles crossing each other, and two far apart.
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, -0.5], [0.3, 0.2, 0.5], [0.2, 0.3, 0.5]], dtype=np.float32)
    assert tailor.count_self_intersections(v, [[0, 1, 2], [3, 4, 5]]) == 1
    assert tailor.count_self_intersections(v + np.array([[0, 0, 0]] * 3 + [[5, 0, 0]] * 3, np.float32), [[0, 1, 2], [3, 4, 5]]) == 0
    # The pairs themselves; vertices joined (sewn) count as one, so the two triangles become
    # neighbours; a joined index outside the vertices is refused.
    pairs = tailor.self_intersecting_pairs(v, [[0, 1, 2], [3, 4, 5]])
    assert pairs.dtype == np.uint32 and pairs.tolist() == [[0, 1]]
    assert tailor.self_intersecting_pairs(v, [[0, 1, 2], [3, 4, 5]], joined=[[0, 3]]).shape == (0, 2)
    with pytest.raises(tailor.InvalidMeshError, match="joined"):
        tailor.self_intersecting_pairs(v, [[0, 1, 2], [3, 4, 5]], joined=[[0, 6]])
    sv, sf = octahedron_sphere(r=1.0)
    pen = tailor.penetration([[0, 0, 0], [0, 0, 2]], sv, sf)
    assert pen["count"] == 1 and pen["max_depth"] > 0.9
    with pytest.raises(tailor.InvalidMeshError):
        tailor.edge_strain(pos, [[0, 5]], [1.0])
    with pytest.raises(tailor.InvalidParameterError):
        tailor.kinetic_energy(np.ones((2, 3), np.float32), [1.0])


def rotate_z(v: np.ndarray, angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return (v @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]], np.float32).T).astype(np.float32)


def test_attach_to_collider_rides_on_a_turning_collider():
    """Particles attached to a sphere collider turn and rise with it (no gravity: the rest of
    the cloth would pull them a few mm down, 6.5 mm measured, which is physics, not riding)."""
    pos, tris, rest = grid(z=0.23)
    sim = tailor.Simulation(pos, tris, rest, tailor.Fabric(density=0.2, stretch=60.0, shear=60.0),
                            tailor.Settings(gravity=(0.0, 0.0, 0.0)))
    v, f = octahedron_sphere()
    cid = sim.add_mesh_collider(v, f)
    start = sim.positions
    ring = np.flatnonzero(np.linalg.norm(start[:, :2], axis=1) < 0.06)  # the middle, over the pole
    sim.attach_to_collider(ring, cid, 100.0)
    assert sorted(sim.collider_attached.tolist()) == sorted(ring.tolist())
    np.testing.assert_allclose(sim.collider_attachment_targets, start[sim.collider_attached], atol=1e-6)
    for k in range(1, 21):
        t = k / 20
        sim.set_collider_positions(cid, rotate_z(v, 0.5 * np.pi * t) + np.float32([0.0, 0.0, 0.1 * t]))
        sim.step(1 / 30)
    p = sim.positions
    expect = rotate_z(start[ring], 0.5 * np.pi) + np.float32([0.0, 0.0, 0.1])
    err = np.linalg.norm(p[ring] - expect, axis=1).max()
    assert err < 2e-3, f"attached particles {err} m from the collider's motion"
    # The targets are the attach-time positions carried by the collider's rigid motion exactly.
    order = sim.collider_attached
    np.testing.assert_allclose(sim.collider_attachment_targets,
                               rotate_z(start[order], 0.5 * np.pi) + np.float32([0.0, 0.0, 0.1]), atol=1e-5)
    sim.detach_from_collider(ring[:3])
    assert len(sim.collider_attached) == len(ring) - 3
    sim.detach_from_collider()
    assert len(sim.collider_attached) == 0


def test_attach_to_collider_bad_input():
    sim = make_sim()
    v, f = octahedron_sphere(subdiv=1)
    cid = sim.add_mesh_collider(v, f)
    with pytest.raises(tailor.InvalidMeshError, match="collider id"):
        sim.attach_to_collider([0, 1], cid + 1, 100.0)
    with pytest.raises(tailor.InvalidMeshError, match="collider id"):
        sim.attach_to_collider([0, 1], -1, 100.0)
    with pytest.raises(tailor.InvalidMeshError, match="particles"):
        sim.attach_to_collider([0, sim.num_particles], cid, 100.0)
    for k in (0.0, -5.0, float("nan"), float("inf")):
        with pytest.raises(tailor.InvalidParameterError, match="stiffness"):
            sim.attach_to_collider([0, 1], cid, k)
    with pytest.raises(tailor.InvalidMeshError):
        sim.detach_from_collider([sim.num_particles])
    assert len(sim.collider_attached) == 0
