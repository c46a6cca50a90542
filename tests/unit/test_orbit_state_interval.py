"""The interval lookup of the orbit tables' interpolation (analysis/periodic.py,
``_interval``): a proportional guess and a short walk in place of a binary search.

It must pick exactly the interval numpy's searchsorted(side="right") - 1 picks (clipped
to [0, n - 2]) on every table: near-uniform ones (where the walk finds it), ones with
zero-length intervals (a switch on a grid point), strongly graded ones (where the walk
gives up and the binary search takes over), and at the nodes themselves and outside the
table. An off-by-one would still interpolate smoothly (on the neighbouring interval) and
pass a loose accuracy test; this one compares the index itself."""

import numpy as np
import pytest

from microslip.analysis.orbit_table import _interval, orbit_state


def _expected(t, nodes):
    return int(np.clip(np.searchsorted(nodes, t, side="right") - 1, 0, nodes.size - 2))


def _tables():
    rng = np.random.default_rng(7)
    uniform = np.linspace(0.0, 1e-3, 1001)
    jittered = np.sort(uniform + rng.uniform(-3e-7, 3e-7, uniform.size))
    inserted = np.sort(np.r_[uniform, uniform[10] + 1e-9, 3.3e-4, 3.3e-4])  # a repeat
    graded = np.r_[0.0, 1e-3 * np.cumsum(0.5 ** np.arange(40, 0, -1)), 1e-3 * (1 + np.arange(50))]
    gap = np.r_[np.linspace(0.0, 1e-4, 20), np.linspace(9e-4, 1e-3, 400)]  # a long flight
    return {"uniform": uniform, "jittered": jittered, "inserted": inserted,
            "graded": graded, "gap": gap}  # fmt: skip


@pytest.mark.parametrize("name", list(_tables()))
def test_the_interval_is_searchsorteds(name):
    nodes = _tables()[name]
    rng = np.random.default_rng(11)
    span = nodes[-1] - nodes[0]
    samples = np.r_[
        rng.uniform(nodes[0], nodes[-1], 4000),
        nodes,  # on the nodes: the interval starting there (side="right")
        np.nextafter(nodes, -np.inf),
        nodes[0] - 0.1 * span, nodes[-1] + 0.1 * span, nodes[-1],
    ]  # fmt: skip
    for t in samples:
        assert _interval(t, nodes) == _expected(t, nodes), t


def test_the_interpolation_reads_the_table_on_its_interval():
    """orbit_state of y = sin(w t) [m] tabulated with y, ẏ, ÿ every h = 5 µs: the quintic
    Hermite is within 2e-14 of it here; the neighbouring interval's polynomial, read one
    interval past its end, is off by ~1e-11 and fails."""
    w, h = 2.0 * np.pi * 1000.0, 5e-6
    nodes = np.arange(0.0, 1e-3 + h / 2, h)
    y, yd, ydd = np.sin(w * nodes), w * np.cos(w * nodes), -w * w * np.sin(w * nodes)
    for t in np.random.default_rng(3).uniform(0.0, 1e-3, 500):
        value, slope = orbit_state(t, nodes, y, yd, ydd[:-1].copy(), ydd[1:].copy())
        assert abs(value - np.sin(w * t)) < 2e-13
        assert abs(slope - w * np.cos(w * t)) < 2e-11 * w
