"""Forced periodic orbits against a long scipy integration to steady state.

The reference (``forced_reference``: DOP853, rtol 1e-12, every contact switch a
terminal event, the laws written out from MODEL.md) integrates for 100–240 excitation
periods and polishes the stroboscopic fixed point by Newton on a finite-difference
monodromy matrix. ``microslip.periodic_orbit`` must give the same state at t = 0, the
same extremes of y and the same amplitude (y_max − y_min)/2 within 1e-8 relative (of
y0 for positions, of y0 ω0 for the speed), on both stable branches of the folded curve
(paper data, Viscous ζ = 0.02, P0 = 0.5 N, f = 0.95 f0: lower branch A = 0.285 y0,
upper branch A = 0.662 y0) and for the damped/excited cases with loss of contact.
"""

import math

import pytest
from forced_reference import folded_model, periodic_cases, steady_case, swept_state

import microslip as ms


def _compare(orbit, ref, u, summary):
    y0 = ref.y0
    y, ydot = ref.to_si(u)
    speed = y0 * 2.0 * math.pi * ref.f0
    assert abs(orbit.y0_state[0] - y) < 1e-8 * y0
    assert abs(orbit.y0_state[1] - ydot) < 1e-8 * speed
    assert orbit.amplitude == pytest.approx(summary["amplitude"], rel=1e-8)
    assert abs(orbit.y_min - summary["y_min"]) < 1e-8 * y0
    assert abs(orbit.y_max - summary["y_max"]) < 1e-8 * y0
    assert orbit.period == pytest.approx(summary["period"], rel=1e-14)


@pytest.mark.parametrize("direction", ["up", "down"])
def test_orbit_on_each_stable_branch(direction):
    ref, u, summary = swept_state(direction)
    y, ydot = ref.to_si(u)
    # start 2 % off the steady state, inside its basin: the transient must return there
    orbit = ms.periodic_orbit(folded_model(), initial_state=(0.98 * y, 0.98 * ydot))
    assert orbit.stable
    assert not orbit.contact_lost
    _compare(orbit, ref, u, summary)


@pytest.mark.parametrize("name", sorted(periodic_cases()))
def test_orbit_from_rest(name):
    model, ref, u, summary = steady_case(name)
    orbit = ms.periodic_orbit(model)
    assert orbit.stable
    assert bool(orbit.contact_lost) == summary["contact_lost"]
    _compare(orbit, ref, u, summary)
