"""Time sweeps of a compliant tangential contact against the event method.

``sweep(method="time")`` runs a TangentialSpring model on the spring-lane kernel (one
normal tape per set-up, the contact point in closed form per piece:
integrators/spring_lanes.py) and a MindlinSpring model on the Mindlin-lane kernel (the
same tape; the contact point's stick through a fundamental series on the piece's
stiffness quartic: integrators/mindlin_lanes.py). Each
point is checked against ``simulate(method="event")`` at rtol 1e-12, an integration with
adaptive steps and located events that shares none of the fixed-step paths: x(T)/T must
agree to the RK4 error at the default step, 1/200 of the shortest period of the model
(docs/theory/numerics.md). The stiff case (k_t = 1e3 K_n, a tangential period T0/32)
fails if the step ignores the tangential oscillation: at T0/200, ω_t dt ≈ 1.

The forced cases: Kelvin–Voigt damping in contact throughout, and with a loss of
contact every period (P0 = 4-6 N: the force jumps to c δ̇ at each touchdown, which the
mode holds out of the stages of the step that locates it); Hunt–Crossley with a loss of
contact every period. x(T)/T converges at 4th order in dt in all of them (measured with
Kelvin–Voigt, P0 = 4 N, F = 0.3 N: 1.5e-8, 1.3e-9, 8.9e-11 relative at T/200, T/400,
T/800).
"""

from __future__ import annotations

import numpy as np
import pytest
from event_reference import time_sweep_error

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection
DURATION = 0.01  # s, ~15 normal periods
CASES = {
    # loss of contact at A = 1.3 y0: contact-point flight and touchdown
    "spring, free vibration": (
        ms.Model(P, tangential=ms.TangentialSpring(P.contact_stiffness)), None,
    ),
    "stiff spring (k_t = 1e3 K_n)": (
        ms.Model(P, tangential=ms.TangentialSpring(1e3 * P.contact_stiffness)), None,
    ),
    # in contact throughout (see the module doc)
    "mindlin, Viscous + HarmonicForce": (
        ms.Model(P, tangential=ms.MindlinSpring(0.8235), damping=ms.Viscous(0.05),
                 excitation=ms.HarmonicForce(2.0, 1200.0)),
        {"excitation.amplitude": [2.0, 3.0]},
    ),
    # loss of contact every period, a force jump at touchdown (see the module doc)
    "mindlin, Viscous + HarmonicForce, flights": (
        ms.Model(P, tangential=ms.MindlinSpring(0.8235), damping=ms.Viscous(0.05),
                 excitation=ms.HarmonicForce(4.0, 1200.0)),
        {"excitation.amplitude": [4.0, 6.0]},
    ),
    # the same on the spring-lane kernel: in contact, and a loss of contact every period
    # with (Kelvin–Voigt) and without (Hunt–Crossley) a force jump at touchdown
    "spring, Viscous + HarmonicForce": (
        ms.Model(P, tangential=ms.TangentialSpring(P.contact_stiffness),
                 damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(2.0, 1200.0)),
        {"excitation.amplitude": [2.0, 3.0]},
    ),
    "spring, Viscous + HarmonicForce, flights": (
        ms.Model(P, tangential=ms.TangentialSpring(P.contact_stiffness),
                 damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(4.0, 1200.0)),
        {"excitation.amplitude": [4.0, 6.0]},
    ),
    "spring, HuntCrossley + HarmonicForce, flights": (
        ms.Model(P, tangential=ms.TangentialSpring(P.contact_stiffness),
                 damping=ms.HuntCrossley(0.05), excitation=ms.HarmonicForce(4.0, 1200.0)),
        {"excitation.amplitude": [4.0, 6.0]},
    ),
    # loss of contact every period, no force jump at touchdown (see the module doc)
    "mindlin, HuntCrossley + HarmonicForce, flights": (
        ms.Model(P, tangential=ms.MindlinSpring(0.8235), damping=ms.HuntCrossley(0.05),
                 excitation=ms.HarmonicForce(4.0, 1200.0)),
        {"excitation.amplitude": [4.0, 6.0]},
    ),
}  # fmt: skip
FORCES = np.array([0.3, 0.6, 0.9])


@pytest.mark.parametrize("name", list(CASES))
def test_time_sweep_matches_the_event_method(name):
    model, axes = CASES[name]
    error = time_sweep_error(model, axes, None if axes else [0.5 * Y0, 1.3 * Y0], FORCES, DURATION)
    assert error <= 1e-6, (error, name)
