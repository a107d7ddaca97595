"""The fuzz harness (tests/fuzz/fuzz.py): a short seeded run finds no crash, hang (over 10 s of
CPU time a case, or 60 s without progress), panic or exception other than TailorError; every case it ever kept replays cleanly; and
the harness itself notices a worker that dies, spins, blocks or raises. `make fuzz` runs it longer."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent / "fuzz"))
import fuzz  # noqa: E402

#: The short run of `make test`: a fixed seed, so a failure here is reproducible exactly.
SHORT_SEED, SHORT_CASES = 19, 3000


def test_a_short_seeded_run_finds_nothing(tmp_path):
    result = fuzz.fuzz(SHORT_SEED, SHORT_CASES, out_dir=tmp_path, log=lambda *_: None)
    print(f"fuzz: {result['cases']} cases in {result['seconds']} s: {result['outcomes']}")
    assert result["failures"] == [], json.dumps(result["failures"], indent=1)
    # The run reached past the parsers: some cases of every target read without an error.
    ok = {k.split()[0] for k, n in result["outcomes"].items() if k.endswith(" ok") and n > 0}
    assert ok == {"pattern", "garment", "mesh", "animated", "pc2", "api"}, result["outcomes"]


SAVED = sorted(p for p in fuzz.CRASHES.iterdir() if (p / "case.json").is_file())


@pytest.mark.parametrize("case", SAVED, ids=[p.name for p in SAVED])
def test_every_kept_case_replays_without_crash_hang_or_foreign_exception(case):
    r = subprocess.run([sys.executable, fuzz.__file__, "--replay", str(case)], capture_output=True, text=True,
                       timeout=fuzz.HANG_S + 20)
    assert r.returncode == 0, (r.returncode, r.stdout, r.stderr[-2000:])
    assert json.loads(r.stdout)["outcome"] in ("ok", "error")


def test_the_harness_catches_a_crash_a_hang_and_a_foreign_exception(tmp_path, monkeypatch):
    monkeypatch.setenv("TAILOR_FUZZ_SELFTEST", "0")
    result = fuzz.fuzz(1, 9, hang_s=2.0, out_dir=tmp_path, log=lambda *_: None, blocked_s=4.0)
    kinds = {f["case"]: f["kind"] for f in result["failures"]}
    assert kinds == {3: f"crash{-6}", 5: "hang", 6: "hang", 7: "exception"}, result["failures"]
    assert len([p for p in tmp_path.iterdir() if (p / "case.json").is_file()]) == 4
    assert os.environ["TAILOR_FUZZ_SELFTEST"] == "0"
