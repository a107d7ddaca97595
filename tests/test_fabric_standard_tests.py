"""The simulated standard tests' arithmetic (`bench/fabric/standard_tests.py`, issue 28): Peirce's
bending length from the cantilever's angle, the beam's bending length, and the Cusick drape
coefficient from a rasterised shadow, checked on shapes whose answers are known; and a short
cantilever and drape through the module that give figures in the physical range."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench" / "fabric"))
import standard_tests as st  # noqa: E402


def test_peirce_gives_half_the_overhang_at_the_standards_angle():
    # ASTM D1388 reads c = l/2 where the chord drops 41.5 degrees; Peirce's formula agrees to 2 %.
    assert st.bending_length_from_angle(1.0, math.radians(41.5)) == pytest.approx(0.5, rel=0.02)
    # A stiffer strip (a smaller angle) has the longer bending length.
    assert st.bending_length_from_angle(1.0, math.radians(20)) > st.bending_length_from_angle(1.0, math.radians(60))


def test_beam_bending_length():
    assert st.beam_bending_length(2e-5, 0.15) == pytest.approx((2e-5 / (0.15 * 9.81)) ** (1 / 3))
    # A fabric's beam stands on the rigidity its hinge stiffness stands for (3 x bend).
    import tailor

    assert st.rigidity(tailor.Fabric(bend=2e-5)) == pytest.approx(6e-5)
    names = [n for n, _ in st.fabrics()]
    assert names[:-1] == [f["name"] for f in tailor.fabric_library()] and names[-1].startswith("default")
    # Each library fabric run isotropic, its measured directions' means: one rigidity to compare.
    for (_, f), lib in zip(st.fabrics(), tailor.fabric_library()):
        assert f.stretch_v is None and f.bend_bias is None and f.bend_v is None
        assert st.rigidity(f) == pytest.approx(lib["rigidity"], rel=1e-6)
        assert f.stretch == pytest.approx(math.sqrt(lib["stretch_u"] * lib["stretch_v"]), rel=1e-6)


def disc():
    mesh = st.piece_mesh(np.column_stack([0.15 * np.cos(t := np.linspace(0, 2 * np.pi, 189, endpoint=False)),
                                          0.15 * np.sin(t)]), 0.01, "disc")
    rest = np.asarray(mesh.rest, np.float64)
    return np.column_stack([rest, np.zeros(len(rest))]), np.asarray(mesh.triangles)


def test_the_drape_coefficient_of_a_flat_and_of_a_hanging_disc():
    x, tris = disc()
    flat = st.shadow_area(x, tris, 0.16)
    assert flat == pytest.approx(math.pi * 0.15 ** 2, rel=0.01)
    assert st.drape_coefficient(flat) == pytest.approx(1.0, abs=0.01)
    # Everything outside the support folded straight down: the shadow is the support's.
    r = np.linalg.norm(x[:, :2], axis=1)
    hung = x.copy()
    out = r > 0.09
    hung[out, :2] *= (0.09 / r[out])[:, None]
    hung[out, 2] = -(r[out] - 0.09)
    assert st.drape_coefficient(st.shadow_area(hung, tris, 0.16)) == pytest.approx(0.0, abs=0.02)


def test_a_short_cantilever_and_drape_through_the_module():
    import tailor

    c = st.cantilever(tailor.Fabric(density=0.15, bend=2e-5), 15, 15)
    # The beam length of the rigidity 6e-5 N·m the hinge stiffness 2e-5 stands for.
    assert 0.0 < c["theta_deg"] < 90.0 and c["c"] > 0.0 and c["c_beam"] == pytest.approx(0.03441, rel=1e-3)
    d = st.cusick(tailor.Fabric.named("11oz-black-denim"), 15, 10)
    assert 0.0 < d["dc"] < 1.0
