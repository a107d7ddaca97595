"""The command line: `python -m tailor ...` as pipeline scripts call it."""

import subprocess
import sys


def run(*args, **kw):
    return subprocess.run([sys.executable, "-m", "tailor", *args], capture_output=True, text=True, **kw)


def test_unknown_command_fails_cleanly():
    r = run("frobnicate")
    assert r.returncode != 0 and "invalid choice" in r.stderr
