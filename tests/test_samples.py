"""The sample garments (sample_blends/{tshirt,skirt,trousers,layered}.blend and their garment
files): every .blend opens with the bpy wheel, its garment read with the add-on's own reader
(sample_blends/build/read_sample.py, in a process of its own) matches the garment file beside it,
and a few frames baked through the module on those arrays, with the body as mesh collider, keep
the quality metrics: no NaN, no particle deeper in the body than the thickness, seams closing;
and each garment file, dressed on the character at rest as check_garments.py does, has all
its seams met within 45 frames and its widest seam gap within a bound over frames 6-11 after that
(about 45 s for the four on the 2-core sandbox, 34 s of it the layered outfit's 15,139
particles). Skips without the bpy wheel."""

import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import tailor

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "sample_blends"
NAMES = ("tshirt", "skirt", "trousers", "layered")
Z_TO_Y = np.array([[1, 0, 0], [0, 0, 1], [0, -1, 0]], np.float32)  # Blender (x, y, z) -> glTF (x, z, -y)

pytestmark = pytest.mark.skipif(
    importlib.util.find_spec("bpy") is None, reason='bpy wheel not installed: .venv/bin/pip install "bpy==4.5.*"'
)


@pytest.fixture(scope="module", params=NAMES)
def sample(request, tmp_path_factory):
    name = request.param
    out = tmp_path_factory.mktemp(name) / "arrays.npz"
    run = subprocess.run([sys.executable, str(SAMPLES / "build" / "read_sample.py"), str(SAMPLES / f"{name}.blend"),
                          str(out)], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    data = dict(np.load(out))
    return name, json.loads(str(data.pop("meta"))), data


def test_blend_matches_its_garment_file(sample):
    name, meta, a = sample
    g = tailor.Garment.load(str(SAMPLES / f"{name}.json"))
    sim, offsets = g.build_simulation()
    assert len(g.seams) == len(meta["seams"]) > 0 and len(g.pieces) == len(meta["pieces"])
    np.testing.assert_allclose(sim.positions, a["positions"] @ Z_TO_Y.T, atol=2e-5)
    np.testing.assert_array_equal(offsets, a["offsets"])
    stored = g.setup
    for fabric, blend in zip(stored["fabrics"], meta["fabrics"], strict=True):
        assert fabric == pytest.approx(blend)
    assert all(f["density"] > 0 and f["stretch"] > 0 for f in meta["fabrics"])
    # Live and Bake in the .blend simulate the sample as the garment file says (the layered
    # outfit collides with itself, with its own sphere radius). Friction: the files recorded
    # none but the layered outfit's (version-1 files read with the solver's 0.3/0.2, which the
    # command line used), the .blend has the panel's.
    recorded = name == "layered"
    assert meta["simulate"] == {"thickness": pytest.approx(stored["thickness"]),
                                "self_collision": stored["self_collision"],
                                "self_collision_radius": pytest.approx(stored["self_collision_radius"]),
                                "friction_static": pytest.approx(stored["friction"]["static"] if recorded else 0.5),
                                "friction_kinetic": pytest.approx(stored["friction"]["kinetic"] if recorded else 0.3)}
    if name == "trousers":
        # Trouser legs 3 and 4; the body's arms 1 and 2 and legs 3 and 4: trousers never meet the arms.
        assert set(np.unique(a["levels"])) == {3, 4}
        assert set(np.unique(a["body_levels"])) == {0, 1, 2, 3, 4}
        levels, warnings = g.collider_levels(len(a["body_levels"]))
        np.testing.assert_array_equal(levels, a["body_levels"])
        assert not warnings
    assert (a["pins"] > 0).any()  # waistband / shoulder line / trouser tops are pinned
    assert meta["pose_position"] == "REST"


def test_a_few_frames_bake_with_the_metrics_holding(sample):
    name, meta, a = sample
    f = meta["fabrics"][0]
    # The .blend's arrays are Blender's Z-up; the solver holds gravity while the seams close.
    settings = tailor.Settings(substeps=8, iterations=15, gravity=(0.0, 0.0, -9.81))
    sim = tailor.Simulation(a["positions"], a["triangles"], a["rest"], tailor.Fabric(**f), settings)
    for k in range(len(meta["seams"])):
        av, aw, bv, bw = (a[f"seam{k}_{x}"] for x in ("av", "aw", "bv", "bw"))
        # A dart's tip is sewn to itself: the module's Garment.build_simulation leaves it out too.
        single = lambda v, w: (w[:, 1] == 0) | (v[:, 0] == v[:, 1])  # noqa: E731
        keep = ~(single(av, aw) & single(bv, bw) & (av[:, 0] == bv[:, 0]))
        sim.add_weighted_seam(av[keep], aw[keep], bv[keep], bw[keep], name=meta["seams"][k])
    if a["levels"].any():
        sim.set_particle_levels(a["levels"])
    thickness = 0.004
    sim.thickness = thickness
    cid = sim.add_mesh_collider(a["body"], a["body_triangles"])
    sim.set_collider_levels(cid, a["body_levels"])
    gap0 = sim.metrics(cid)["seam_gap"]
    for _ in range(6):
        sim.step(1.0 / 30.0)
        m = sim.metrics(cid)
        assert np.isfinite(sim.positions).all()
        assert m["penetration_max_depth"] <= thickness, m
    # Seams close at the ramp's set speed (0.5 m/s): the widest gap shrinks by most of 6 frames' worth.
    assert m["seam_gap"] < gap0 - 0.8 * settings.ramp_closing_speed * 6 / 30.0, (gap0, m)


# Seam gap (m) of each garment file once all its seams have met at rest (the pins attach), over
# frames 6-11 after that: (median, worst frame). Measured 2026-11-26 on the 2-core sandbox (this
# test prints them), since all seam pairs meet together and contact friction counts the cloth's
# pressure on the body (not on sewn particles): tshirt 0.23 / 0.25 mm, skirt 0.50 / 0.51,
# trousers 0.38 / 0.39, layered 0.51 / 2.25 (2026-11-22: 0.66 / 0.74, 0.43 / 0.49, 0.39 / 0.48,
# 0.47 / 0.76). The layered outfit's worst frame is a single-frame spike (frame 8 after the
# release; 0.44-0.57 mm at the others): its bound is 3 mm until that is understood (issue 18's
# note). Nothing may be deeper in the body than the thickness at any of them.
SETTLED = {"tshirt": (1e-3, 1e-3), "skirt": (1e-3, 1e-3), "trousers": (1e-3, 1e-3), "layered": (1e-3, 3e-3)}


@pytest.mark.parametrize("name", NAMES)
def test_the_garment_file_assembles_on_the_character_at_rest(name):
    """The garment file as `check_garments.py` runs it (its own fabric, levels, pins and
    self-collision, the body of character.glb at rest): every seam meets (the pins attach:
    `tailor.bake.ColliderPins.after_frame`) within 45 frames; over frames 6-11 after that the
    seam gap's median and worst frame are within their bounds and nothing is inside the body."""
    from tailor import dress as dressing
    from tailor.motion import ColliderMotion

    character = ColliderMotion(SAMPLES / "character.glb")
    d = dressing.dress(SAMPLES / f"{name}.json", character.rest, character.triangles)
    released = None
    for f in range(45):
        d.step(1.0 / 30.0)
        if d.pins.attached:
            released = f + 1
            break
    assert released is not None, f"{name}: the seams have not all met after 45 frames"
    for _ in range(5):
        d.step(1.0 / 30.0)
    gaps = []
    for _ in range(6):
        d.step(1.0 / 30.0)
        q = d.record()
        assert not q["nan"]
        assert q["penetration_max_m"] <= d.info["thickness_m"], (name, q)
        gaps.append(q["seam_gap_max_m"])
    print(f"{name}: seams met at frame {released}; seam gap over the next frames 6-11 "
          f"{[round(g * 1e3, 2) for g in gaps]} mm, strain {q['strain_max']:.2f}")
    median_bound, worst_bound = SETTLED[name]
    assert float(np.median(gaps)) < median_bound and max(gaps) < worst_bound, (name, released, gaps)
