"""normal_flow.propagate_each: the rows of a batch are the flows of propagate, bit for bit,
whatever the other rows and the thread count (forced_response runs its finite-difference
flow and its branch points through it: docs/design.md, determinism)."""

from __future__ import annotations

import math

import numba
import numpy as np

import microslip as ms
from microslip.analysis.normal_flow import (
    S_SIZE,
    STATE_ONLY,
    VARIATIONAL,
    propagate,
    propagate_each,
)

P = ms.Parameters()
MODEL = ms.Model(P, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(12.0, 1400.0))
FREQUENCIES = np.array([900.0, 1400.0, 1400.0 * (1 + 1e-7), 2100.0])  # with loss of contact
N_STEPS = 160
ROW_STEPS = np.array([160, 96, 200, 130])  # each row its own count (forced_response)


def batch(rows: np.ndarray, record: bool, variational=VARIATIONAL):
    cs = np.array([MODEL.replace(**{"excitation.frequency": f}).pack(0.0) for f in FREQUENCIES])
    starts = np.array([[P.static_deflection * (1 + 0.3 * k), 0.01 * k] for k in range(4)])
    periods = 1.0 / FREQUENCIES
    n = rows.size
    ends, phis, summaries = np.empty((n, 2)), np.empty((n, 2, 2)), np.empty((n, S_SIZE))
    propagate_each(
        cs[rows],
        starts[rows],
        periods[rows],
        ROW_STEPS[rows],
        record,
        ends,
        phis,
        summaries,
        variational,
    )
    return (cs, starts, periods), (ends, phis, summaries)


def test_rows_equal_propagate_alone_in_any_company_and_thread_count():
    (cs, starts, periods), (ends, phis, summaries) = batch(np.arange(4), True)
    assert summaries[:, 4].max() == 1.0  # a row loses contact: switches are exercised
    for i in range(4):
        end, phi, _n, _a, summary = propagate(
            cs[i], starts[i, 0], starts[i, 1], 0.0, periods[i], ROW_STEPS[i], True, True
        )
        np.testing.assert_array_equal(ends[i], end)
        np.testing.assert_array_equal(phis[i], phi)
        np.testing.assert_array_equal(summaries[i], summary)
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        _, (ends_1, phis_1, _s) = batch(np.array([2, 0]), True)
    finally:
        numba.set_num_threads(threads)
    np.testing.assert_array_equal(ends_1, ends[[2, 0]])
    np.testing.assert_array_equal(phis_1, phis[[2, 0]])
    assert all(math.isfinite(v) for v in ends.ravel())


def test_state_only_flow_has_the_bits_of_the_variational_one():
    """A transient skips the variational equation: its state, recorded nodes and
    summary must be those of the full flow bit for bit (the four Φ components must not
    leak into y, ẏ, nor the re-steps that locate switches depend on them), and Φ is NaN
    rather than a stale identity."""
    cs = np.array([MODEL.replace(**{"excitation.frequency": f}).pack(0.0) for f in FREQUENCIES])
    for i in range(4):
        start = (P.static_deflection * (1 + 0.3 * i), 0.01 * i)
        full = propagate(cs[i], *start, 0.0, 3.0 / FREQUENCIES[i], 3 * N_STEPS, True, True)
        alone = propagate(cs[i], *start, 0.0, 3.0 / FREQUENCIES[i], 3 * N_STEPS, True, False)
        for k in (0, 2, 3, 4):  # state, nodes, accelerations, summary
            np.testing.assert_array_equal(alone[k], full[k])
        assert np.isnan(alone[1]).all()
        assert np.isfinite(full[1]).all()


def test_state_only_rows_skip_the_monodromy_with_the_same_states():
    """The transients of forced orbits (periodic.transient_states) run without Φ."""
    (cs, starts, periods), (ends, phis, _s) = batch(np.arange(4), False, STATE_ONLY)
    assert np.isnan(phis).all()
    for i in range(4):
        end = propagate(
            cs[i], starts[i, 0], starts[i, 1], 0.0, periods[i], ROW_STEPS[i], False, True
        )[0]
        np.testing.assert_array_equal(ends[i], end)
