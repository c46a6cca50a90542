"""The repeated tape of a periodic normal motion (integrators/periodic_tape.py) against
the closed form of the undamped free vibration on a linear contact (m2 = 1: harmonic in
contact, free fall in flight; linear_contact_reference.py, no microslip code).

One period is integrated (RK4, contact switches located) and repeated, shifted by the
period T(A) of ``free_period``; the last, partial period is integrated on its own. So the
tape's error must not grow from period to period. A wrong shift or period shows up as a
phase error that grows over the 74 periods (the step-by-step tape's own phase error
grows that way: 1.9e-6 m g in the last period against 2.0e-8 in the first, at
A = 0.5 y0; a period 1e-9 too long gives 2.5e-7 and 6.2e-7 m g in the last period of
the two cases here), a wrong tail as pieces that do not add up to the run.
"""

from __future__ import annotations

import linear_contact_reference
import numpy as np
import pytest

import microslip as ms
from microslip.integrators import normal_tape as nt
from microslip.integrators import periodic_tape as pt

P = ms.Parameters(m2=1.0)
Y0 = P.static_deflection
T0 = P.natural_period
WEIGHT = P.mass * P.g


def _served_errors(amplitude, t_end, dt):
    """(largest |P - N| [N] in the first period, in the last one, total piece length [s],
    period rows) over the repeated tape."""
    force, period, _ = linear_contact_reference.normal_force(P, amplitude)
    c = nt.normal_coefficients(ms.Model(P).pack(0.0))
    start = Y0 - amplitude
    cycle, shape = pt.cycle_rows(c, start, 0.0, ms.free_period(P, amplitude), t_end, dt)
    carry, tape, _work = nt.tape_buffers(start, 0.0)
    tau = np.linspace(0.0, 1.0, 9)
    first = last = covered = 0.0
    while True:
        rows, status = pt.repeat_rows(carry, tape, cycle, shape)
        assert status in (0, 1)
        for r in range(rows):
            t = tape[r, nt.T0] + tau * tape[r, nt.H]
            error = float(np.max(np.abs(np.polyval(tape[r, nt.A0 : nt.A4 + 1][::-1], tau)
                                        - force(t))))  # fmt: skip
            covered += tape[r, nt.H]
            if tape[r, nt.T0] < period:
                first = max(first, error)
            if tape[r, nt.T0] >= t_end - period:
                last = max(last, error)
        if status == 0:
            return first, last, covered, shape[0]


@pytest.mark.parametrize("fraction", [0.5, 1.3])  # in contact throughout; loss of contact
def test_repeated_tape_keeps_its_error_over_74_periods(fraction):
    t_end = 74.3 * T0
    first, last, covered, period_rows = _served_errors(fraction * Y0, t_end, T0 / 200)
    assert period_rows > 0  # the cycle was used
    # measured: 2.0e-8 and 4.2e-8 m g in the first period and the same in the last
    assert first <= 1e-7 * WEIGHT, first / WEIGHT  # the RK4 error of one period
    assert last <= 1.1 * first, (first / WEIGHT, last / WEIGHT)
    assert abs(covered - t_end) <= 1e-12 * t_end


def test_no_cycle_for_short_runs_or_without_a_period():
    """Below two periods, or with period 0, the tape is filled step by step."""
    c = nt.normal_coefficients(ms.Model(P).pack(0.0))
    period = ms.free_period(P, 0.5 * Y0)
    for t_end, given in ((1.5 * period, period), (10 * period, 0.0)):
        _rows, shape = pt.cycle_rows(c, 0.5 * Y0, 0.0, given, t_end, T0 / 200)
        assert shape[0] == 0


def test_periods_are_checked():
    with pytest.raises(ValueError, match="periods must be 2 finite values >= 0 s"):
        pt.cycle_periods([1e-6, -1.0], 2)
    assert np.array_equal(pt.cycle_periods(None, 3), np.zeros(3))
