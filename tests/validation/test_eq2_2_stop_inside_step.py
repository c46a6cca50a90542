"""Eq. (2.2): a stop (sliding speed back to zero) that happens inside one RK4 step.

Two cases that no end-of-step test can see, against the scipy reference:

* a dip: the slider slides without stopping at either end of a step, but its speed
  (continued in the sliding mode) dips below zero and back inside the step, so it must
  stop and stick there. The initial speed is ẋ0 = −min I(t) − δ, where I(t) = ∫(F −
  μ|R|)/m dt is the sliding impulse from the reference; the dip, of depth δ, is centred
  in one step of each grid (dt chosen so) and lasts half a step.
* a whole slip phase inside one step, near the motion threshold: F = F_th (1 + 3e-5)
  (eq. 4.2), so each slip lasts ~T0/330; the first one starts at t = 0 and ends inside
  the first step, later ones start and end inside one step.

``rk4`` must keep its 4th order through both, with the reference's switches.
"""

import numpy as np
import pytest
from scipy.optimize import minimize_scalar
from scipy_reference import reference_solution, sliding_impulse

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection
T0 = P.natural_period
NAMES = ms.integrators.EVENT_NAMES
DURATION = 2.37 * T0


def events(r):
    return [NAMES[k] for k in r.event_kind]


def observed_order(steps, errors):
    return -np.polyfit(np.log(steps), np.log(errors), 1)[0]


@pytest.fixture(scope="module")
def dip():
    """(F, A, t_m, I_min, I''(t_m)) of the first speed minimum of sliding from the top."""
    force, amplitude = 0.5, 0.9 * Y0
    t = np.linspace(0.0, 1.2 * T0, 2401)
    k = int(np.argmin(sliding_impulse(P, force, amplitude, t)[1:])) + 1
    res = minimize_scalar(
        lambda s: sliding_impulse(P, force, amplitude, [0.0, s])[-1],
        bounds=(t[k - 1], t[k + 1]), method="bounded", options={"xatol": 1e-14},
    )  # fmt: skip
    h = 1e-7
    values = sliding_impulse(P, force, amplitude, [0.0, res.x - h, res.x, res.x + h])
    curvature = (values[1] - 2.0 * values[2] + values[3]) / h**2
    assert curvature > 0.0
    return force, amplitude, res.x, values[2], curvature


def test_rk4_fourth_order_through_a_dip_inside_one_step(dip):
    force, amplitude, t_min, impulse_min, curvature = dip
    steps = np.array([200, 400, 800])
    errors = []
    for n in steps:
        dt = t_min / (round(t_min * n / T0 - 0.5) + 0.5)  # t_min in the middle of a step
        # v ≈ −δ + I''(t − t_m)²/2 < 0 for |t − t_m| < dt/4: the dip lasts half a step.
        depth = curvature * (0.5 * dt) ** 2 / 8.0
        state = (Y0 - amplitude, 0.0, 0.0, -impulse_min - depth)
        # The scenario: the speed, continued in the sliding mode, is positive at both ends
        # of the step, and dips below zero inside it.
        k = int(t_min / dt)
        ends = sliding_impulse(P, force, amplitude, [0.0, k * dt, t_min, (k + 1) * dt])
        assert np.all(state[3] + ends[[1, 3]] > 0.0) and state[3] + ends[2] < 0.0
        ref = reference_solution(
            P, force=force, initial_state=state, t_eval=[0.0, DURATION], rtol=1e-13, atol=1e-16
        )
        r = ms.simulate(P, force=force, initial_state=state, duration=DURATION, method="rk4", dt=dt)
        assert events(r) == ref.event_kind
        assert ref.event_kind[:2] == ["stick_start", "slip_start"]
        assert k * dt < r.event_t[0] < r.event_t[1] < (k + 1) * dt  # both in that step
        np.testing.assert_allclose(r.event_t, ref.event_t, rtol=0, atol=1e-3 * dt)
        errors.append(abs(r.x[-1] - ref.x[-1]) / abs(ref.x[-1]))
    order = observed_order(steps, errors)
    assert order >= 3.7, (order, errors)  # measured 4.09
    assert errors[0] < 5e-8, errors  # measured 4.4e-9


def test_rk4_fourth_order_through_slip_phases_inside_one_step():
    amplitude = Y0 / 2
    force = P.motion_threshold(amplitude) * (1.0 + 3e-5)
    duration = 6.37 * T0
    ref = reference_solution(
        P, force=force, amplitude=amplitude, t_eval=[0.0, duration], rtol=1e-13, atol=1e-16
    )
    assert ref.event_kind.count("stick_start") >= 6
    steps = np.array([100, 200, 400, 800])
    errors = []
    for n in steps:
        dt = T0 / n
        r = ms.simulate(P, force=force, amplitude=amplitude, duration=duration, method="rk4", dt=dt)
        assert events(r) == ref.event_kind
        # Near the threshold a switch is a shallow root: measured <= 2.1e-3 dt (n = 100).
        np.testing.assert_allclose(r.event_t, ref.event_t, rtol=0, atol=5e-3 * dt)
        step = np.floor(r.event_t / dt)
        if n <= 400:  # the first slip (from t = 0) ends inside the first step
            assert r.event_kind[0] == NAMES.index("stick_start") and step[0] == 0
        if n <= 200:  # and later ones start and stop inside one step
            starts = np.flatnonzero(r.event_kind[:-1] == NAMES.index("slip_start"))
            assert np.count_nonzero(step[starts] == step[starts + 1]) >= 3
        errors.append(abs(r.x[-1] - ref.x[-1]) / abs(ref.x[-1]))
    order = observed_order(steps, errors)
    assert order >= 3.7, (order, errors)  # measured 4.4
