"""Time sweeps with StaticKinetic friction against the event method.

``sweep(method="time")`` of a model with ``StaticKinetic(μ_s, μ_k)`` friction runs on the
shared-normal lane kernels with a lane's own static and kinetic coefficients: stick up
to μ_s N (eq. 2.2 with μ_s), slip against μ_k N (eq. 2.5 with μ_k), on a rigid contact
(integrators/rigid_lane_law.py), a TangentialSpring (integrators/spring_lane_law.py) and
a MindlinSpring (integrators/mindlin_lane_law.py). Each point is checked against
``simulate(method="event")`` at rtol 1e-12 (adaptive steps, located events, none of the
lanes' code): x(T)/T must agree to the RK4 error at the default step (1e-6 of the
largest, as for Coulomb friction: docs/theory/numerics.md).

The forces straddle both limits: 0.3 N slides only where the vibration unloads the
contact below 0.3/μ_s, 0.9 N below μ_k m g = 0.981 N, 1.2 N between μ_k m g and
μ_s m g (stuck at rest, sliding for ever once released). A sweep that used one
coefficient for both (Coulomb's μ = 0.1 = μ_k) is off by far more than the tolerance:
the last test shows the event method itself tells the two laws apart at these points.
The Mindlin case with flights failed (x(T)/T 22 times the event method's at F = 1.2 N,
A = 1.3 y0) while the Mindlin lanes decided a grazing touchdown on k_t(0) and dN/dt at
δ = 0, both zero to rounding for m2 > 1, instead of their ratio R = δ̇/λ
(integrators/spring_lane_law.py, ``touchdown``).
"""

from __future__ import annotations

import numpy as np
import pytest
from event_reference import time_sweep_error

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection
DURATION = 0.01  # s, ~15 normal periods
FRICTION = ms.StaticKinetic(mu_static=0.15, mu_kinetic=0.1)
FORCES = np.array([0.3, 0.9, 1.2])
# A = 0.05 y0 holds every force (μ_s N >= 0.15 m g (0.95)² = 1.33 N), A = 0.5 y0 stays in
# contact, A = 1.3 y0 flies every period
AMPLITUDES = np.array([0.05, 0.5, 1.3]) * Y0
CASES = {
    "rigid, free vibration": (ms.Model(P, friction=FRICTION), None),
    "spring, free vibration": (
        ms.Model(P, tangential=ms.TangentialSpring(P.contact_stiffness), friction=FRICTION),
        None,
    ),
    "mindlin, free vibration": (
        ms.Model(P, tangential=ms.MindlinSpring(0.8235), friction=FRICTION), None,
    ),
    "rigid, Viscous + HarmonicForce, flights": (
        ms.Model(P, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(4.0, 1200.0),
                 friction=FRICTION),
        {"excitation.amplitude": [2.0, 6.0]},
    ),
}  # fmt: skip


@pytest.mark.parametrize("name", list(CASES))
def test_static_kinetic_time_sweep_matches_the_event_method(name):
    model, axes = CASES[name]
    error = time_sweep_error(model, axes, None if axes else AMPLITUDES, FORCES, DURATION)
    assert error <= 1e-6, (error, name)


def test_the_event_method_tells_static_kinetic_from_coulomb_at_these_points():
    """The check above can fail: at F = 1.2 N and A = 0.05 y0 the slider stays stuck
    under StaticKinetic(0.15, 0.1) (μ_s N_min > F) and runs away under Coulomb μ = 0.1;
    at F = 0.9 N and A = 0.5 y0 both creep, 7 % apart: far more than the 1e-6 of the
    largest mean velocity the sweep must match."""
    coulomb = ms.Model(P)
    static = ms.Model(P, friction=FRICTION)
    run = {"duration": DURATION, "rtol": 1e-12}
    stuck = {"force": 1.2, "amplitude": 0.05 * Y0, **run}
    assert ms.simulate(static, **stuck).x[-1] == 0.0
    assert ms.simulate(coulomb, **stuck).x[-1] > 1e-6  # m
    creep = {"force": 0.9, "amplitude": 0.5 * Y0, **run}
    x_static, x_coulomb = ms.simulate(static, **creep).x[-1], ms.simulate(coulomb, **creep).x[-1]
    assert 0.0 < x_static < 0.95 * x_coulomb
