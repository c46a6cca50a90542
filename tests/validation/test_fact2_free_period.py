"""docs/model-facts.md, fact 2 / Sec. 3, Fig. 2: the period of the free normal vibration (2.4).

The exact period is the energy integral T(A) = 2 ∫ dy / sqrt(2(E − V(y))/m) between the
turning points, V(y) = S c_n max(y,0)^(m2+1)/(m2+1) − m g y. It is evaluated here with
scipy's QUADPACK, independently of microslip: the inverse-square-root endpoint
singularities are taken by the algebraic weight of ``quad(weight='alg')`` after
factoring E − V(y) = (y − a) Q(y) exactly (divided differences with expm1/log1p, so no
cancellation near the turning point), and a loss of contact (y < 0, free fall) is split off.
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

import microslip as ms

EPS = 2.220446049250313e-16


def energy_period(params, amplitude, epsrel=1e-13):
    """T(A) [s] by the energy integral, for rest at the top y = y0 − A."""
    m, g, k, m2 = params.mass, params.g, params.area * params.c_n, params.m2
    n = m2 + 1.0
    y0 = (m * g / k) ** (1.0 / m2)

    def potential(y):
        return (k * y**n / n if y > 0.0 else 0.0) - m * g * y

    def divided_difference(p, q):
        """(V(p) − V(q)) / (p − q) for p > 0, q >= 0, accurate for q → p."""
        d = (p - q) / p
        ratio = n if d == 0.0 else -math.expm1(n * math.log1p(-d)) / d
        return k * p ** (n - 1.0) * ratio / n - m * g

    top = y0 - amplitude
    energy = potential(top)
    hi = 2.0 * y0
    while potential(hi) < energy:
        hi *= 2.0
    bottom = brentq(lambda y: potential(y) - energy, y0, hi, xtol=1e-300, rtol=4 * EPS)
    opts = {"epsabs": 0.0, "epsrel": epsrel, "limit": 500}

    # Lower half [y0, bottom]: E − V(y) = (bottom − y) D(bottom, y), D > 0.
    lower, _ = quad(
        lambda y: 1.0 / math.sqrt(2.0 * divided_difference(bottom, y) / m),
        y0,
        bottom,
        weight="alg",
        wvar=(0.0, -0.5),
        **opts,
    )
    if top > 0.0:  # E − V(y) = (y − top) (−D(top, y))
        upper, _ = quad(
            lambda y: 1.0 / math.sqrt(-2.0 * divided_difference(top, y) / m),
            top,
            y0,
            weight="alg",
            wvar=(-0.5, 0.0),
            **opts,
        )
    elif top == 0.0:  # E = 0: E − V(y) = y (m g − k y^m2 / n)
        upper, _ = quad(
            lambda y: 1.0 / math.sqrt(2.0 * (m * g - k * y**m2 / n) / m),
            0.0,
            y0,
            weight="alg",
            wvar=(-0.5, 0.0),
            **opts,
        )
    else:  # free fall from top < 0 to contact at y = 0, then the contact arc to y0
        flight, _ = quad(
            lambda y: 1.0 / math.sqrt(2.0 * g), top, 0.0, weight="alg", wvar=(-0.5, 0.0), **opts
        )
        arc, _ = quad(lambda y: 1.0 / math.sqrt(2.0 * (energy - potential(y)) / m), 0.0, y0, **opts)
        upper = flight + arc
    return 2.0 * (upper + lower)


def linear_spring_period(params, amplitude):
    """Closed form for m2 = 1: harmonic in contact, free-fall parabola in flight."""
    y0 = params.mass * params.g / (params.area * params.c_n)
    omega = math.sqrt(params.g / y0)
    if amplitude <= y0:
        return 2.0 * math.pi / omega
    v_contact = math.sqrt(2.0 * params.g * (amplitude - y0))
    harmonic_amplitude = math.sqrt(y0 * (2.0 * amplitude - y0))
    arc = 2.0 * math.pi - 2.0 * math.acos(y0 / harmonic_amplitude)
    return 2.0 * v_contact / params.g + arc / omega


FRACTIONS = [0.01, 1 / 3, 2 / 3, 1.0, 1.3, 2.0]


@pytest.mark.parametrize("fraction", [0.01, 0.5, 1.0, 1.3, 2.0, 5.0])
def test_energy_integral_reproduces_the_linear_spring(fraction):
    """The quadrature of this test is itself checked against a closed form (m2 = 1)."""
    p = ms.Parameters(m2=1.0, c_n=2e13)
    y0 = p.static_deflection
    expected = linear_spring_period(p, fraction * y0)
    assert energy_period(p, fraction * y0) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("fraction", [0.01, 0.5, 1.0, 1.3, 2.0, 5.0])
def test_free_period_of_the_linear_spring_with_loss_of_contact(fraction):
    p = ms.Parameters(m2=1.0, c_n=2e13)
    amplitude = fraction * p.static_deflection
    assert ms.free_period(p, amplitude) == pytest.approx(
        linear_spring_period(p, amplitude), rel=1e-10
    )


@pytest.mark.parametrize("m2", [1.5, 2.0, 3.0])
@pytest.mark.parametrize("fraction", FRACTIONS)
def test_free_frequency_matches_the_energy_integral(m2, fraction):
    p = ms.Parameters(m2=m2)
    amplitude = fraction * p.static_deflection
    period = energy_period(p, amplitude)
    assert ms.free_period(p, amplitude) == pytest.approx(period, rel=1e-9)
    assert ms.free_frequency(p, amplitude) == pytest.approx(1.0 / period, rel=1e-9)


@pytest.mark.parametrize("m2", [1.5, 2.0, 3.0])
def test_lindstedt_poincare_small_amplitude(m2):
    """f/f0 = 1 − (m2 − 1)(2 m2 + 1) a²/48 + O(a³), a = A/y0."""
    p = ms.Parameters(m2=m2)
    y0 = p.static_deflection
    f0 = math.sqrt(m2 * p.g / y0) / (2.0 * math.pi)
    a = np.array([0.005, 0.01, 0.02, 0.04, 0.08])
    lp = 1.0 - (m2 - 1.0) * (2.0 * m2 + 1.0) * a**2 / 48.0
    exact = np.array([1.0 / (energy_period(p, x * y0) * f0) for x in a])
    code = np.array([ms.free_frequency(p, x * y0) / f0 for x in a])
    for ratio in (exact, code):
        residual = np.abs(ratio - lp)
        assert np.all(residual < 0.1 * (1.0 - lp))  # the a² term leads
        order = np.polyfit(np.log(a), np.log(residual), 1)[0]
        assert 2.8 < order < 4.2, order


def test_turning_points_bound_an_orbit_of_equal_energy():
    for m2 in (1.5, 2.0, 3.0):
        p = ms.Parameters(m2=m2)
        y0 = p.static_deflection
        k = p.area * p.c_n
        for fraction in FRACTIONS:
            low, high = ms.turning_points(p, fraction * y0)
            assert low == y0 - fraction * y0
            energy = k * max(low, 0.0) ** (m2 + 1) / (m2 + 1) - p.mass * p.g * low
            at_high = k * high ** (m2 + 1) / (m2 + 1) - p.mass * p.g * high
            assert at_high == pytest.approx(energy, rel=1e-13, abs=1e-14 * p.mass * p.g * y0)
            assert high > y0
