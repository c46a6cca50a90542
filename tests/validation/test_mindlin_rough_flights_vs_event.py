"""Mindlin lanes through flights on a rough contact law (m2 = 1.5, a Hertz contact)
against the event method.

k_t = λ dN/dδ ∝ δ^0.5 is not smooth where δ = 0, so the Mindlin lanes cross each
lift-off and touchdown on the scalar RK4 step (integrators/mindlin_windows.py) and
take the rest of each period in their closed form. The independent reference is
``simulate`` with the event method at rtol 1e-12 (DOP853 with located switching); the
yardstick is ``simulate(method="rk4")`` at the lanes' step, the same 4th-order
integration of every step (docs/theory/numerics.md, "Lanes on a Mindlin spring"). The
lanes must come as close to the reference as that run does, and must not hand the
set-ups back (``run_mindlin_lanes`` raises LaneStalledError where it does).
"""

from __future__ import annotations

import numpy as np

import microslip as ms
from microslip.budget import shortest_period
from microslip.integrators.mindlin_lanes import run_mindlin_lanes
from microslip.integrators.normal_tape import normal_coefficients
from microslip.simulation import initial_state_from_amplitude
from microslip.validation import DEFAULT_RK4_STEPS_PER_PERIOD

HERTZ = ms.Parameters(m2=1.5)
RATIO = 0.8235  # λ = 2(1-ν)/(2-ν) at ν = 0.3
FORCES = np.array([0.1, 0.5, 0.7, 0.9]) * HERTZ.mu * HERTZ.mass * HERTZ.g


def _lanes(model, normal0, periods, duration):
    """x(duration) [m] of every (set-up, force) lane on the Mindlin lanes (set-up major)."""
    dt = shortest_period(model) / DEFAULT_RK4_STEPS_PER_PERIOD
    n = len(normal0)
    coeffs = np.tile(normal_coefficients(model.pack(0.0)), (n, 1))
    groups = np.repeat(np.arange(n), FORCES.size)
    mu = model.params.mu
    return run_mindlin_lanes(coeffs, np.asarray(normal0), np.full(n, RATIO), groups,
                             np.tile(FORCES, n), mu, mu, duration, dt,
                             periods=periods)[0]  # fmt: skip


def _errors(lanes, models, duration, **start):
    """(lanes' error, rk4's error) against the event method, in units of the largest
    mean velocity; ``models`` one per set-up, ``start`` the simulate keyword per set-up."""
    v = lanes.reshape(len(models), FORCES.size) / duration
    event, rk4 = np.empty_like(v), np.empty_like(v)
    for g, model in enumerate(models):
        kwargs = {key: values[g] for key, values in start.items()}
        for i, force in enumerate(FORCES):
            options = dict(force=float(force), duration=duration, **kwargs)
            event[g, i] = ms.simulate(model, rtol=1e-12, **options).x[-1] / duration
            rk4[g, i] = ms.simulate(model, method="rk4", **options).x[-1] / duration
    scale = np.abs(event).max()
    return np.abs(v - event).max() / scale, np.abs(rk4 - event).max() / scale


def test_free_vibration_with_flights_on_a_hertz_contact():
    """From rest above the surface (A = 1.05, 1.2, 1.5 y0: a flight every period, on the
    repeated tape of one period), 0.01 s, about 150 periods. Measured: the lanes 2.6e-7
    of the largest velocity off, rk4 1.9e-6."""
    model = ms.Model(HERTZ, tangential=ms.MindlinSpring(RATIO))
    amplitudes = np.array([1.05, 1.2, 1.5]) * HERTZ.static_deflection
    normal0 = [initial_state_from_amplitude(HERTZ, a)[:2] for a in amplitudes]
    periods = [ms.free_period(HERTZ, a) for a in amplitudes]
    duration = 0.01
    lanes = _lanes(model, normal0, periods, duration)
    lanes_error, rk4_error = _errors(lanes, [model] * 3, duration, amplitude=amplitudes)
    assert rk4_error > 0.0
    assert lanes_error <= max(rk4_error, 1e-6)


def test_the_repeated_and_the_stepped_tape_agree_through_flights():
    """The same free vibration on a tape filled step by step (over 6000 rows: windows
    that reach past a block of 2048 into the rows integrated ahead of it) and on the
    repeated one (windows inside one period) agree to the RK4 error, 1e-6 of the
    largest displacement."""
    model = ms.Model(HERTZ, tangential=ms.MindlinSpring(RATIO))
    amplitude = 1.3 * HERTZ.static_deflection
    normal0 = [initial_state_from_amplitude(HERTZ, amplitude)[:2]]
    period = ms.free_period(HERTZ, amplitude)
    duration = 0.002
    repeated = _lanes(model, normal0, [period], duration)
    stepped = _lanes(model, normal0, None, duration)
    assert np.abs(repeated - stepped).max() <= 1e-6 * np.abs(repeated).max()


def test_forced_vibration_with_flights_on_a_hertz_contact():
    """A damped contact under a harmonic force strong enough to lift it off (ζ = 0.05,
    P0 = 4, 8 and 12 N at 16 kHz), from rest at y0, 0.003 s: the stepped tape, windows
    across its blocks. Measured: the lanes 1.0e-6 of the largest velocity off, rk4
    3.5e-6."""
    base = ms.Model(HERTZ, tangential=ms.MindlinSpring(RATIO), damping=ms.Viscous(0.05),
                    excitation=ms.HarmonicForce(8.0, 16e3))  # fmt: skip
    models = [base.replace(**{"excitation.amplitude": p0}) for p0 in (4.0, 8.0, 12.0)]
    dt = shortest_period(base) / DEFAULT_RK4_STEPS_PER_PERIOD
    assert all(shortest_period(m) / DEFAULT_RK4_STEPS_PER_PERIOD == dt for m in models)
    duration = 0.003
    n = len(models)
    coeffs = np.array([normal_coefficients(m.pack(0.0)) for m in models])
    normal0 = np.tile([HERTZ.static_deflection, 0.0], (n, 1))
    lanes = run_mindlin_lanes(coeffs, normal0, np.full(n, RATIO), np.repeat(np.arange(n), 4),
                              np.tile(FORCES, n), HERTZ.mu, HERTZ.mu, duration, dt)[0]  # fmt: skip
    lanes_error, rk4_error = _errors(lanes, models, duration)
    assert rk4_error > 0.0
    assert lanes_error <= max(rk4_error, 1e-6)
