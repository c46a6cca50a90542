"""Forced periodic orbits and Floquet multipliers against an independent scipy integration.

The reference integrates the normal motion with a harmonic force and Kelvin–Voigt
damping (MODEL.md table; eq. 2.4 with excitation) in the scales η = y/y0, τ = ω0 t,
ω0 = sqrt(K_n/m), K_n = m2 m g / y0, where it reads

    η'' = (1 + p sin(Ω τ) - n) / m2,   n = η^m2 + 2 ζ m2 η'  in contact, 0 in flight,

p = P0/(m g), Ω = f/f0; contact iff η > 0 and n > 0. Each contact switch is a terminal
event of scipy's DOP853 (rtol 1e-12) and the integration restarts in the new mode. It
shares no code with microslip.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import microslip as ms
from microslip.analysis.forced_response import forced_response
from microslip.analysis.periodic import periodic_orbit

P = ms.Parameters()
F0 = P.natural_frequency
Y0 = P.static_deflection
W0 = 2.0 * math.pi * F0
ZETA = 0.02
P0 = 0.6  # N: the curve bends left and folds near 0.92 f0 and 0.95 f0
F_BAND = 0.935  # f/f0 inside the hysteresis band
# A down-sweep from rest above the band reaches the upper orbit (stages: f/f0, periods).
DOWN_SWEEP = ((1.0, 120), (0.96, 120), (0.945, 120), (F_BAND, 300))


def _reference(zeta, p, omega, u0, tau_end, extrema_after=None, m2=2.0):
    """(state at tau_end, y/y0 at every ẏ = 0 after ``extrema_after``)."""
    k = 2.0 * zeta * m2

    def raw(u):
        return u[0] * abs(u[0]) ** (m2 - 1.0) + k * u[1]

    def rhs(contact):
        def f(tau, u):
            n = raw(u) if contact else 0.0
            return [u[1], (1.0 + p * math.sin(omega * tau) - n) / m2]

        return f

    def gap(tau, u):
        return u[0]

    def force(tau, u):
        return raw(u) if (u[0] > 0.0) else -1.0

    def turning(tau, u):
        return u[1]

    gap.terminal = force.terminal = True
    turning.terminal = False
    tau, u = 0.0, np.array(u0, dtype=float)
    contact = u[0] > 0.0 and raw(u) > 0.0
    extrema = []
    while tau < tau_end:
        gap.direction = force.direction = -1.0 if contact else 1.0
        sol = solve_ivp(
            rhs(contact), (tau, tau_end), u, method="DOP853", rtol=1e-12, atol=1e-14,
            events=[gap, force, turning], max_step=0.25,
        )  # fmt: skip
        if extrema_after is not None:
            extrema += [
                y[0]
                for t, y in zip(sol.t_events[2], sol.y_events[2], strict=True)
                if t >= extrema_after
            ]
        tau, u = sol.t[-1], sol.y[:, -1].copy()
        if sol.status == 1:
            contact = not contact
    return u, extrema


def _model(p0=P0, zeta=ZETA, f=F_BAND):
    return ms.Model(P, damping=ms.Viscous(zeta), excitation=ms.HarmonicForce(p0, f * F0))


@functools.cache
def _steady_extremes(stages, zeta=ZETA, p0=P0):
    """A scipy frequency sweep from rest: (f/f0, periods) stages; extremes of the last
    period and the final state (η, η') at a whole number of periods.

    Each stage ends after a whole number of periods, where sin(Ω τ) = 0, so the next
    stage starts at τ = 0 with a continuous force.
    """
    u = np.array([1.0, 0.0])
    for i, (omega, periods) in enumerate(stages):
        period = 2.0 * math.pi / omega
        last = i == len(stages) - 1
        u, extrema = _reference(
            zeta, p0 / (P.mass * P.g), omega, u, periods * period,
            extrema_after=(periods - 1) * period if last else None,
        )  # fmt: skip
    return max(extrema) * Y0, min(extrema) * Y0, u


@pytest.fixture(scope="module")
def branches():
    model = _model()
    up = forced_response(model, frequencies=(0.6 * F0, F_BAND * F0)).isel(point=-1)
    down = forced_response(model, frequencies=(1.45 * F0, F_BAND * F0)).isel(point=-1)
    return up, down


def test_both_stable_orbits_in_the_hysteresis_band_match_scipy_sweeps(branches):
    up, down = branches
    assert float(up.frequency) == F_BAND * F0 == float(down.frequency)
    assert bool(up.stable) and bool(down.stable)
    assert float(down.amplitude) > 2.0 * float(up.amplitude)  # two different orbits
    # Up: from rest at f (the lower orbit). Down: from rest above the band, stepped down.
    for point, stages in (
        (up, ((F_BAND, 300),)),
        (down, DOWN_SWEEP),
    ):
        y_max, y_min, _ = _steady_extremes(stages)
        amplitude = 0.5 * (y_max - y_min)
        assert abs(float(point.amplitude) - amplitude) <= 1e-8 * amplitude
        assert abs(float(point.y_max) - y_max) <= 1e-8 * amplitude
        assert abs(float(point.y_min) - y_min) <= 1e-8 * amplitude


def test_contact_loss_orbit_matches_scipy():
    model = _model(p0=3.0, zeta=0.05, f=0.95)
    orbit = periodic_orbit(model)
    assert orbit.contact_lost and orbit.N_min == 0.0 and orbit.y_min < 0.0
    y_max, y_min, _ = _steady_extremes(((0.95, 150),), zeta=0.05, p0=3.0)
    amplitude = 0.5 * (y_max - y_min)
    assert abs(orbit.amplitude - amplitude) <= 1e-8 * amplitude
    assert abs(orbit.y_min - y_min) <= 1e-8 * amplitude


@pytest.mark.parametrize(
    ("p0", "zeta", "f", "start", "size"),
    [
        (P0, ZETA, F_BAND, None, (0.2, 0.3)),
        (P0, ZETA, F_BAND, "upper", (0.7, 0.9)),
        (3.0, 0.05, 0.95, None, (0.9, 1.0)),
    ],
    ids=["lower", "upper", "contact-loss"],
)
def test_floquet_multipliers_match_scipy_finite_difference_monodromy(p0, zeta, f, start, size):
    if start == "upper":  # start from the end of the scipy down-sweep
        start = tuple(_steady_extremes(DOWN_SWEEP)[2] * np.array([Y0, Y0 * W0]))
    orbit = periodic_orbit(_model(p0=p0, zeta=zeta, f=f), initial_state=start)
    assert size[0] * Y0 < orbit.amplitude < size[1] * Y0  # the intended orbit
    scale = np.array([Y0, Y0 * W0])
    s = orbit.y0_state / scale
    period = 2.0 * math.pi / f
    eps = 1e-5
    monodromy = np.zeros((2, 2))
    for j in range(2):
        e = np.zeros(2)
        e[j] = eps
        plus, _ = _reference(zeta, p0 / (P.mass * P.g), f, s + e, period)
        minus, _ = _reference(zeta, p0 / (P.mass * P.g), f, s - e, period)
        monodromy[:, j] = (plus - minus) / (2.0 * eps)
    expected = np.sort_complex(np.linalg.eigvals(monodromy))
    got = np.sort_complex(orbit.multipliers)
    assert np.max(np.abs(got - expected)) <= 1e-6
