"""Shared fixtures: the built `tailor` module and small scenes."""

import numpy as np
import pytest

import tailor

# The add-on's tests run in a process of their own (`make test-addon`): they install the built
# extension zip and must import its bundled `tailor`, not this development build.
collect_ignore = ["addon"]


@pytest.fixture
def square():
    """A 20 cm square of 4 x 4 cells: positions (z = 0), triangles, rest."""
    n = 4
    xs = np.linspace(0.0, 0.2, n + 1, dtype=np.float32)
    rest = np.array([[x, y] for y in xs for x in xs], dtype=np.float32)
    tris = []
    for j in range(n):
        for i in range(n):
            a, b, c, d = j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i
            tris += [[a, b, c], [a, c, d]]
    pos = np.concatenate([rest, np.zeros((len(rest), 1), np.float32)], axis=1)
    return pos, np.array(tris, dtype=np.int64), rest


@pytest.fixture
def tube():
    return tailor.sewn_tube(width=0.3, height=0.3, edge=0.03, gap=0.08, bottom=0.0)
