"""Eq. (2.2)–(2.5): the Coulomb law holds at every sample, with true stick.

* |F_t| <= μ|R| always (friction never exceeds the limit);
* stick only at ẋ = 0, and then ẋ is exactly 0 and F_t = −F (static equilibrium, Fig. 5);
* sliding samples have ẋ > 0 (F >= 0), except at the very instant sliding starts;
  there F_t = −μ|R| sgn ẋ;
* loss of contact (y <= 0) means |R| = 0, hence no friction;
* m ẍ = F + F_t.
"""

import numpy as np
import pytest

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection
STICK, SLIP, FLIGHT = 0, 1, 2
SLIP_START = ms.integrators.EVENT_NAMES.index("slip_start")
STICK_START = ms.integrators.EVENT_NAMES.index("stick_start")


def check_coulomb(r, force):
    mu_r = P.mu * P.area * P.c_n * np.maximum(r.y, 0.0) ** P.m2  # μ|R| from (2.3)
    np.testing.assert_allclose(r.friction_limit, mu_r, rtol=1e-14, atol=0)
    assert np.all(np.abs(r.Ft) <= mu_r * (1.0 + 1e-12))
    stick = r.state == STICK
    sliding = r.direction != 0.0
    assert np.array_equal(stick, ~sliding & (r.y > 0.0))
    # Stick: exactly at rest, friction balances the drive.
    assert np.all(r.xdot[r.direction == 0.0] == 0.0)
    assert np.all(r.Ft[r.direction == 0.0] == -force)
    assert np.all(r.xddot[r.direction == 0.0] == 0.0)
    # Slip: F_t = −μ|R| sgn ẋ, and the slider moves forward.
    assert np.all(r.direction[sliding] == 1.0)
    np.testing.assert_allclose(r.Ft[sliding], -mu_r[sliding], rtol=1e-14, atol=0)
    assert np.all(r.xdot[sliding] >= 0.0)
    at_rest = sliding & (r.xdot == 0.0)
    starts = np.append(r.event_t[r.event_kind == SLIP_START], 0.0)
    assert np.all(np.isin(r.t[at_rest], starts)), "sliding at zero speed away from a slip start"
    # Flight: no reaction, no friction.
    flight = r.state == FLIGHT
    assert np.array_equal(flight, r.y <= 0.0)
    assert np.all(r.R[flight] == 0.0)
    assert np.all(r.Ft[flight & sliding] == 0.0)
    # Newton (2.5).
    np.testing.assert_allclose(
        P.mass * r.xddot, np.where(sliding, force + r.Ft, 0.0), rtol=0, atol=1e-15
    )


FRACTIONS = [0.0, 1 / 3, 2 / 3, 1.0, 1.3, 2.0]
FORCES = [0.0, 0.3, 0.5, 0.95, 1.2]


@pytest.mark.parametrize("method", ["event", "rk4"])
@pytest.mark.parametrize("force", FORCES)
@pytest.mark.parametrize("fraction", FRACTIONS)
def test_coulomb_law_at_every_step_sample(method, force, fraction):
    r = ms.simulate(P, force=force, amplitude=fraction * Y0, duration=0.01, method=method)
    check_coulomb(r, force)


@pytest.mark.parametrize("force", [0.3, 0.5, 0.95])
@pytest.mark.parametrize("fraction", [1 / 3, 1.3])
def test_coulomb_law_on_dense_output(force, fraction):
    t_eval = np.linspace(0.0, 0.005, 20001)
    r = ms.simulate(P, force=force, amplitude=fraction * Y0, duration=0.005, t_eval=t_eval)
    check_coulomb(r, force)
    if force > P.motion_threshold(fraction * Y0):
        assert np.any(r.state == STICK) and np.any(r.state == SLIP)


@pytest.mark.parametrize("fraction", [1 / 3, 2 / 3, 1.0, 1.3])
def test_switch_states(fraction):
    """At a slip start μ|R| = F (in contact); at a stick start ẋ = 0 and F <= μ|R|."""
    force = 0.5
    r = ms.simulate(P, force=force, amplitude=fraction * Y0, duration=0.01)
    y, xdot = r.event_states[:, 0], r.event_states[:, 3]
    mu_r = P.mu * P.area * P.c_n * np.maximum(y, 0.0) ** P.m2
    starts = r.event_kind == SLIP_START
    stops = r.event_kind == STICK_START
    assert starts.sum() >= 10 and stops.sum() >= 10
    np.testing.assert_allclose(mu_r[starts], force, rtol=1e-9)
    assert np.all(xdot[stops] == 0.0)
    assert np.all(mu_r[stops] >= force)
    # Stick and slip alternate.
    kinds = r.event_kind[starts | stops]
    assert np.all(kinds[1:] != kinds[:-1])
