"""A lane below μ m g parks within PARKED_LANE_PERIODS + μ m g/(μ m g - |F|) periods.

The work estimate of a free vibration's time sweep (sweeps/kernel_choice.py,
``parking_fractions``) counts on it: over a period the mean normal force is m g, so a
lane that slides through a whole period loses (μ m g - |F|) T/m of speed, and it cannot
have gained more than μ g T; once it stops in every period it starts each one as it
started the last and parks (docs/theory/numerics.md, "Repeating lanes"). Here the
shared-normal kernel's own functions run period by period on the repeated tape and
the period at which each lane parks is counted. The bound is loose: measured, every
lane below parks within 3 periods, even at μ m g (1 - 1e-8), at A from 1.3e-10 m to
1.5 y0. A lane at μ m g to the last bit may slide through every period (at A =
1.289e-10 m, F = 0.981 N: its speed at each period start moves in the last bits), so
the estimate counts one within NEAR_LIMIT of μ m g as never parking.
"""

import numpy as np
import pytest

import microslip as ms
from microslip.integrators import lane_parking as parking
from microslip.integrators import periodic_tape
from microslip.integrators import shared_lanes as sl
from microslip.integrators.kernel import as_tuple
from microslip.integrators.normal_tape import normal_coefficients
from microslip.model.normal import normal_force
from microslip.simulation import initial_state_from_amplitude
from microslip.sweeps import cost

P = ms.Parameters()
LIMIT = P.mu * P.mass * P.g  # μ m g [N]


def periods_to_park(amplitude, forces, most):
    """The period (from 1) at which each lane parks on the repeated tape of the free
    vibration of amplitude A [m], or most + 1 if it is still live after ``most``."""
    c = normal_coefficients(ms.Model(P).pack(0.0))
    y0, v0 = initial_state_from_amplitude(P, amplitude)[:2]
    period = ms.free_period(P, amplitude)
    rows, shape = periodic_tape.cycle_rows(c, y0, v0, period, 3 * period, P.natural_period / 200)
    n = forces.size
    mu = np.full(n, P.mu)
    lanes, order, _ = sl.pack_lanes(c[None], np.zeros(n, dtype=np.int64), forces, mu, mu)
    sl.start_modes(lanes, 0, n, normal_force(0.0, y0, v0, as_tuple(c)))
    switches, flagged = np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64)
    book, n_live, n_active = parking.new_book(n), n, sl.active_end(lanes, n)
    for k in range(most):
        parking.mark_period_start(lanes, switches, flagged, book, n_live, sl.X, sl.V, sl.MODE)
        status, n_active = sl.lanes_over_rows(
            rows, np.int64(0), shape[0], lanes, n_live, n_active, switches, flagged
        )
        assert status == sl.OK
        n_live = parking.park(lanes, switches, flagged, book, n_live, k + 1, sl.X, sl.V, sl.MODE)
        n_active = sl.active_end(lanes, min(n_active, n_live))
        if n_live == 0:
            break
    parked_at = np.full(n, most + 1.0)
    for i in range(n_live, n):  # the parked lanes, in kernel order; B_COLUMN: their lane
        parked_at[order[int(book[parking.B_COLUMN, i])]] = book[parking.B_AT, i]
    return parked_at


@pytest.mark.parametrize("amplitude", [1.289391496536438e-10, 0.05, 0.3, 0.9, 1.5])
def test_lanes_below_the_static_limit_park_within_the_bound(amplitude):
    """A [m] or, above 1e-3, A/y0 (flights at 1.5)."""
    amplitude *= P.static_deflection if amplitude > 1e-3 else 1.0
    forces = LIMIT * np.array([0.0, 0.3, 0.6, 0.9, 0.97, 0.99, 0.999, 1.0 - 1e-4])
    bound = cost.PARKED_LANE_PERIODS + LIMIT / (LIMIT - forces)
    parked_at = periods_to_park(amplitude, forces, int(bound.max()))
    assert np.all(parked_at <= bound), (parked_at, bound)
