"""Eq. (2.2) with F < 0 and sliding against the drive, against the scipy reference.

Backward sliding from rest (F < 0), and reversals: a slider sliding one way while the
drive pushes the other way comes to rest and, where |F| > μ|R| there (in flight, or at
a low reaction), slides off the other way (event ``reversal``). The independent DOP853
reference of ``scipy_reference.py`` handles both signs and any initial state; ``event``
must match it closely and ``rk4`` must keep its 4th order through these switches.
"""

import numpy as np
import pytest
from scipy_reference import reference_solution

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection
T0 = P.natural_period
NAMES = ms.integrators.EVENT_NAMES
TIGHT = {"rtol": 1e-12, "atol": 1e-14}
DURATION = 0.01  # ≈ 15 normal periods
T_EVAL = np.linspace(0.0, DURATION, 201)

CASES = {
    # F < 0 from rest at the top: stick-slip backwards, in contact and with flights.
    "backward-A=y0/3": {"force": -0.5, "amplitude": Y0 / 3},
    "backward-A=1.3y0": {"force": -0.5, "amplitude": 1.3 * Y0},
    # Forward at the start, F < 0, in flight: stops and reverses in flight.
    "reversal-in-flight": {"force": -0.3, "initial_state": (-0.3 * Y0, 0.0, 0.0, 1.7531e-5)},
    # Forward at the start, F < 0, in contact: reverses where |F| > μ|R|, sticks once at
    # a high reaction, then slides backwards for good (|F| > μ m g).
    "reversal-in-contact": {"force": -1.2, "initial_state": (Y0 / 3, 0.0, 0.0, 2e-4)},
}
REVERSALS = {"reversal-in-flight": 1, "reversal-in-contact": 1}


def events(r):
    return [NAMES[k] for k in r.event_kind]


@pytest.fixture(scope="module")
def references():
    return {name: reference_solution(P, t_eval=T_EVAL, **kwargs) for name, kwargs in CASES.items()}


@pytest.mark.parametrize("case", list(CASES))
def test_event_method_matches_scipy(references, case):
    ref = references[case]
    r = ms.simulate(P, duration=DURATION, t_eval=T_EVAL, **TIGHT, **CASES[case])
    scale = np.max(np.abs(ref.x))
    assert ref.x[-1] < -0.1 * scale  # the slider ends up behind its start
    # Measured: x <= 2e-11, ẋ <= 7e-10 relative.
    np.testing.assert_allclose(r.x, ref.x, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(r.xdot, ref.xdot, rtol=0, atol=1e-8 * np.max(np.abs(ref.xdot)))
    np.testing.assert_allclose(r.y, ref.y, rtol=0, atol=1e-9 * Y0)


@pytest.mark.parametrize("case", list(CASES))
def test_switching_instants_match_scipy(references, case):
    ref = references[case]
    r = ms.simulate(P, duration=DURATION, **TIGHT, **CASES[case])
    assert events(r) == ref.event_kind
    assert ref.event_kind.count("reversal") == REVERSALS.get(case, 0)
    assert ref.event_kind.count("stick_start") >= (1 if case == "reversal-in-contact" else 10)
    # Measured: <= 9e-11 T0.
    np.testing.assert_allclose(r.event_t, ref.event_t, rtol=0, atol=1e-9 * T0)
    np.testing.assert_allclose(
        r.event_states[:, 2], ref.event_x, rtol=0, atol=1e-9 * np.max(np.abs(ref.x))
    )


@pytest.mark.parametrize("amplitude", [Y0 / 3, 1.3 * Y0])
def test_mirror_symmetry(amplitude):
    """(2.2)–(2.5) are odd in (F, x): F → −F gives x → −x with the same switches."""
    common = {"amplitude": amplitude, "duration": DURATION}
    for method in ("event", "rk4"):
        forward = ms.simulate(P, force=0.5, method=method, **common)
        backward = ms.simulate(P, force=-0.5, method=method, **common)
        np.testing.assert_allclose(backward.x, -forward.x, rtol=1e-12, atol=0)
        np.testing.assert_array_equal(backward.event_kind, forward.event_kind)
        np.testing.assert_allclose(backward.event_t, forward.event_t, rtol=1e-12)


STEPS_PER_PERIOD = np.array([100, 200, 400, 800])
ORDER_DURATION = 2.37 * T0  # not a multiple of any step


@pytest.mark.parametrize("case", list(CASES))
def test_rk4_is_fourth_order(case):
    kwargs = CASES[case]
    ref = reference_solution(P, t_eval=[0.0, ORDER_DURATION], rtol=1e-13, atol=1e-16, **kwargs)
    errors = []
    for n in STEPS_PER_PERIOD:
        r = ms.simulate(P, duration=ORDER_DURATION, method="rk4", dt=T0 / n, **kwargs)
        assert events(r) == ref.event_kind  # through the same switches, reversals included
        errors.append(abs(r.x[-1] - ref.x[-1]) / abs(ref.x[-1]))
    order = -np.polyfit(np.log(STEPS_PER_PERIOD), np.log(errors), 1)[0]
    assert order >= 3.7, (order, errors)
    assert errors[1] < 5e-6, errors
