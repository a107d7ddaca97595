"""The fabric library (issue 28; `tailor_core::fabrics`): measured fabrics by name, in the
module, in a garment's setup and in a garment file; and the calibration of the source's bending
model the library's rigidities stand on."""

import json
from pathlib import Path

import numpy as np
import pytest

import tailor

SKIRT = Path(__file__).resolve().parents[1] / "native/tailor-core/tests/data/svg/skirt_two_panels.svg"


def test_the_library_lists_measured_fabrics_with_their_solver_fabric():
    lib = tailor.fabric_library()
    assert len(lib) >= 8 and len({f["name"] for f in lib}) == len(lib)
    densities = [f["density"] for f in lib]
    assert densities == sorted(densities)  # lightest first
    for f in lib:
        fab = f["fabric"]
        assert fab.density == pytest.approx(f["density"], rel=1e-6)
        # Anisotropic as measured: u along the pattern's x axis, v along its y axis.
        assert fab.stretch == pytest.approx(f["stretch_u"], rel=1e-5)
        assert fab.stretch_v == pytest.approx(f["stretch_v"], rel=1e-5)
        assert fab.shear == pytest.approx(f["shear"], rel=1e-5)
        rig = (f["rigidity_u"] * f["rigidity_bias"] * f["rigidity_v"]) ** (1 / 3)
        assert f["rigidity"] == pytest.approx(rig, rel=1e-9)
        k = tailor.HINGE_ENERGY_PER_RIGIDITY
        assert (fab.bend, fab.bend_bias, fab.bend_v) == pytest.approx(
            (f["rigidity_u"] / k, f["rigidity_bias"] / k, f["rigidity_v"] / k), rel=1e-5)
        assert repr(tailor.Fabric.named(f["name"])) == repr(fab)
    denim = next(f for f in lib if f["name"] == "11oz-black-denim")
    assert denim["rigidity_v"] == pytest.approx(96.951576e-6 / 4)  # the source's ke over 4 (below)
    with pytest.raises(tailor.InvalidParameterError, match="silk.*not in the fabric library.*11oz-black-denim"):
        tailor.Fabric.named("silk")


def test_a_garment_takes_its_fabrics_by_name_in_its_setup_and_its_file(tmp_path):
    g = tailor.Garment.from_pattern(str(SKIRT), edge=0.08)
    n = len(g.pieces)
    g.setup = {**g.setup, "fabrics": ["11oz-black-denim"] + ["tango-red-jet-set"] * (n - 1)}
    denim, light = tailor.Fabric.named("11oz-black-denim"), tailor.Fabric.named("tango-red-jet-set")
    assert g.setup["fabrics"][0]["stretch"] == pytest.approx(denim.stretch)  # kept as values
    sim, offsets = g.build_simulation()
    meshes = g.meshes()
    masses = np.asarray(sim.masses)
    for i, (m, off) in enumerate(zip(meshes, offsets)):
        rest = np.asarray(m.rest, np.float64)
        t = np.asarray(m.triangles, np.int64)
        area = 0.5 * np.abs(np.cross(rest[t[:, 1]] - rest[t[:, 0]], rest[t[:, 2]] - rest[t[:, 0]])).sum()
        density = denim.density if i == 0 else light.density
        assert masses[off:off + len(rest)].sum() == pytest.approx(density * area, rel=1e-4), i
    # A garment file naming its fabrics loads with their values; an unknown name says so.
    path = tmp_path / "skirt.json"
    g.save(str(path))
    doc = json.loads(path.read_text())
    doc["setup"]["fabrics"] = ["royal-target"] * n
    path.write_text(json.dumps(doc))
    again = tailor.Garment.load(str(path))
    assert again.setup["fabrics"][0]["bend"] == pytest.approx(tailor.Fabric.named("royal-target").bend)
    doc["setup"]["fabrics"] = ["velvet"] * n
    path.write_text(json.dumps(doc))
    with pytest.raises(tailor.TailorError, match="velvet"):
        tailor.Garment.load(str(path))


def _hinges(tris):
    edges = {}
    for tri in tris:
        for k in range(3):
            a, b, o = int(tri[k]), int(tri[(k + 1) % 3]), int(tri[(k + 2) % 3])
            edges.setdefault((min(a, b), max(a, b)), []).append(o)
    return [(a, b, o[0], o[1]) for (a, b), o in edges.items() if len(o) == 2]


def _area(a, b, c):
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a))


def test_the_sources_bending_model_gives_a_quarter_of_the_continuum_energy():
    """`ARCSIM_HINGE_ENERGY_PER_RIGIDITY`: ARCSim's hinge energy `ke·l²/(2a)·θ²/4` (the source's
    simulator, `physics.cpp`), summed over a mesh of ours bent onto a cylinder away from its
    border, is a quarter of the continuum `½·B·κ²·A` with `B = ke`: a measured `ke` is a
    rigidity of `ke/4` (0.2512 at 5 mm edges)."""
    piece = tailor.Piece.from_json(json.dumps({
        "name": "strip", "outline": [[0, 0], [0.3, 0], [0.3, 0.2], [0, 0.2]], "fixed_vertices": [0, 1, 2, 3],
        "holes": [], "internal_lines": [], "notches": [], "grain": None, "placement": None, "edges": []}))
    ratios = []
    for edge in (0.01, 0.005):
        m = tailor.triangulate(piece, edge)
        r2 = np.asarray(m.rest, np.float64)
        rest = np.c_[r2, np.zeros(len(r2))]
        radius = 0.15
        x = np.c_[radius * np.sin(r2[:, 0] / radius), r2[:, 1], radius * (1 - np.cos(r2[:, 0] / radius))]
        energy = area = 0.0
        for a, b, c, d in _hinges(np.asarray(m.triangles)):
            if not all(0.03 < rest[i][0] < 0.27 and 0.03 < rest[i][1] < 0.17 for i in (a, b, c, d)):
                continue
            n0 = np.cross(x[b] - x[a], x[c] - x[a])
            n1 = np.cross(x[d] - x[a], x[b] - x[a])
            theta = np.arccos(np.clip(np.dot(n0, n1) / np.linalg.norm(n0) / np.linalg.norm(n1), -1, 1))
            two = _area(rest[a], rest[b], rest[c]) + _area(rest[a], rest[b], rest[d])
            length = np.linalg.norm(rest[b] - rest[a])
            energy += length**2 / (2 * two) * theta**2 / 4
            area += two / 3
        ratios.append(energy / (0.5 * area / radius**2))
    assert all(abs(r - 0.25) < 0.01 for r in ratios), ratios
    assert abs(ratios[1] - 0.25) <= abs(ratios[0] - 0.25), ratios  # nearer as the mesh refines


def test_an_anisotropic_fabric_is_simulated_by_direction(tmp_path):
    """`Fabric(stretch_v=...)`: a strip hanging along the pattern's y axis (v) stretches by the
    stiffness along v; the same strip of the isotropic fabric of u's stiffness hangs longer. The
    fabric's directions reach a garment's setup and its file; a bad value is refused by name."""
    def hang(fabric, grain=0.0):
        w, l, nx, ny = 0.1, 0.5, 4, 20
        xs, ys = np.meshgrid(np.linspace(0, w, nx + 1), np.linspace(0, l, ny + 1))
        rest = np.stack([xs.ravel(), ys.ravel()], 1).astype(np.float32)
        idx = lambda i, j: j * (nx + 1) + i  # noqa: E731
        tris = [t for j in range(ny) for i in range(nx)
                for t in ((idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)), (idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)))]
        pos = np.stack([rest[:, 0], np.zeros(len(rest)), rest[:, 1] - l], 1).astype(np.float32)
        sim = tailor.Simulation(pos, np.asarray(tris, np.uint32), rest, fabric=fabric,
                                settings=tailor.Settings(iterations=100, air_damping=4.0))
        if grain:
            sim.set_triangle_grain(np.full(len(tris), grain, np.float32))
        sim.pin(np.arange(idx(0, ny), idx(nx, ny) + 1, dtype=np.uint32))
        for _ in range(120):
            sim.step(1 / 30)
        return -float(np.asarray(sim.positions)[: nx + 1, 2].mean()) - l

    soft = hang(tailor.Fabric(0.2, 20.0, 20.0, 1e-7))
    aniso = hang(tailor.Fabric(0.2, 20.0, 20.0, 1e-7, stretch_v=80.0))
    # The fabric turned a quarter (its u axis along the strip): u's stiffness again.
    turned = hang(tailor.Fabric(0.2, 20.0, 20.0, 1e-7, stretch_v=80.0), grain=np.pi / 2)
    want = 0.2 * 9.81 * 0.5 ** 2 / 2
    assert soft == pytest.approx(want / 20.0, rel=0.05) and aniso == pytest.approx(want / 80.0, rel=0.05)
    assert turned == pytest.approx(want / 20.0, rel=0.05)
    f = tailor.Fabric(0.2, 20.0, 20.0, 1e-7, stretch_v=80.0, bend_v=2e-7)
    assert "stretch_v=80" in repr(f) and f.bend_bias is None
    g = tailor.Garment.from_pattern(str(SKIRT), edge=0.08)
    g.setup = {**g.setup, "fabrics": [{"density": 0.2, "stretch": 20.0, "shear": 20.0, "bend": 1e-7,
                                       "stretch_v": 80.0}] * len(g.pieces)}
    path = tmp_path / "aniso.json"
    g.save(str(path))
    assert tailor.Garment.load(str(path)).setup["fabrics"][0]["stretch_v"] == 80.0
    with pytest.raises(tailor.InvalidParameterError, match="stretch_v"):
        hang(tailor.Fabric(0.2, 20.0, 20.0, 1e-7, stretch_v=-1.0))


def test_a_fabrics_directions_are_the_solvers():
    """`Fabric.directions()`: the stiffness in each direction as the core takes it (v as u, the
    bias the mean of u's and v's bending, unless given)."""
    d = tailor.Fabric(0.2, 100.0, 10.0, 1e-5, bend_v=3e-5).directions()
    assert d["stretch_u"] == d["stretch_v"] == 100.0
    assert d["bend_u"] == pytest.approx(1e-5) and d["bend_v"] == pytest.approx(3e-5)
    assert d["bend_bias"] == pytest.approx(2e-5)
    assert tailor.Fabric(bend_bias=4e-5).directions()["bend_bias"] == pytest.approx(4e-5)
