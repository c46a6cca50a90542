"""A period doubling of the forced normal motion, against an independent scipy integration.

Paper data, Kelvin–Voigt damping ζ = 0.03, harmonic force P0 = 2 m g. Coming down in
frequency from 2.3 f0, the stable period-1 orbit loses stability near 2.11 f0 through a
real Floquet multiplier at −1 (a flip) and the response from rest becomes period-2: the
stroboscopic samples y(kT) alternate between two values. The issue asks that

- ``forced_response`` continue the period-1 branch through it as unstable orbits and flag
  that stretch (``period_doubling``), and
- ``periodic_orbit`` refuse (``NotPeriodOneError``), so that ``mean_velocity`` falls back
  to a time average of a simulation, with a warning.

The scipy reference (``forced_reference.py``) writes the normal law out again and gives
the stroboscopic map, its fixed points (Newton) and finite-difference multipliers; the
full system with stick and slip (``sliding_reference.py``) gives the time averages.
"""

from __future__ import annotations

import functools
import warnings

import numpy as np
import pytest
from forced_reference import NormalReference
from sliding_reference import solve as solve_full

import microslip as ms
from microslip.analysis.forced_response import forced_response
from microslip.analysis.periodic import NotPeriodOneError, periodic_orbit

P = ms.Parameters()
F0 = P.natural_frequency
Y0 = P.static_deflection
INSIDE = 2.05  # f/f0: period-2 response from rest, unstable period-1 orbit
OUTSIDE = 2.2  # f/f0: stable period-1 response
BRACKET = (2.10, 2.12)  # f/f0 just inside / just outside the flagged stretch
FORCE = 0.6  # F [N] < μ m g = 0.981 N: bounded stick-slip


def model(ratio: float) -> ms.Model:
    return ms.Model(
        P, damping=ms.Viscous(0.03), excitation=ms.HarmonicForce(2.0 * P.mass * P.g, ratio * F0)
    )


@functools.cache
def curve():
    return forced_response(model(2.3), frequencies=(2.3 * F0, 2.0 * F0))


@functools.cache
def settled(ratio: float, periods: int = 400):
    """(reference, scaled state at t = kT after ``periods`` periods from rest at y0)."""
    ref = NormalReference(model(ratio))
    return ref, ref.settle(np.array([1.0, 0.0]), periods)


@functools.cache
def reference_orbit(ratio: float):
    """(reference, period-1 fixed point by Newton from the settled state, multipliers)."""
    ref, u = settled(ratio)
    fixed = ref.fixed_point(u)
    return ref, fixed, ref.multipliers(fixed)


def test_scipy_response_is_period_2_inside_and_period_1_outside():
    ref, u = settled(INSIDE)
    strobes = [u]
    for _ in range(4):
        strobes.append(ref.strobe(strobes[-1]))
    eta = np.array([s[0] for s in strobes])
    # Two distinct stroboscopic values, each repeated every second period.
    assert np.all(np.abs(np.diff(eta)) > 0.3)
    np.testing.assert_allclose(eta[2:], eta[:-2], rtol=0.0, atol=1e-6)
    ref, u = settled(OUTSIDE)
    assert abs(ref.strobe(u)[0] - u[0]) < 1e-8


def test_flip_is_flagged_on_the_stretch_where_scipy_finds_a_multiplier_below_minus_1():
    ds = curve()
    assert ds.attrs["complete"] == 1
    assert list(ds.attrs["folds"]) == []  # a flip is no fold: the frequency keeps falling
    ratio = ds.frequency.values / F0
    flag = ds.period_doubling.values
    # The independent multipliers bracket the flip: real < -1 at 2.10 f0, inside the
    # unit circle at 2.12 f0 (and at 2.05 f0, 2.2 f0).
    for r, flipped in ((INSIDE, True), (BRACKET[0], True), (BRACKET[1], False), (OUTSIDE, False)):
        _, _, mult = reference_orbit(r)
        if flipped:
            assert np.all(np.isreal(mult)) and np.min(mult.real) < -1.0
        else:
            assert np.max(np.abs(mult)) < 1.0
    assert flag.any() and not flag.all()
    # One flagged stretch, from the flip down to the end of the curve.
    first = int(np.argmax(flag))
    assert flag[first:].all() and not flag[:first].any()
    assert BRACKET[0] <= ratio[first] < BRACKET[1] and ratio[first - 1] >= BRACKET[0]
    assert not ds.stable.values[flag].any() and ds.stable.values[~flag].all()
    assert np.all(ds.max_multiplier.values[flag] > 1.0)
    # At the end (2.0 f0) the continued orbit is the reference's unstable period-1 orbit:
    # same amplitude, same largest multiplier.
    ref, fixed, mult = reference_orbit(2.0)
    summary = ref.period_summary(fixed)
    assert float(ds.amplitude[-1]) == pytest.approx(summary["amplitude"], rel=1e-7)
    assert float(ds.max_multiplier[-1]) == pytest.approx(np.max(np.abs(mult)), rel=1e-5)


def test_periodic_orbit_refuses_inside_and_flags_the_unstable_orbit():
    with pytest.raises(NotPeriodOneError, match="not a stable period-1") as info:
        periodic_orbit(model(INSIDE))
    assert "\n" not in str(info.value)
    orbit = periodic_orbit(model(INSIDE), strict=False)
    assert not orbit.stable and not orbit.period_one
    _, fixed, mult = reference_orbit(INSIDE)
    worst = orbit.multipliers[np.argmax(np.abs(orbit.multipliers))]
    assert abs(worst.imag) == 0.0 and worst.real < -1.0
    np.testing.assert_allclose(np.sort(orbit.multipliers.real), np.sort(mult.real), rtol=1e-5)
    np.testing.assert_allclose(orbit.y0_state[0] / Y0, fixed[0], rtol=0.0, atol=1e-9)
    stable = periodic_orbit(model(OUTSIDE))
    assert stable.stable and stable.period_one


def test_mean_velocity_falls_back_to_a_time_average_with_a_warning():
    """The fall-back averages x over periods 100 to 200 of a simulation from rest: it
    equals scipy's full-system average over the same window (integration accuracy), and
    the steady period-2 mean up to the transient left after 100 periods (< 1e-4)."""
    m = model(INSIDE)
    with pytest.warns(RuntimeWarning, match="falls back to the time average"):
        value = ms.mean_velocity(m, force=FORCE)
    period = m.excitation.period
    window = np.array([100.0, 200.0]) * period
    full = solve_full(m, force=FORCE, state0=(Y0, 0.0, 0.0, 0.0), t_eval=window)
    same_window = (full.x[1] - full.x[0]) / (window[1] - window[0])
    assert value == pytest.approx(same_window, rel=1e-8)
    # The steady period-2 mean: from the settled normal state, over 40 periods.
    ref, u = settled(INSIDE)
    y, ydot = ref.to_si(u)
    steady = solve_full(
        m, force=FORCE, state0=(y, ydot, 0.0, 0.0), t_eval=[20 * period, 60 * period]
    )
    steady_value = (steady.x[1] - steady.x[0]) / (40.0 * period)
    assert value == pytest.approx(steady_value, rel=1e-4)
    # Where the response is period-1 there is no warning.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert ms.mean_velocity(model(OUTSIDE), force=FORCE) >= 0.0
