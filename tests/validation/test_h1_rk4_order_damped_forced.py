"""RK4 keeps 4th order with damping and a harmonic force through stick, slip and loss of
contact (every switch located), and agrees with the event method.

The second case lands hard (P0 = 4 N): the Kelvin–Voigt force jumps to c δ̇ ~ 0.5 N at
touchdown. Before the contact was held over a step (model/system.py, the mode), that
jump entered the stages of the step locating the touchdown and the error stopped
falling (3e-5 y0 at every dt from T/100 to T/800)."""

from __future__ import annotations

import numpy as np
import pytest

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection
DURATION = 3e-3
FORCE = 0.5


@pytest.mark.parametrize(("amplitude", "frequency"), [(1.5 * P.mass * P.g, 1300.0), (4.0, 1200.0)])
def test_rk4_fourth_order_and_event_agreement(amplitude, frequency):
    model = ms.Model(
        P, damping=ms.Viscous(ratio=0.05),
        excitation=ms.HarmonicForce(amplitude=amplitude, frequency=frequency),
    )  # fmt: skip
    event = ms.simulate(model, force=FORCE, duration=DURATION, rtol=1e-13, atol=1e-15)
    names = {ms.integrators.EVENT_NAMES[k] for k in event.event_kind}
    assert {"contact_lost", "contact_made", "slip_start", "stick_start"} <= names
    x_ref, y_ref = event.x[-1], event.y[-1]
    period = 1.0 / 1485.0
    errors = []
    for n in (200, 400, 800):
        r = ms.simulate(model, force=FORCE, duration=DURATION, method="rk4", dt=period / n)
        errors.append((abs(r.x[-1] - x_ref) / abs(x_ref), abs(r.y[-1] - y_ref) / Y0))
    errors = np.array(errors)
    ratios = errors[:-1] / errors[1:]
    # Order 4: halving dt divides the error by ~16 (order 2 would give ~4).
    assert np.all(ratios > 11.0) and np.all(ratios < 23.0), ratios
    assert errors[-1, 0] < 1e-6  # and the finest run agrees with the event method
