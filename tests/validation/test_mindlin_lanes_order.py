"""The Mindlin-lane time kernel (integrators/mindlin_lanes.py) against an independent
event-driven scipy DOP853 integration (tangential_reference.py, sharing no code with
microslip), and its convergence order.

The kernel integrates the normal motion once (RK4 on the grid k·dt, contact switches
located) and every lane's contact point per piece: in stick the linear system
ḟ = k_t(t) ẋ, m ẍ = F - f through its fundamental series on the piece's quartic
k_t(τ) = λ dN_el/dδ, in slip the rigid law with the stop function s u̇ = s ẋ - μ_k Ṅ/k_t,
out of contact free flight with a relaxed spring. A wrong stiffness (its nodes, fit or
the interpolated normal state), a wrong series, a missed or misplaced release, stop,
touchdown or lift-off would show up as an O(1) error or a lost order here.
"""

from __future__ import annotations

import numpy as np
import pytest
import tangential_reference

import microslip as ms
from microslip.budget import shortest_period
from microslip.integrators.mindlin_lanes import run_mindlin_lanes
from microslip.integrators.normal_tape import normal_coefficients
from microslip.simulation import initial_state_from_amplitude

P = ms.Parameters()
Y0 = P.static_deflection
DURATION = 0.005  # s, ~7 normal periods
SK = ms.StaticKinetic(mu_static=0.15, mu_kinetic=0.1)
MINDLIN = ms.MindlinSpring(0.8235)
FINE = (200, 400, 800)  # steps per shortest period of the model

CASES = {
    # creep in contact: a release and a stop every period, k_t following δ
    "in contact": (ms.Model(P, tangential=MINDLIN), 0.5, 0.5 * Y0, FINE),
    # a flight every period: k_t -> 0 at lift-off and touchdown, the spring relaxed
    "flights": (ms.Model(P, tangential=MINDLIN), 0.8, 1.3 * Y0, FINE),
    # mu_s > mu_k: the force drops from mu_s N to mu_k N at each release
    "static-kinetic": (ms.Model(P, tangential=MINDLIN, friction=SK), 0.7, 0.5 * Y0, FINE),
    "static-kinetic, flights": (ms.Model(P, tangential=MINDLIN, friction=SK), 0.5, 1.3 * Y0,
                                FINE),
    # lambda = 10: the body oscillates ~3 times faster than the normal motion
    "stiff": (ms.Model(P, tangential=ms.MindlinSpring(10.0)), 0.6, 0.8 * Y0, (100, 200, 400)),
}  # fmt: skip


def _x_end(model, force, amplitude, dt):
    """x(DURATION) [m] of one lane from rest, a relaxed spring, on the model's tape."""
    c = model.pack(0.0)
    friction = model.friction or ms.Coulomb()
    mu_s = P.mu if isinstance(friction, ms.Coulomb) else friction.mu_static
    mu_k = P.mu if isinstance(friction, ms.Coulomb) else friction.mu_kinetic
    normal0 = np.array([initial_state_from_amplitude(P, amplitude)[:2]])
    x = run_mindlin_lanes(normal_coefficients(c)[None], normal0, [model.tangential.ratio],
                          [0], [force], mu_s, mu_k, DURATION, dt)[0]  # fmt: skip
    return float(x[0])


@pytest.mark.parametrize("name", list(CASES))
def test_fourth_order_against_scipy(name):
    """x(T) against scipy at rtol 1e-12: within 3e-6 relative at the default step (1/200
    of the shortest period; measured 0.3-2.1e-6, where simulate(method="rk4") has
    0.1-1.0e-6 on the same cases), and the error falls >= 10x per halving of dt (~16x
    measured)."""
    model, force, amplitude, divisions = CASES[name]
    reference = tangential_reference.reference_solution(
        model, t_eval=[DURATION], amplitude=amplitude, force=force
    ).x[-1]
    period = shortest_period(model)
    errors = [
        abs(_x_end(model, force, amplitude, period / n) - reference) / abs(reference)
        for n in divisions
    ]
    assert errors[divisions.index(200)] <= 3e-6, errors
    assert errors[0] / errors[1] >= 10.0 and errors[1] / errors[2] >= 10.0, errors
