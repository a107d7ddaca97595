"""Every Python entry point of the native module runs inside `errors::guard` (tailor-py), so a
panic reaches Python as `tailor.InternalError`, never as pyo3's `PanicException`. A new
`#[pyfunction]` or `#[pymethods]` method without it fails here, naming it."""

import re
from pathlib import Path

SRC = Path(__file__).resolve().parent.parent / "native/tailor-py/src"


def entry_points(text: str):
    """(name, body) of every #[pyfunction] and every fn inside a #[pymethods] impl block."""
    out = []
    for m in re.finditer(r"^\s*(#\[pyfunction\]|#\[pymethods\])", text, re.M):
        if m.group(1) == "#[pyfunction]":
            f = re.compile(r"\bfn (\w+)").search(text, m.end())
            out.append((f.group(1), body_after(text, f.end())))
        else:
            start = text.index("{", m.end())
            end = match(text, start)
            for f in re.finditer(r"\n    (?:pub )?fn (\w+)", text[start:end]):
                out.append((f.group(1), body_after(text, start + f.end())))
    return out


def match(text: str, i: int) -> int:
    depth = 0
    for j in range(i, len(text)):
        depth += {"{": 1, "}": -1}.get(text[j], 0)
        if depth == 0:
            return j
    raise ValueError("unbalanced")


def body_after(text: str, i: int) -> str:
    """The first lines of the function body after the signature starting before `i`."""
    par = 0
    for j in range(i, len(text)):
        par += {"(": 1, ")": -1}.get(text[j], 0)
        if text[j] == "{" and par == 0:
            return text[j + 1 : j + 200]
    return ""


def test_every_entry_point_is_guarded():
    names, unguarded = [], []
    for path in sorted(SRC.glob("*.rs")):
        for name, body in entry_points(path.read_text()):
            names.append(name)
            if not re.match(r"\s*(crate::errors::)?guard\(", body):
                unguarded.append(f"{path.name}: {name}")
    assert len(names) > 150, names  # the scan found the module's functions
    assert unguarded == [], unguarded
