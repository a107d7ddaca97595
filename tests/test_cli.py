"""The command line: `python -m tailor ...` as pipeline scripts call it."""

import json
import subprocess
import sys


def run(*args, **kw):
    return subprocess.run([sys.executable, "-m", "tailor", *args], capture_output=True, text=True, **kw)


def test_demo_runs_and_reports(tmp_path):
    r = run("demo", "--scene", "sleeve", "--frames", "30", "--out", str(tmp_path))
    assert r.returncode == 0, r.stderr
    assert "ns per particle-iteration" in r.stdout and "seam gap" in r.stdout
    report = json.loads((tmp_path / "report.json").read_text())
    s = report["summary"]
    assert s["frames"] == 30 and not s["nan"]
    assert s["seam_gap_max_m"] < 2e-3 and s["penetration_count"] == 0
    assert len(report["frames"]) == 30
    assert (tmp_path / "sleeve.obj").read_text().count("\nf ") == s["triangles"]


def test_unknown_command_fails_cleanly():
    r = run("frobnicate")
    assert r.returncode != 0 and "invalid choice" in r.stderr
