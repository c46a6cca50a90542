"""Eqs. (2.2)–(2.5): the Coulomb law, checked from the trajectory's own samples.

Nothing here reads the friction force or the friction mode that microslip reports: the
facts are computed from the sampled (t, y, ẋ) alone, with |R| = S c_n max(y, 0)^m2 (2.3)
evaluated here from the raw parameters.

* Between two samples at which the slider moves (ẋ ≠ 0 somewhere), the speed has one
  sign s (reversals are switching instants, hence samples) and m Δẋ equals the impulse
  ∫(F − μ|R| s) dt, by the trapezoidal rule from the samples (eqs. 2.2, 2.5). Summed
  over each slip phase, the same holds for the whole phase.
* The friction force m Δẋ/Δt − F never exceeds μ|R| and opposes ẋ.
* Stick (ẋ = 0 over an interval) holds only while |F| <= μ|R|; where |F| > μ|R| at rest,
  the slider is sliding at the next sample, in the direction of F.
* ``SimulationResult.Ft`` and ``.xddot`` agree with central differences of the samples.

Samples: ``rk4`` at a fine step (its step output holds every switching instant), and
``event`` on a dense ``t_eval`` that includes the switching instants of a first run.
"""

import numpy as np
import pytest

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection
T0 = P.natural_period
W0 = P.natural_angular_frequency
DURATION = 0.005  # ≈ 7.4 normal periods
DT = T0 / 2000
MU_MG = P.mu * P.mass * P.g


def limit(y):
    """μ|R(y)| [N] from (2.3) and the raw parameters."""
    return P.mu * P.area * P.c_n * np.maximum(y, 0.0) ** P.m2


def samples(method, force, start):
    """A run with samples at every switching instant and about 2000 per period."""
    common = {"force": force, "duration": DURATION, **start}
    if method == "rk4":
        return ms.simulate(P, method="rk4", dt=DT, **common)
    first = ms.simulate(P, rtol=1e-12, atol=1e-14, **common)
    t_eval = np.union1d(np.linspace(0.0, DURATION, 15001), first.event_t)
    return ms.simulate(P, rtol=1e-12, atol=1e-14, t_eval=t_eval, **common)


def check_coulomb(r, force):
    t, v, mu_r = r.t, r.xdot, limit(r.y)
    h = np.diff(t)
    assert np.all(h > 0.0)
    moving = (v[:-1] != 0.0) | (v[1:] != 0.0)
    s = np.sign(v[:-1] + v[1:])
    # One sign of ẋ per interval: a sign change is a switching instant, hence a sample
    # (a sample a rounding error before a stop may show ẋ ≈ -1e-21 m/s).
    rounding = -1e-12 * np.max(np.abs(v))
    assert np.all(s[moving] * v[:-1][moving] >= rounding)
    assert np.all(s[moving] * v[1:][moving] >= rounding)
    scale = h * max(MU_MG, abs(force))  # an impulse of order μ m g h
    # Kinetic friction (2.2) in Newton's law (2.5), interval by interval.
    impulse = h * (force - s * 0.5 * (mu_r[:-1] + mu_r[1:]))
    residual = P.mass * np.diff(v) - impulse
    assert np.all(np.abs(residual[moving]) <= 2e-5 * scale[moving]), np.max(
        np.abs(residual[moving] / scale[moving])
    )
    # Friction force: never above μ|R| (up to the trapezoid's error), always against ẋ.
    friction = P.mass * np.diff(v) / h - force
    bound = np.maximum(mu_r[:-1], mu_r[1:])
    slack = 2e-5 * max(MU_MG, abs(force))
    assert np.all(np.abs(friction[moving]) <= bound[moving] + slack)
    assert np.all(s[moving] * friction[moving] <= slack)
    # Whole slip phases: m Δẋ = ∫(F − μ|R| sgn ẋ) dt.
    edges = np.flatnonzero(np.diff(np.r_[0, moving.astype(int), 0]))
    assert edges.size % 2 == 0
    for a, b in zip(edges[::2], edges[1::2], strict=True):
        total = np.sum(impulse[a:b])
        np.testing.assert_allclose(
            P.mass * (v[b] - v[a]), total, rtol=0, atol=2e-5 * np.sum(scale[a:b])
        )
    # Stick: only while |F| <= μ|R| (2.2); at rest with |F| > μ|R| it slides off along F.
    stuck = ~moving
    tolerance = 1e-9 * max(MU_MG, abs(force))
    assert np.all(mu_r[:-1][stuck] >= abs(force) - tolerance)
    assert np.all(mu_r[1:][stuck] >= abs(force) - tolerance)
    release = (v[:-1] == 0.0) & (mu_r[:-1] < abs(force) - tolerance)
    assert np.all(np.sign(v[1:][release]) == np.sign(force))
    # The derived outputs of SimulationResult, against central differences.
    inner = moving[:-1] & moving[1:] & (s[:-1] == s[1:]) & ~np.isin(t[1:-1], r.event_t)
    inner |= stuck[:-1] & stuck[1:]
    # Second-order three-point derivative on the uneven grid (samples next to a switch
    # are closer together); intervals far below the sampling step amplify rounding.
    h1, h2 = h[:-1], h[1:]
    inner &= np.minimum(h1, h2) >= 1e-3 * np.median(h)
    central = (
        -h2 / (h1 * (h1 + h2)) * v[:-2]
        + (h2 - h1) / (h1 * h2) * v[1:-1]
        + h1 / (h2 * (h1 + h2)) * v[2:]
    )
    accel_scale = max(MU_MG, abs(force)) / P.mass
    np.testing.assert_allclose(r.xddot[1:-1][inner], central[inner], atol=1e-4 * accel_scale)
    np.testing.assert_allclose(
        r.Ft[1:-1][inner], P.mass * central[inner] - force, atol=1e-4 * accel_scale * P.mass
    )
    np.testing.assert_allclose(r.friction_limit, mu_r, rtol=1e-13, atol=0)
    return moving, stuck


STARTS = {
    "A=y0/3": {"amplitude": Y0 / 3},
    "A=y0": {"amplitude": Y0},
    "A=1.3y0": {"amplitude": 1.3 * Y0},
    "A=2y0": {"amplitude": 2.0 * Y0},
}


@pytest.mark.parametrize("method", ["event", "rk4"])
@pytest.mark.parametrize("force", [0.0, 0.5, -0.5, 0.95, -1.2])
@pytest.mark.parametrize("start", list(STARTS), ids=list(STARTS))
def test_coulomb_law_from_samples(method, force, start):
    r = samples(method, force, STARTS[start])
    moving, stuck = check_coulomb(r, force)
    amplitude = STARTS[start]["amplitude"]
    if abs(force) > P.motion_threshold(amplitude):
        assert np.count_nonzero(moving) > 100
        assert np.sign(r.x[-1]) == np.sign(force)  # it moves along F
    if abs(force) < MU_MG:
        assert np.count_nonzero(stuck) > 100


# Sliding against the drive: forward at the start with F < 0, and backward with F > 0,
# in flight (A = 1.3 y0, y(0) < 0) and in contact. Each stops and reverses or sticks.
REVERSING = {
    "forward-F<0-flight": (-0.3, (-0.3 * Y0, 0.0, 0.0, 1.7531e-5)),
    "forward-F<0-contact": (-1.2, (Y0 / 3, 0.0, 0.0, 2e-4)),
    "backward-F>0-contact": (0.5, (Y0 / 3, 0.0, 0.0, -2e-4)),
}


@pytest.mark.parametrize("method", ["event", "rk4"])
@pytest.mark.parametrize("case", list(REVERSING), ids=list(REVERSING))
def test_coulomb_law_through_reversals(method, case):
    force, state = REVERSING[case]
    r = samples(method, force, {"initial_state": state})
    check_coulomb(r, force)
    assert np.any(r.xdot * np.sign(force) < 0.0) and np.any(r.xdot * np.sign(force) > 0.0)


@pytest.mark.parametrize("force", [0.5, -0.5])
@pytest.mark.parametrize("fraction", [1 / 3, 2 / 3, 1.0, 1.3])
def test_switch_states(force, fraction):
    """At a slip start μ|R| = |F| (in contact); at a stick start ẋ = 0 and |F| <= μ|R|."""
    names = ms.integrators.EVENT_NAMES
    r = ms.simulate(P, force=force, amplitude=fraction * Y0, duration=0.01)
    y, xdot = r.event_states[:, 0], r.event_states[:, 3]
    mu_r = limit(y)
    starts = r.event_kind == names.index("slip_start")
    stops = r.event_kind == names.index("stick_start")
    assert starts.sum() >= 10 and stops.sum() >= 10
    np.testing.assert_allclose(mu_r[starts], abs(force), rtol=1e-9)
    assert np.all(xdot[stops] == 0.0)
    assert np.all(mu_r[stops] >= abs(force))
    # Stick and slip alternate.
    kinds = r.event_kind[starts | stops]
    assert np.all(kinds[1:] != kinds[:-1])
