"""Eq. (2.4): the free normal vibration is conservative and periodic.

docs/model-facts.md, facts 2 and 6.

E = ½ m ẏ² + V(y), V(y) = S c_n max(y,0)^(m2+1)/(m2+1) − m g y, written out here, must stay
constant along a simulated run, with or without loss of contact, and whatever the
tangential force (the normal motion does not depend on x). The period read off the
simulated zero crossings of ẏ must be the exact free period.
"""

import numpy as np
import pytest

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection
FRACTIONS = [0.01, 1 / 3, 2 / 3, 1.0, 1.3, 2.0]
TIGHT = {"rtol": 1e-12, "atol": 1e-14}


def energy(params, y, ydot):
    k = params.area * params.c_n
    n = params.m2 + 1.0
    return (
        0.5 * params.mass * ydot**2 + k * np.maximum(y, 0.0) ** n / n - params.mass * params.g * y
    )


def energy_drift(params, r):
    """max |E(t) − E(0)| over the run, in units of m g y0."""
    e = energy(params, r.y, r.ydot)
    return np.max(np.abs(e - e[0])) / (params.mass * params.g * params.static_deflection)


@pytest.mark.parametrize("fraction", FRACTIONS)
@pytest.mark.parametrize("force", [0.0, 0.5])
def test_energy_is_conserved_by_the_event_method(fraction, force):
    # 0.05 s ≈ 60–74 normal periods.
    tight = ms.simulate(P, force=force, amplitude=fraction * Y0, duration=0.05, **TIGHT)
    default = ms.simulate(P, force=force, amplitude=fraction * Y0, duration=0.05)
    loose = ms.simulate(
        P, force=force, amplitude=fraction * Y0, duration=0.05, rtol=1e-10, atol=1e-12
    )
    assert energy_drift(P, tight) < 1e-9  # measured <= 1.8e-10
    assert energy_drift(P, default) < 1e-8
    assert energy_drift(P, loose) < 1e-7  # measured <= 1.8e-8
    # The energy error is controlled by the tolerance: 100x tighter, >= 30x smaller.
    if fraction > 0.01:
        assert energy_drift(P, tight) < energy_drift(P, loose) / 30


@pytest.mark.parametrize("fraction", [1 / 3, 1.0, 2.0])
def test_energy_is_conserved_by_rk4(fraction):
    r = ms.simulate(P, force=0.5, amplitude=fraction * Y0, duration=0.05, method="rk4")
    assert energy_drift(P, r) < 1e-6


@pytest.mark.parametrize("m2", [1.5, 3.0])
@pytest.mark.parametrize("fraction", [0.5, 1.0, 1.5])
def test_energy_is_conserved_for_other_exponents(m2, fraction):
    p = ms.Parameters(m2=m2)
    amplitude = fraction * p.static_deflection
    periods = 50
    duration = periods * ms.free_period(p, amplitude)
    r = ms.simulate(p, force=0.5, amplitude=amplitude, duration=duration, **TIGHT)
    # Per period: measured <= 1.4e-11 (m2 = 1.5 with loss of contact, where the contact
    # law y^1.5 is least smooth), <= 2e-12 otherwise.
    assert energy_drift(p, r) < 3e-11 * periods


@pytest.mark.parametrize("changes", [{}, {"mass": 2.5, "m2": 1.5}])  # m = 1 hides m vs 1/m
def test_normal_energy_matches_the_formula(changes):
    p = P.replace(**changes)
    y0 = p.static_deflection
    y = np.linspace(-2 * y0, 3 * y0, 101)
    ydot = np.linspace(-1e-3, 1e-3, 101)
    scale = p.mass * p.g * y0
    np.testing.assert_allclose(
        ms.normal_energy(p, y, ydot), energy(p, y, ydot), rtol=1e-14, atol=1e-14 * scale
    )


def ydot_upward_crossings(params, r):
    """Times where ẏ goes from − to + (the highest points), by cubic Hermite interpolation
    of ẏ with the exact ÿ = g − S c_n max(y,0)^m2 / m at the samples."""
    yd = r.ydot
    acc = params.g - params.area * params.c_n * np.maximum(r.y, 0.0) ** params.m2 / params.mass
    times = []
    for i in np.nonzero((yd[:-1] < 0.0) & (yd[1:] >= 0.0))[0]:
        h = r.t[i + 1] - r.t[i]
        f0, f1, d0, d1 = yd[i], yd[i + 1], acc[i] * h, acc[i + 1] * h
        lo, hi = 0.0, 1.0
        for _ in range(60):
            s = 0.5 * (lo + hi)
            value = (
                (2 * s**3 - 3 * s**2 + 1) * f0
                + (s**3 - 2 * s**2 + s) * d0
                + (-2 * s**3 + 3 * s**2) * f1
                + (s**3 - s**2) * d1
            )
            lo, hi = (s, hi) if value < 0.0 else (lo, s)
        times.append(r.t[i] + 0.5 * (lo + hi) * h)
    return np.array(times)


@pytest.mark.parametrize("fraction", FRACTIONS)
def test_period_of_the_simulation_is_the_free_period(fraction):
    amplitude = fraction * Y0
    period = ms.free_period(P, amplitude)
    for tolerances, bound in ((TIGHT, 1e-10), ({}, 1e-8)):
        # Dense output (~400 samples per period) keeps the test's cubic interpolation of
        # the crossings far below the bounds, whatever steps the integrator takes.
        dense = np.linspace(0.0, 0.05, 30001)
        r = ms.simulate(
            P, force=0.5, amplitude=amplitude, duration=0.05, t_eval=dense, **tolerances
        )
        tops = ydot_upward_crossings(P, r)
        assert tops.size >= 50
        # The run starts at a top: the k-th top is at k T.
        k = np.round(tops / period)
        assert np.all(np.diff(k) == 1)
        mean_period = (tops[-1] - tops[0]) / (k[-1] - k[0])
        assert mean_period == pytest.approx(period, rel=bound)  # measured 1.6e-11 / 1.6e-9
        assert np.max(np.abs(tops - k * period)) < 100 * bound * period


def test_normal_motion_does_not_depend_on_the_tangential_motion():
    t_eval = np.linspace(0.0, 0.01, 201)
    for fraction in (2 / 3, 1.3):
        runs = [
            ms.simulate(p, force=f, amplitude=fraction * Y0, duration=0.01, t_eval=t_eval, **TIGHT)
            for p, f in ((P, 0.0), (P, 0.5), (P.replace(mu=0.0), 0.5), (P, 2.0))
        ]
        for r in runs[1:]:
            np.testing.assert_allclose(r.y, runs[0].y, rtol=0, atol=1e-10 * Y0)
            np.testing.assert_allclose(
                r.ydot, runs[0].ydot, rtol=0, atol=1e-10 * Y0 * P.natural_angular_frequency
            )
