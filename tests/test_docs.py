"""Code in the documentation runs as written."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def python_blocks(path):
    return re.findall(r"```python\n(.*?)```", path.read_text(), re.S)


def test_readme_python_example_runs():
    blocks = python_blocks(ROOT / "README.md")
    assert blocks, "README has no python example"
    for code in blocks:
        namespace = {}
        exec(compile(code, "README.md", "exec"), namespace)
        assert namespace["stats"]["seam_gap_max"] < 1e-3
        assert namespace["positions"].shape[1] == 3
