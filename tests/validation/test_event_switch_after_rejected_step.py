"""Regression: an adaptive step rejected across a switch must not creep towards it.

A compliant contact point sliding under a damped, forced normal motion that lifts off
(separation inside the overlap, N_raw -> 0 with δ > 0): the spring force f = μ_k N
changes its law at the separation (a kink). A trial step across it used to be rejected
again and again, its error estimate shrinking the step towards the switch until it
underflowed (after ~175 excitation periods here). The event method now aims the next
trial at the switch; it must run through, keep |f| <= μ N, and agree with the
fixed-step RK4 method (located switching on a fine grid, a different algorithm).
"""

from __future__ import annotations

import numpy as np
import pytest

import microslip as ms

PERIOD = 1.0 / 1400.0  # s, the excitation period


@pytest.mark.parametrize(
    "tangential", [ms.TangentialSpring(7e7), ms.MindlinSpring(0.8)], ids=["spring", "mindlin"]
)
def test_sliding_contact_point_through_repeated_lift_off(tangential):
    model = ms.Model(
        ms.Parameters(),
        damping=ms.Viscous(0.05),
        excitation=ms.HarmonicForce(5.0, 1400.0),
        tangential=tangential,
        drive=ms.PrescribedVelocity(1e-4),
    )
    duration = 200 * PERIOD
    t_eval = np.linspace(150 * PERIOD, duration, 1201)
    event = ms.simulate(model, duration=duration, t_eval=t_eval)
    assert event.t[-1] == pytest.approx(duration, rel=1e-12)
    kinds = [kind for _t, kind in event.events]
    assert kinds.count("contact_lost") > 150 and kinds.count("slip_start") > 150
    mu = model.params.mu
    assert np.all(np.abs(event.spring_force) <= mu * event.N * (1 + 1e-9) + 1e-12)
    rk4 = ms.simulate(model, duration=duration, t_eval=t_eval, method="rk4", dt=PERIOD / 4000)
    scale = np.max(np.abs(event.spring_force))
    assert scale > 0.1 * mu * model.params.mass * model.params.g
    assert np.max(np.abs(event.spring_force - rk4.spring_force)) <= 1e-5 * scale
    assert np.max(np.abs(event.u - rk4.u)) <= 1e-9 * np.max(np.abs(event.u))
