"""`python -m tailor import` and `info`: pattern file -> garment file -> JSON description."""

import json
import subprocess
import sys
from pathlib import Path

import pytest


ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "native/tailor-core/tests/data"


def run(*args):
    return subprocess.run([sys.executable, "-m", "tailor", *map(str, args)], capture_output=True, text=True)


def import_and_describe(pattern, out, *extra):
    r = run("import", pattern, *extra, "-o", out)
    assert r.returncode == 0, r.stderr
    assert Path(out).exists() and Path(out).with_suffix(".bin").exists()
    r = run("info", out, "--json")
    assert r.returncode == 0, r.stderr
    info = json.loads(r.stdout)
    assert info["pieces"], info
    for p in info["pieces"]:
        assert set(p) >= {"name", "vertices", "triangles", "outline_length_m", "min_angle_deg"}
        assert p["vertices"] > 3 and p["triangles"] > 0 and p["outline_length_m"] > 0
        assert p["min_angle_deg"] > 20
    for s in info["seams"]:
        assert set(s) >= {"a", "b", "pairs", "mode"} and s["mode"] in ("equal", "unequal")
        assert s["pairs"] >= 2
    return info


def test_garmentcode_import_info_round_trip(tmp_path):
    info = import_and_describe(DATA / "garmentcode/flare_skirt_specification.json", tmp_path / "skirt.json",
                               "--edge", "0.03")
    names = {p["name"] for p in info["pieces"]}
    assert len(info["seams"]) > 0 and all(s["a"] in names and s["b"] in names for s in info["seams"])
    text = run("info", tmp_path / "skirt.json")
    assert text.returncode == 0 and "seams" in text.stdout


def test_svg_import_info_round_trip(tmp_path):
    info = import_and_describe(DATA / "svg/skirt_two_panels.svg", tmp_path / "svg.json", "--edge", "0.02")
    assert len(info["pieces"]) == 2 and info["seams"] == []


def test_dxf_import_info_round_trip(tmp_path):
    # The repository's own graded AAMA nest (sizes S, M, L; `dxf/README.md`): the third-party
    # Gerber exports in ../shared may not be copied here, and the test must run without them.
    dxf = DATA / "dxf/synthetic_aama.dxf"
    sizes = run("info", dxf, "--sizes", "--json")
    assert sizes.returncode == 0, sizes.stderr
    listed = json.loads(sizes.stdout)["sizes"]
    extra = ["--size", listed[0]] if listed else []
    assert listed == ["S", "M", "L"], listed
    info = import_and_describe(dxf, tmp_path / "nest.json", "--edge", "0.03", *extra)
    assert len(info["pieces"]) >= 2


def test_a_piece_cut_on_the_fold_imports_whole_unless_no_unfold(tmp_path):
    # `dxf/synthetic_fold.dxf`: a half drawn with a mirror line along its fold.
    dxf = DATA / "dxf/synthetic_fold.dxf"
    whole = import_and_describe(dxf, tmp_path / "whole.json", "--edge", "0.03")["pieces"][0]
    drawn = import_and_describe(dxf, tmp_path / "drawn.json", "--edge", "0.03", "--no-unfold")["pieces"][0]
    assert whole["vertices"] > drawn["vertices"]
    assert whole["outline_length_m"] > drawn["outline_length_m"] + 0.2


def test_pieces_are_cut_as_their_quantities_say_unless_no_quantities(tmp_path):
    # `dxf/synthetic_cut.dxf`: SLEEVE cut twice, PANEL once, ALT 0 times.
    dxf = DATA / "dxf/synthetic_cut.dxf"
    cut = import_and_describe(dxf, tmp_path / "cut.json", "--edge", "0.03")["pieces"]
    drawn = import_and_describe(dxf, tmp_path / "drawn.json", "--edge", "0.03", "--no-quantities")["pieces"]
    assert [p["name"] for p in cut] == ["SLEEVE R", "SLEEVE L", "PANEL"]
    assert [p["name"] for p in drawn] == ["SLEEVE", "PANEL", "ALT"]
    assert cut[0]["outline_length_m"] == pytest.approx(cut[1]["outline_length_m"], rel=1e-6)


def test_bad_files_fail_with_the_file_named(tmp_path):
    missing = tmp_path / "missing.dxf"
    r = run("import", missing, "-o", tmp_path / "x.json")
    assert r.returncode != 0 and "missing.dxf" in r.stderr and "Traceback" not in r.stderr
    junk = tmp_path / "junk.json"
    junk.write_text("{ not json")
    r = run("import", junk, "-o", tmp_path / "y.json")
    assert r.returncode != 0 and "junk.json" in r.stderr and "Traceback" not in r.stderr
    r = run("info", junk, "--json")
    assert r.returncode != 0 and "junk.json" in r.stderr and "Traceback" not in r.stderr
    r = run("info", tmp_path / "nothing.json")
    assert r.returncode != 0 and "nothing.json" in r.stderr
    r = run("import", DATA / "svg/skirt_two_panels.svg", "--edge", "-1", "-o", tmp_path / "z.json")
    assert r.returncode != 0 and "edge" in r.stderr


def test_a_pattern_is_arranged_round_a_body_on_import(tmp_path):
    """`--arrange BODY`: each piece where `tailor.arrange.arrange_garment` puts it (the file's
    placements dropped), the plan printed a line a piece; a body that cannot be read, or a
    negative clearance, is one line and exit 2, and nothing is written."""
    import numpy as np

    import tailor
    from tailor.arrange import arrange_garment

    spec, body = DATA / "garmentcode/flare_skirt_specification.json", ROOT / "sample_blends/sources/mean_all.obj"
    out = tmp_path / "arranged.json"
    r = run("import", spec, "--edge", "0.03", "--arrange", body, "-o", out)
    assert r.returncode == 0, r.stderr
    garment = tailor.Garment.load(str(out))
    names = [p.name for p in garment.pieces]
    for name in names:
        assert f"  {name}: waist, " in r.stdout, r.stdout
    assert f"arranged round {body}" in r.stdout
    assert all(p is None for p in garment.placements)
    want, _ = arrange_garment(tailor.Garment.from_pattern(str(spec), edge=0.03), *tailor.read_mesh(str(body)), up="y")
    got = garment.build_simulation()[0].positions
    assert np.allclose(got, want.build_simulation()[0].positions, atol=1e-6)
    own = tailor.Garment.from_pattern(str(spec), edge=0.03).build_simulation()[0].positions
    assert np.abs(got - own).max() > 0.01  # not the file's own placement
    for bad, says in ((("--arrange", tmp_path / "none.obj"), "none.obj"),
                      (("--arrange", body, "--clearance", "-1"), "--clearance")):
        dest = tmp_path / "bad.json"
        r = run("import", spec, "--edge", "0.03", *bad, "-o", dest)
        assert r.returncode == 2 and says in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr
        assert not dest.exists() and "Traceback" not in r.stderr
