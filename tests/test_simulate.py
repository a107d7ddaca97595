"""`python -m tailor simulate`: a garment file on a collider, as pipeline scripts run it."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import tailor
from tailor.commands.simulate import FAILED_CHECKS

DATA = Path(__file__).resolve().parents[1] / "native/tailor-core/tests/data"
SKIRT = DATA / "garmentcode" / "flare_skirt_specification.json"


def cli(*args):
    return subprocess.run([sys.executable, "-m", "tailor", *map(str, args)], capture_output=True, text=True)


def write_sphere_obj(path, center, radius, subdivisions=3):
    """An icosphere written as OBJ (the test's own collider, no shared data needed)."""
    t = (1 + 5**0.5) / 2
    v = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
         [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    f = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6],
         [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10],
         [8, 6, 7], [9, 8, 1]]
    v = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(subdivisions):
        mid, nf = {}, []

        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                p = v[a] + v[b]
                v.append(p / np.linalg.norm(p))
                mid[k] = len(v) - 1
            return mid[k]

        for a, b, c in f:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            nf += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        f = nf
    with open(path, "w") as fh:
        for p in v:
            q = np.asarray(center) + radius * p
            fh.write(f"v {q[0]:.6f} {q[1]:.6f} {q[2]:.6f}\n")
        for a, b, c in f:
            fh.write(f"f {a + 1} {b + 1} {c + 1}\n")


def coarse_skirt_on_a_ball(tmp_path):
    """The skirt imported at 8 cm edges and `tailor simulate`'s arguments for 3 Preview frames
    on a ball under it: (garment file, arguments after the garment)."""
    garment = tmp_path / "skirt.json"
    assert cli("import", SKIRT, "--edge", "0.08", "-o", garment).returncode == 0
    body = tmp_path / "ball.obj"
    write_sphere_obj(body, (0.0, 0.9, 0.0), 0.15, subdivisions=2)
    return garment, ["--collider", body, "--frames", "3", "--preset", "preview"]


def test_skirt_on_a_sphere_with_report_and_cache(tmp_path):
    garment = tmp_path / "skirt.json"
    r = cli("import", SKIRT, "--edge", "0.05", "-o", garment)
    assert r.returncode == 0, r.stderr
    body = tmp_path / "ball.obj"
    write_sphere_obj(body, (0.0, 0.9, 0.0), 0.15)
    report, cache = tmp_path / "report.json", tmp_path / "skirt.pc2"
    r = cli("simulate", garment, "--collider", body, "--frames", "8", "--report", report, "-o", cache)
    # Eight frames end while the seams still close: the report and the cache are written, and
    # the run fails "open" (it never assembled), exit 3.
    assert r.returncode == 3, r.stderr
    rep = json.loads(report.read_text())
    assert [v["check"] for v in rep["summary"]["verdict"]] == ["open"], rep["summary"]["verdict"]
    assert "still closing" in rep["summary"]["verdict"][0]["reason"]
    assert len(rep["frames"]) == 8
    keys = {"frame", "ms", "seam_gap_max_m", "penetration_count", "penetration_max_m", "self_intersections", "strain_max", "nan"}
    assert keys <= set(rep["frames"][0]) and keys <= set(rep["summary"])
    assert not rep["summary"]["nan"]
    # The cache is the garment welded along its seams (the default for every output), and
    # beside it the mesh it deforms: as many vertices, in its order.
    c = tailor.read_pc2(cache)
    info = json.loads(cli("info", garment, "--json").stdout)
    v, t = tailor.read_mesh(tmp_path / "skirt.obj")
    assert c["frames"].shape == (8, len(v), 3) and len(v) < sum(p["vertices"] for p in info["pieces"])
    assert rep["outputs"] == "welded" and t.max() == len(v) - 1


def test_per_piece_writes_the_pieces_as_solved_and_resumes(tmp_path):
    """`--per-piece`: the cache holds every particle, piece after piece in the garment file's
    order (the welded cache is those particles welded), its mesh all the pieces, one OBJ a
    piece and frame, one USD mesh a piece named after it; a killed per-piece run resumes."""
    from pxr import Usd, UsdGeom

    garment, common = coarse_skirt_on_a_ball(tmp_path)
    r = cli("simulate", garment, *common, "--report", tmp_path / "w.json", "-o", tmp_path / "welded.pc2")
    assert r.returncode in (0, 3), r.stderr
    r = cli("simulate", garment, *common, "--report", tmp_path / "p.json", "-o", tmp_path / "pieces.pc2",
            "--per-piece", "--usd", tmp_path / "pieces.usda", "--obj-dir", tmp_path / "objs")
    assert r.returncode in (0, 3), r.stderr
    assert json.loads((tmp_path / "p.json").read_text())["outputs"] == "per piece"
    g = tailor.Garment.load(garment)
    meshes = g.meshes()
    sim, _ = g.build_simulation()
    particles = tailor.read_pc2(tmp_path / "pieces.pc2")["frames"]
    assert particles.shape == (3, sim.num_particles, 3)
    w = tailor.weld(sim.positions, sim.triangles, sim.seam_pairs())
    np.testing.assert_array_equal(tailor.read_pc2(tmp_path / "welded.pc2")["frames"][2], w.apply(particles[2]))
    v, t = tailor.read_mesh(tmp_path / "pieces.obj")
    np.testing.assert_array_equal(t, np.asarray(sim.triangles))
    assert len(v) == sim.num_particles
    stage = Usd.Stage.Open(str(tmp_path / "pieces.usda"))
    prims = [p for p in stage.GetPrimAtPath("/Garment").GetChildren()]
    assert [p.GetName() for p in prims] == [p.name for p in g.pieces]
    start = 0
    for piece, mesh, prim in zip(g.pieces, meshes, prims):
        n = len(mesh.rest)
        usd_points = np.array(UsdGeom.Mesh(prim).GetPointsAttr().Get(2))
        np.testing.assert_array_equal(usd_points, particles[1][start:start + n])
        np.testing.assert_array_equal(np.array(UsdGeom.Mesh(prim).GetFaceVertexIndicesAttr().Get()),
                                      np.asarray(mesh.triangles).reshape(-1))
        ov, ot = tailor.read_mesh(tmp_path / "objs" / f"skirt.{piece.name}.0003.obj")
        np.testing.assert_array_equal(ov, particles[2][start:start + n])
        start += n
    # Killed after the first frame's record (kept by hand), the per-piece run resumes to the same cache.
    whole = (tmp_path / "pieces.pc2").read_bytes()
    keep = tailor.read_pc2(tmp_path / "pieces.pc2")["frames"][:1]
    tailor.write_pc2(tmp_path / "cut.pc2", keep, 1.0, 1.0)
    r = cli("simulate", garment, *common, "--report", tmp_path / "c.json", "-o", tmp_path / "cut.pc2",
            "--per-piece", "--resume")
    assert r.returncode in (0, 3), r.stderr
    assert (tmp_path / "cut.pc2").read_bytes() == whole
    bad = cli("simulate", garment, *common, "--report", tmp_path / "b.json", "-o", tmp_path / "cut.pc2", "--resume")
    assert bad.returncode == 2 and "Traceback" not in bad.stderr, bad.stderr  # a per-piece cache is not welded


def test_a_skirt_below_the_body_is_reported_as_fallen_and_the_command_fails(tmp_path):
    """Issue 18: a skirt with nothing to hang on (the body, a 15 cm ball, is 1 m above its
    waist) closes its seams under 1 mm, pierces nothing and never diverges, and falls: the
    report says so (no particle near the body, the centroid metres below where it started), a
    warning names the check, and the command exits 3."""
    garment = tmp_path / "skirt.json"
    assert cli("import", SKIRT, "--edge", "0.05", "-o", garment).returncode == 0
    body = tmp_path / "ball.obj"
    write_sphere_obj(body, (0.0, 2.0, 0.0), 0.15)
    report = tmp_path / "report.json"
    r = cli("simulate", garment, "--collider", body, "--frames", "40", "--report", report)
    assert r.returncode == 3, (r.returncode, r.stdout[-2000:], r.stderr)
    rep = json.loads(report.read_text())
    s, last = rep["summary"], rep["frames"][-1]
    assert last["seam_gap_max_m"] < 1e-3 and last["penetration_count"] == 0 and not s["nan"], last
    assert last["on_body_fraction"] == 0.0 and last["centroid_shift_m"] > 0.5, last
    assert [f["check"] for f in last["failed"]] == ["fell"]
    assert s["on_body_fraction"] == 0.0 and s["centroid_shift_m"] > 0.5
    assert [v["check"] for v in s["verdict"]] == ["fell"] and s["verdict"][0]["frame"] > 1, s["verdict"]
    warnings = [line for line in r.stdout.splitlines() if line.startswith("warning: ")]
    assert warnings == [f"warning: fell from frame {s['verdict'][0]['frame']}: {s['verdict'][0]['reason']}"], warnings
    summary = json.loads(r.stdout.splitlines()[-1].removeprefix("summary: "))
    assert summary["verdict"] == s["verdict"] and summary["on_body_fraction"] == 0.0


def test_a_skirt_on_the_hips_stays_on_and_passes(tmp_path):
    """The same skirt on a ball as wide as hips (25 cm, centre 15 cm under the skirt's waist)
    hangs on it: every assembled frame has most of the skirt within 10 cm of the body and its
    centroid within 20 cm of where it started; the command exits 0 with an empty verdict."""
    garment = tmp_path / "skirt.json"
    assert cli("import", SKIRT, "--edge", "0.05", "-o", garment).returncode == 0
    body = tmp_path / "hips.obj"
    write_sphere_obj(body, (0.0, 0.75, 0.0), 0.25)
    report = tmp_path / "report.json"
    r = cli("simulate", garment, "--collider", body, "--frames", "40", "--report", report)
    assert r.returncode == 0, (r.stdout[-2000:], r.stderr)
    s = json.loads(report.read_text())["summary"]
    assert s["verdict"] == [] and s["assembled_frames"] > 10, s
    assert s["on_body_fraction"] > 0.25 and s["centroid_shift_m"] < 0.2, s
    assert "warning:" not in r.stdout and "on body" in r.stdout


def test_bad_collider_fails_with_a_message(tmp_path):
    garment = tmp_path / "skirt.json"
    assert cli("import", SKIRT, "--edge", "0.06", "-o", garment).returncode == 0
    r = cli("simulate", garment, "--collider", tmp_path / "missing.obj", "--frames", "2", "--report", tmp_path / "r.json")
    assert r.returncode != 0 and "missing.obj" in r.stderr


SAMPLES = Path(__file__).resolve().parents[1] / "sample_blends"


def test_a_sample_garment_file_simulates_with_its_own_settings(tmp_path):
    """What the garment file records besides pieces and seams is used, as the add-on and the
    samples' checks use it: the T-shirt's painted shoulder pins ride on the character once every
    seam has met; the layered outfit collides with itself (default sphere radius, 5 mm on its 1 cm
    mesh) with its fleece-on-jersey friction; flags
    override the file; values that no longer fit a re-triangulated garment are left out with a
    warning in the report."""
    character = SAMPLES / "character.glb"
    report = tmp_path / "tshirt.json"
    # The garment assembles at the character's rest pose first (the add-on's preroll and
    # transition, not recorded): its seams meet there and the pins ride from the first frame.
    r = cli("simulate", SAMPLES / "tshirt.json", "--collider", character, "--frames", "3", "--report", report)
    assert r.returncode == 0, r.stderr
    rep = json.loads(report.read_text())
    assert rep["attached"] > 0 and rep["pins_attached"] and not rep["warnings"], {k: rep[k] for k in rep if k != "frames"}
    assert rep["thickness_m"] == pytest.approx(0.004) and rep["self_collision"] is False
    # Assembled on the first frame's pose, recorded (no preroll): one frame ends while the seams
    # still close, "open".
    r = cli("simulate", SAMPLES / "layered.json", "--collider", character, "--frames", "1", "--report", report,
            "--thickness", "0.005", "--assemble-at", "start")
    assert r.returncode == 3, r.stderr  # one frame ends while the seams still close: "open"
    rep = json.loads(report.read_text())
    assert rep["self_collision"] and rep["self_collision_radius_m"] == pytest.approx(0.005, rel=0.05)
    assert rep["self_collision_friction"] == [pytest.approx(0.6), pytest.approx(0.4)]
    assert rep["thickness_m"] == pytest.approx(0.005) and "self-collision on" in r.stdout
    r = cli("simulate", SAMPLES / "tshirt.json", "--collider", character, "--frames", "1", "--report", report,
            "--edge", "0.03", "--assemble-at", "start")
    assert r.returncode == 3, r.stderr
    rep = json.loads(report.read_text())
    assert rep["attached"] == 0 and any("painted 'pin'" in w and "left out" in w for w in rep["warnings"]), rep["warnings"]


def test_self_contacts_choose_the_cloth_cloth_model(tmp_path):
    """Issue 23: `--self-contacts triangles` keeps particles off the cloth's triangles (on the
    CPU), recorded in the report and the summary line; a garment file can say it too."""
    garment, args = coarse_skirt_on_a_ball(tmp_path)
    report = tmp_path / "r.json"
    r = cli("simulate", garment, *args, "--report", report, "--self-collision", "--self-contacts", "triangles")
    assert r.returncode in (0, 3), r.stderr
    rep = json.loads(report.read_text())
    assert rep["self_collision"] and rep["self_collision_contacts"] == "triangles"
    assert rep["self_collision_radius_m"] == pytest.approx(tailor.DEFAULT_THICKNESS)
    assert "self-collision on (triangles)" in r.stdout
    g = tailor.Garment.load(garment)
    g.setup = {**g.setup, "self_collision": True, "self_collision_contacts": "triangles"}
    g.save(tmp_path / "tri.json")
    r = cli("simulate", tmp_path / "tri.json", *args, "--report", report)
    assert r.returncode in (0, 3), r.stderr
    assert json.loads(report.read_text())["self_collision_contacts"] == "triangles"
    # --no-self-collision turns off what the file turns on.
    r = cli("simulate", tmp_path / "tri.json", *args, "--report", report, "--no-self-collision")
    assert r.returncode in (0, 3), r.stderr
    assert json.loads(report.read_text())["self_collision"] is False and "self-collision off" in r.stdout
    r = cli("simulate", garment, *args, "--report", report, "--self-contacts", "cubes")
    assert r.returncode == 2 and "spheres" in r.stderr


def test_an_animated_collider_assembles_at_its_rest_pose_first(tmp_path):
    """Issue 24: `tailor simulate` assembles as the add-on's Bake does (its Preroll, Transition
    and Assemble Without Gravity defaults): on an animated collider the garment is sewn at the
    rest pose its patterns were placed for, then the body moves into the clip's first frame, and
    only then are frames recorded. The trousers, placed for the rest pose, have their back
    piece through the calf in the walk's first pose: assembled there (`--assemble-at start`, the
    command's only behaviour before), 9-10 particles stay 29 mm inside the body from frame 1
    and the verdict fails "inside"; assembled at rest, nothing is deeper than 5 mm and it passes.
    (Measured 2026-11-26: 9 particles, 29.0 mm, inside from frame 1, on both backends.)"""
    character = SAMPLES / "character.glb"
    report = tmp_path / "trousers.json"
    r = cli("simulate", SAMPLES / "trousers.json", "--collider", character, "--frames", "3", "--report", report)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr
    rep = json.loads(report.read_text())
    assert rep["assembly"]["at"] == "rest" and rep["assembly"]["gravity"] is False, rep["assembly"]
    assert rep["assembly"]["preroll_frames"] >= 60 and rep["assembly"]["transition_frames"] == 40, rep["assembly"]
    assert "assembly at the rest pose" in r.stdout
    for f in rep["frames"]:
        # Measured: none inside at frame 1, then 1-2 particles 3-4.4 mm deep as the walk starts.
        assert f["penetration_max_m"] < 0.005 and not f["seams_closing"] and f["seam_gap_max_m"] < 1e-3, f
    assert rep["summary"]["verdict"] == []
    # A still collider has one pose: the garment assembles on it, recorded, as before.
    body = tmp_path / "ball.obj"
    write_sphere_obj(body, (0.0, 0.9, 0.0), 0.15, subdivisions=1)
    garment = SAMPLES / "tshirt.json"
    r = cli("simulate", garment, "--collider", body, "--frames", "1", "--report", report)
    assert json.loads(report.read_text())["assembly"] == {"at": "start", "preroll_frames": 0, "transition_frames": 0,
                                                          "gravity": True}
    r = cli("simulate", garment, "--collider", body, "--frames", "1", "--report", report, "--preroll", "-1")
    assert r.returncode == 2 and "--preroll -1" in r.stderr, r.stderr


def test_painted_pins_attach_in_proportion_to_their_weight():
    """A pin painted at weight w rides on the collider at w times the setup's pin stiffness, one
    rule for the add-on and the command line (`Garment.attach_groups`, in the core): weights at
    or above 0.999 are 1, lighter ones rounded to 1/20; unpainted (0) particles are not pinned.
    Fixed in place instead, weight 1 pins hold and lighter ones pull softly."""
    g = tailor.Garment.load(str(SAMPLES / "skirt.json"))
    g.clear_painted("pin")
    n0 = len(g.meshes()[0].rest)
    w = np.zeros(n0, np.float32)
    w[[0, 1]], w[[2, 3, 4]], w[5] = 1.0, 0.5, 0.999
    w[6] = 0.52
    g.set_painted("pin", 0, w)
    assert [(p.tolist(), k) for p, k in g.attach_groups()] == [([0, 1, 5], 100.0), ([2, 3, 4, 6], 50.0)]
    assert [(x, p.tolist()) for x, p in g.pin_weights()] == [(1.0, [0, 1, 5]), (0.5, [2, 3, 4, 6])]
    g.setup = {**g.setup, "pin_stiffness": 40.0}
    assert [k for _, k in g.attach_groups()] == [40.0, 20.0]
    sim, _ = g.build_simulation()
    assert not g.build_warnings and len(sim.collider_attached) == 0  # they wait for the bake loop
    g.setup = {**g.setup, "pin_mode": "fixed"}
    assert g.attach_groups() == []
    fixed, _ = g.build_simulation(settings=tailor.Settings(ramp_enabled=False))
    before = fixed.positions[[0, 1, 5]].copy()
    fixed.step(1 / 30)
    np.testing.assert_array_equal(fixed.positions[[0, 1, 5]], before)
    # Riding pins with nothing to ride on are held in place, and the build says so.
    g.setup = {**g.setup, "pin_mode": "attach"}
    held, _ = g.build_simulation(settings=tailor.Settings(ramp_enabled=False), ride=False)
    assert any("no collider" in x for x in g.build_warnings)
    held.step(1 / 30)
    np.testing.assert_array_equal(held.positions[[0, 1, 5]], before)
    with pytest.raises(tailor.InvalidParameterError, match="pin"):
        g.set_painted("pin", 0, w[:-1])
    with pytest.raises(tailor.InvalidParameterError, match="painted map"):
        g.set_painted("pinn", 0, w)


def pc2_count(path) -> int:
    """The sample count in a PC2 header (0 while the file is not there yet)."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(32)
    except FileNotFoundError:
        return 0
    return int.from_bytes(head[28:32], "little", signed=True) if len(head) == 32 else 0


def test_a_killed_run_keeps_its_frames_and_resume_finishes_it_as_one_run(tmp_path):
    """`-o` is a valid cache after every frame: a run killed mid-way keeps the frames it
    solved (readable as they are), and `--resume` solves them again, checks them, and goes on
    to the same cache and records as an uninterrupted run; a cache of other settings is
    refused by the check, not continued."""
    import signal
    import time

    garment = tmp_path / "skirt.json"
    assert cli("import", SKIRT, "--edge", "0.05", "-o", garment).returncode == 0
    body = tmp_path / "ball.obj"
    write_sphere_obj(body, (0.0, 0.9, 0.0), 0.15)
    cache, report = tmp_path / "killed.pc2", tmp_path / "killed.json"
    args = ["simulate", garment, "--collider", body, "--report", report, "-o", cache]
    proc = subprocess.Popen([sys.executable, "-m", "tailor", *map(str, args), "--frames", "400"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while pc2_count(cache) < 4 and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.002)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    kept = tailor.read_pc2(cache)["frames"]
    assert 4 <= len(kept) < 30, len(kept)  # killed mid-run, every frame it counted readable

    r = cli(*args, "--frames", "30", "--resume")
    assert f"solving the {len(kept)} frames" in r.stdout and "frame   30/30" in r.stdout, r.stderr
    whole, whole_report = tmp_path / "whole.pc2", tmp_path / "whole.json"
    w = cli("simulate", garment, "--collider", body, "--report", whole_report, "-o", whole, "--frames", "30")
    assert r.returncode == w.returncode in (0, 3), (r.stderr, w.stderr)  # the same verdict
    resumed, once = tailor.read_pc2(cache), tailor.read_pc2(whole)
    np.testing.assert_array_equal(resumed["frames"], once["frames"])
    np.testing.assert_array_equal(resumed["frames"][: len(kept)], kept)
    a, b = json.loads(report.read_text()), json.loads(whole_report.read_text())
    assert a["complete"] and b["complete"]
    strip = lambda recs: [{k: v for k, v in rec.items() if k not in ("ms", "stages_ms")} for rec in recs]  # noqa: E731
    assert strip(a["frames"]) == strip(b["frames"])

    # Other settings than the cache was solved with: the first re-solved frame differs.
    r = cli(*args, "--frames", "30", "--resume", "--substeps", "3")
    assert r.returncode == 2 and "differs from a new solve" in r.stderr, r.stderr
    assert "Traceback" not in r.stderr


def test_the_collider_animation_is_chosen_by_name(tmp_path):
    """`--animation` plays the glTF clip it names; a name the file does not have, or a mesh
    that is not glTF, is an error naming what there is."""
    character = Path(__file__).resolve().parents[1] / "sample_blends" / "character.glb"
    garment = tmp_path / "skirt.json"
    assert cli("import", SKIRT, "--edge", "0.08", "-o", garment).returncode == 0
    r = cli("simulate", garment, "--collider", character, "--animation", "jump", "--frames", "1",
            "--report", tmp_path / "r.json")
    assert r.returncode == 2 and "no animation 'jump'" in r.stderr and "'walk'" in r.stderr, r.stderr
    body = tmp_path / "ball.obj"
    write_sphere_obj(body, (0.0, 0.9, 0.0), 0.15, subdivisions=1)
    r = cli("simulate", garment, "--collider", body, "--animation", "walk", "--frames", "1",
            "--report", tmp_path / "r.json")
    assert r.returncode == 2 and "not glTF" in r.stderr, r.stderr
    r = cli("simulate", garment, "--collider", character, "--animation", "walk", "--frames", "2",
            "--report", tmp_path / "walk.json", "--preset", "preview")
    assert r.returncode in (0, 3), r.stderr
    assert len(json.loads((tmp_path / "walk.json").read_text())["frames"]) == 2


def test_threads_are_the_solvers_and_change_no_result(tmp_path):
    """`--threads 1`: the report says so, and the garment's frames are those of the default."""
    garment = tmp_path / "skirt.json"
    assert cli("import", SKIRT, "--edge", "0.08", "-o", garment).returncode == 0
    body = tmp_path / "ball.obj"
    write_sphere_obj(body, (0.0, 0.9, 0.0), 0.15, subdivisions=1)
    runs = {}
    for threads in (None, 1):
        out = tmp_path / f"t{threads}.json"
        args = ["simulate", garment, "--collider", body, "--frames", "3", "--report", out, "--preset", "preview",
                "-o", tmp_path / f"t{threads}.pc2", *(["--threads", str(threads)] if threads else [])]
        r = cli(*args)
        assert r.returncode in (0, 3), r.stderr
        runs[threads] = json.loads(out.read_text())
    assert runs[1]["threads"] == 1 and runs[None]["threads"] >= 1
    frames = {t: tailor.read_pc2(str(tmp_path / f"t{t}.pc2"))["frames"] for t in runs}
    np.testing.assert_array_equal(frames[None], frames[1])
    r = cli("simulate", garment, "--collider", body, "--frames", "1", "--report", tmp_path / "bad.json",
            "--threads", "0")
    assert r.returncode == 2 and "threads" in r.stderr, r.stderr


def test_loop_plays_the_collider_motion_over_again(tmp_path):
    """Past the end of a PC2 cache the body holds its last pose; with `--loop` it starts over:
    the garment then moves again with it (a ball that rises for 3 frames and repeats)."""
    garment = tmp_path / "skirt.json"
    assert cli("import", SKIRT, "--edge", "0.08", "-o", garment).returncode == 0
    body = tmp_path / "ball.obj"
    write_sphere_obj(body, (0.0, 0.9, 0.0), 0.15, subdivisions=1)
    rest, _ = tailor.read_mesh(str(body))
    rest = np.asarray(rest, np.float32)
    anim = tmp_path / "rise.pc2"
    tailor.write_pc2(str(anim), np.stack([rest + [0.0, 0.01 * k, 0.0] for k in range(3)]).astype(np.float32))
    shifts = {}
    for loop in (False, True):
        out = tmp_path / f"loop{loop}.json"
        args = ["simulate", garment, "--collider", body, "--collider-anim", anim, "--frames", "8",
                "--report", out, "--preset", "preview", "-o", tmp_path / f"loop{loop}.pc2"]
        r = cli(*args, *(["--loop"] if loop else []))
        assert r.returncode in (0, 3), r.stderr
        shifts[loop] = [f["centroid_shift_m"] for f in json.loads(out.read_text())["frames"]]
    held, looped = shifts[False], shifts[True]
    assert held[:3] == looped[:3]  # the same frames while the cache lasts (frames 0-2)
    assert held[3] != looped[3] and held[5:] != looped[5:], "--loop changed nothing past the cache's end"


def test_usd_and_obj_outputs_are_the_welded_garment_with_uvs(tmp_path):
    """`--usd`: one welded mesh (no crack along the seams: each seam's two rows of particles are
    one row of points), its points sampled at every frame and equal to the PC2's frames welded,
    the pattern's UVs per face corner, Y up and metres, read back with `pxr`. `--obj-dir`: the
    same mesh as one OBJ a frame, read back to the bit, with a UV per corner."""
    from pxr import Usd, UsdGeom

    garment = tmp_path / "skirt.json"
    assert cli("import", SKIRT, "--edge", "0.05", "-o", garment).returncode == 0
    body = tmp_path / "ball.obj"
    write_sphere_obj(body, (0.0, 0.9, 0.0), 0.15, subdivisions=2)
    usd, cache = tmp_path / "skirt.usdc", tmp_path / "skirt.pc2"
    r = cli("simulate", garment, "--collider", body, "--frames", "12", "--report", tmp_path / "r.json", "-o", cache,
            "--usd", usd, "--preset", "preview", "--obj-dir", tmp_path / "objs")
    assert r.returncode in (0, 3), r.stderr
    stage = Usd.Stage.Open(str(usd))
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y and UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    mesh = UsdGeom.Mesh(stage.GetPrimAtPath("/Garment/skirt"))
    points = mesh.GetPointsAttr()
    assert points.GetTimeSamples() == [float(f) for f in range(1, 13)]
    frames = tailor.read_pc2(cache)["frames"]  # welded, as every output
    g = tailor.Garment.load(garment)
    sim, _ = g.build_simulation()
    w = tailor.weld(sim.positions, sim.triangles, sim.seam_pairs())
    assert w.num_vertices < sim.num_particles  # welded: the seams' two sides are one
    assert frames.shape[1] == w.num_vertices
    for f in (1, 7, 12):
        np.testing.assert_array_equal(np.array(points.Get(f)), frames[f - 1])
    faces = np.array(mesh.GetFaceVertexIndicesAttr().Get())
    assert len(faces) == 3 * len(w.triangles) and faces.max() == w.num_vertices - 1
    st = UsdGeom.PrimvarsAPI(mesh).GetPrimvar("st")
    assert st.GetInterpolation() == UsdGeom.Tokens.faceVarying and len(st.Get()) == len(faces)
    objs = sorted((tmp_path / "objs").glob("skirt.*.obj"))
    assert [o.name for o in objs] == [f"skirt.{f:04d}.obj" for f in range(1, 13)]
    v, t = tailor.read_mesh(objs[6])
    np.testing.assert_array_equal(v, frames[6])
    np.testing.assert_array_equal(t, w.triangles)
    assert sum(line.startswith("vt ") for line in objs[6].read_text().splitlines()) == len(faces)
    r = cli("simulate", garment, "--collider", body, "--frames", "1", "--report", tmp_path / "r2.json",
            "--usd", tmp_path / "skirt.abc")
    assert r.returncode == 2 and ".usda" in r.stderr, r.stderr



def test_usd_carries_normals_and_with_maps_the_fit_maps(tmp_path):
    """`--usd` samples unit vertex normals with the points (facing as the welded triangles
    wind); with `--maps` too, each fit map is a time-sampled per-point primvar
    (`tailor_strain`, `tailor_pressure`, `tailor_distance`), the .npz's particles welded."""
    from pxr import Usd, UsdGeom

    from tailor.usd import vertex_normals

    garment = tmp_path / "skirt.json"
    assert cli("import", SKIRT, "--edge", "0.06", "-o", garment).returncode == 0
    body = tmp_path / "ball.obj"
    write_sphere_obj(body, (0.0, 0.9, 0.0), 0.15, subdivisions=2)
    usd, maps = tmp_path / "skirt.usda", tmp_path / "maps.npz"
    r = cli("simulate", garment, "--collider", body, "--frames", "3", "--report", tmp_path / "r.json",
            "--usd", usd, "--maps", maps, "--preset", "preview")
    assert r.returncode in (0, 3), r.stderr
    stage = Usd.Stage.Open(str(usd))  # kept: a prim is valid while its stage lives
    mesh = UsdGeom.Mesh(stage.GetPrimAtPath("/Garment/skirt"))
    assert mesh.GetNormalsInterpolation() == UsdGeom.Tokens.vertex
    normals, points = mesh.GetNormalsAttr(), mesh.GetPointsAttr()
    assert normals.GetTimeSamples() == [1.0, 2.0, 3.0]
    faces = np.array(mesh.GetFaceVertexIndicesAttr().Get()).reshape(-1, 3)
    n, p = np.array(normals.Get(3)), np.array(points.Get(3))
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-5)
    np.testing.assert_allclose(n, vertex_normals(p, faces), atol=1e-6)
    face = np.cross(p[faces[:, 1]] - p[faces[:, 0]], p[faces[:, 2]] - p[faces[:, 0]])
    assert (np.einsum("ij,ij->i", face, n[faces[:, 0]]) > 0).mean() > 0.95  # they face as the triangles wind
    # The thickness the cloth kept from the body, for a render-time shell (the report's figure).
    thickness = UsdGeom.PrimvarsAPI(mesh).GetPrimvar("tailor_thickness")
    assert thickness.GetInterpolation() == UsdGeom.Tokens.constant
    assert thickness.Get() == pytest.approx(json.loads((tmp_path / "r.json").read_text())["thickness_m"])
    z = np.load(maps)
    g = tailor.Garment.load(garment)
    sim, _ = g.build_simulation()
    w = tailor.weld(sim.positions, sim.triangles, sim.seam_pairs())
    api = UsdGeom.PrimvarsAPI(mesh)
    for key in ("strain", "pressure", "distance"):
        pv = api.GetPrimvar(f"tailor_{key}")
        assert pv.GetInterpolation() == UsdGeom.Tokens.vertex and pv.GetAttr().GetTimeSamples() == [1.0, 2.0, 3.0]
        want = w.apply(np.repeat(z[key][2][:, None], 3, axis=1))[:, 0]
        np.testing.assert_allclose(np.array(pv.Get(3)), want, rtol=1e-6, atol=1e-7)


def test_a_collider_with_another_up_axis_is_turned_into_the_garments(tmp_path):
    """A garment file that states its up axis (`setup["up"]`) and a collider with the other one:
    the collider is turned into the garment's coordinates, gravity follows the garment's axis,
    and the run is the very run of the same body given in the garment's axis (the turn is
    exact: swaps and sign flips)."""
    from tailor.motion import turn_up

    garment = tmp_path / "skirt.json"
    assert cli("import", SKIRT, "--edge", "0.06", "-o", garment).returncode == 0
    body = tmp_path / "ball.obj"
    write_sphere_obj(body, (0.0, 0.9, 0.0), 0.15, subdivisions=2)
    r = cli("simulate", garment, "--collider", body, "--frames", "6", "--report", tmp_path / "a.json",
            "-o", tmp_path / "a.pc2", "--preset", "preview")
    assert r.returncode in (0, 3), r.stderr
    # The same garment saying it is Y up, on the ball written Z up.
    g = tailor.Garment.load(garment)
    g.setup = {**g.setup, "up": "y"}
    stated = tmp_path / "stated.json"
    g.save(stated)
    v, t = tailor.read_mesh(body)
    z_up = tmp_path / "ball_z.obj"
    with open(z_up, "w") as fh:
        fh.writelines(f"v {p[0]!r} {p[1]!r} {p[2]!r}\n" for p in turn_up(v, "y", "z").tolist())
        fh.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in t.tolist())
    r = cli("simulate", stated, "--collider", z_up, "--up", "z", "--frames", "6", "--report", tmp_path / "b.json",
            "-o", tmp_path / "b.pc2", "--preset", "preview")
    assert r.returncode in (0, 3), r.stderr
    assert "the collider is Z up and the garment Y up" in r.stdout
    rep = json.loads((tmp_path / "b.json").read_text())
    assert (rep["up"], rep["collider_up"]) == ("y", "z")
    np.testing.assert_array_equal(tailor.read_pc2(tmp_path / "b.pc2")["frames"],
                                  tailor.read_pc2(tmp_path / "a.pc2")["frames"])
    np.testing.assert_array_equal(turn_up(turn_up(v, "y", "z"), "z", "y"), v)
    with pytest.raises(tailor.InvalidParameterError, match="'x'"):
        turn_up(v, "y", "x")


def test_maps_writes_every_frames_strain_distance_and_pressure(tmp_path):
    """`--maps` writes the fit maps of every recorded frame (Simulation.fit_maps) and a summary
    of them in each frame's record; the skirt hangs on a ball, so its particles touching the
    ball are pressed and the rest are not; a wrong suffix or --resume is refused first."""
    garment = tmp_path / "skirt.json"
    assert cli("import", SKIRT, "--edge", "0.05", "-o", garment).returncode == 0
    body = tmp_path / "ball.obj"
    write_sphere_obj(body, (0.0, 0.9, 0.0), 0.15)
    report, maps = tmp_path / "r.json", tmp_path / "maps.npz"
    r = cli("simulate", garment, "--collider", body, "--frames", "3", "--report", report, "--maps", maps,
            "-o", tmp_path / "c.pc2")
    assert r.returncode in (0, FAILED_CHECKS), r.stderr  # the skirt on a ball may fail a check; no error
    z = np.load(maps)
    frames = json.load(open(report))["frames"]
    n = tailor.Garment.load(garment).build_simulation()[0].num_particles  # the maps are per particle
    assert {k: z[k].shape for k in z} == {k: (3, n) for k in ("strain", "distance", "pressure")}
    assert all(np.isfinite(z[k]).all() for k in z)
    last = frames[-1]["fit"]
    assert last["strain_max"] == pytest.approx(float(z["strain"][-1].max()))
    touching = z["distance"][-1] < 0.006
    assert touching.any() and (z["pressure"][-1][~touching] == 0).all() and (z["pressure"][-1][touching] > 0).any()
    bad = cli("simulate", garment, "--collider", body, "--frames", "1", "--report", report, "--maps", tmp_path / "m.npy")
    assert bad.returncode != 0 and "--maps" in bad.stderr and ".npz" in bad.stderr and "Traceback" not in bad.stderr
    bad = cli("simulate", garment, "--collider", body, "--frames", "1", "--report", report, "--maps", maps,
              "-o", tmp_path / "c2.pc2", "--resume")
    assert bad.returncode != 0 and "--resume" in bad.stderr and "Traceback" not in bad.stderr


def test_two_level_runs_the_skirt_on_the_hips_and_the_report_says_so(tmp_path):
    """`--two-level` (the two-level global step, `Settings.two_level`) drapes the skirt on the
    hips as the plain step does (it passes its checks) and the report records the setting; a
    run without it records False."""
    garment = tmp_path / "skirt.json"
    assert cli("import", SKIRT, "--edge", "0.05", "-o", garment).returncode == 0
    body = tmp_path / "hips.obj"
    write_sphere_obj(body, (0.0, 0.75, 0.0), 0.25)
    for flag, expect in ((["--two-level"], True), ([], False)):
        report = tmp_path / f"report-{expect}.json"
        r = cli("simulate", garment, "--collider", body, "--frames", "30", "--report", report, *flag)
        assert r.returncode == 0, (r.stdout[-2000:], r.stderr)
        doc = json.loads(report.read_text())
        assert doc["two_level"] is expect and doc["summary"]["verdict"] == [], doc["summary"]
    assert tailor.Settings(two_level=True).two_level and not tailor.Settings().two_level
    assert not tailor.Settings.preset("final").two_level  # opt-in: it costs 1.2-1.5x the frame (docs/accuracy.md)


def test_set_thickness_marks_every_mesh_of_a_usd_file_another_exporter_wrote(tmp_path):
    """`tailor.usd.set_thickness` (the add-on's USD export through Blender's exporter): the
    constant primvar `tailor_thickness` on every mesh, saved; a file USD cannot open and a
    negative thickness are errors that say what."""
    from pxr import Usd, UsdGeom

    from tailor.usd import set_thickness

    path = tmp_path / "two.usda"
    stage = Usd.Stage.CreateNew(str(path))
    for name in ("a", "b"):
        UsdGeom.Mesh.Define(stage, f"/Root/{name}")
    UsdGeom.Xform.Define(stage, "/Root/empty")
    stage.GetRootLayer().Save()
    assert set_thickness(path, 0.004) == 2
    back = Usd.Stage.Open(str(path))
    for name in ("a", "b"):
        pv = UsdGeom.PrimvarsAPI(back.GetPrimAtPath(f"/Root/{name}")).GetPrimvar("tailor_thickness")
        assert pv.GetInterpolation() == UsdGeom.Tokens.constant and pv.Get() == pytest.approx(0.004)
    junk = tmp_path / "junk.usda"
    junk.write_text("not usd at all")
    with pytest.raises(Exception, match="junk.usda"):
        set_thickness(junk, 0.004)
    with pytest.raises(ValueError, match="thickness"):
        set_thickness(path, -1.0)


def test_fabric_makes_every_piece_a_library_fabric(tmp_path):
    """`--fabric NAME`: every piece that fabric of the library (the cloth moves otherwise than
    with the file's own), the report says which; an unknown name is one line naming the
    library's fabrics, exit 2, before any work."""
    garment, common = coarse_skirt_on_a_ball(tmp_path)
    r = cli("simulate", garment, *common, "--report", tmp_path / "own.json", "-o", tmp_path / "own.pc2")
    assert r.returncode in (0, 3), r.stderr
    r = cli("simulate", garment, *common, "--report", tmp_path / "denim.json", "-o", tmp_path / "denim.pc2",
            "--fabric", "11oz-black-denim")
    assert r.returncode in (0, 3), r.stderr
    assert json.loads((tmp_path / "denim.json").read_text())["fabric"] == "11oz-black-denim"
    assert json.loads((tmp_path / "own.json").read_text())["fabric"] is None
    own, denim = (tailor.read_pc2(tmp_path / f"{n}.pc2")["frames"] for n in ("own", "denim"))
    assert np.abs(own[-1] - denim[-1]).max() > 1e-4
    bad = cli("simulate", garment, *common, "--report", tmp_path / "bad.json", "--fabric", "velvet")
    assert bad.returncode == 2 and "velvet" in bad.stderr and "11oz-black-denim" in bad.stderr, bad.stderr
    assert "Traceback" not in bad.stderr and len(bad.stderr.strip().splitlines()) == 1
