"""MODEL.md identity 5: the steady mean velocity from one period of a periodic normal orbit.

References shared with microslip: none. Normal orbits come from scipy's DOP853
(``forced_reference.py``); the tangential references integrate the whole system with every
stick and slip located as solver events (``sliding_reference.py``), or are the
independent reflected-process walk of ``reflected_process.py`` (paper's free vibration).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from forced_reference import NormalReference, forced_table, free_vibration_table
from reflected_process import reflected_cycle
from sliding_reference import SlidingReference, kinematic_mean_velocity

import microslip as ms
from microslip.analysis.forced_sliding import mean_velocities, sliding_table, slip_intervals
from microslip.analysis.steady_state import mean_velocity

P = ms.Parameters()
ZETA, P0, FREQ = 0.05, 0.5, 1400.0
MODEL = ms.Model(P, damping=ms.Viscous(ZETA), excitation=ms.HarmonicForce(P0, FREQ))
TABLE_TOL = {"rtol": 1e-13, "atol": 1e-15}  # scipy tolerances of the node tables


@pytest.mark.parametrize("amplitude", [1e-7, 2e-7])
def test_free_vibration_reproduces_the_paper_closed_form(amplitude):
    t, y, v, a = free_vibration_table(P, amplitude, 1024, **TABLE_TOL)
    table = sliding_table(t, y, v, a[:-1], a[1:], mass=P.mass, gravity=P.g)
    forces = np.array([0.3, 0.6, 0.9])
    mine = mean_velocities(table, P.mu, forces)
    assert (mine > 0).sum() >= 2
    for force, value in zip(forces, mine, strict=True):
        independent = reflected_cycle(P, force=force, amplitude=amplitude).mean_velocity
        closed_form = mean_velocity(P, force=force, amplitude=amplitude)
        assert value == pytest.approx(independent, rel=1e-10, abs=1e-300)
        assert value == pytest.approx(closed_form, rel=1e-10, abs=1e-300)


def _forced_reference(force, periods=10):
    tau_period = NormalReference(MODEL).period_tau
    u = NormalReference(MODEL, **TABLE_TOL).settle([1.0, 0.0], 120)  # past the transient
    normal = NormalReference(MODEL, rtol=1e-12, atol=1e-14)
    value, releases = SlidingReference(normal, force).window_mean_velocity(
        [*u, 0.0, 0.0], 2 * tau_period, (2 + periods) * tau_period
    )
    return value * normal.y0 * normal.omega, releases


def test_harmonic_force_matches_a_long_event_driven_integration():
    model = MODEL
    force = 0.8  # μ N_min = 0.648 N: F = 0.5 N would never slide (checked below)
    reference, releases = _forced_reference(force)
    assert releases == 10  # one slip per period
    assert ms.mean_velocity(model, force=force) == pytest.approx(reference, rel=1e-8)
    # The reflected process on an independent scipy table agrees too.
    t, y, v, a = forced_table(MODEL, 512, **TABLE_TOL)
    table = sliding_table(
        t, y, v, a[:-1], a[1:], mass=P.mass, gravity=P.g, force_amplitude=P0,
        omega=2.0 * math.pi * FREQ,
    )  # fmt: skip
    assert mean_velocities(table, P.mu, np.array([force]))[0] == pytest.approx(reference, rel=1e-8)
    assert ms.mean_velocity(model, force=0.5) == 0.0
    assert _forced_reference(0.5, periods=2) == (0.0, 0)


def _kinematic_reference(load, period, force, mu, periods=4):
    """Event-driven x(t) slope under a normal force N(t) known in closed form (no normal
    state), in the scales t/T and x/(g T^2)."""
    return kinematic_mean_velocity(
        load, period, force=force, mass=P.mass, g=P.g, mu=mu, skip=2, measure=periods
    )


@pytest.mark.parametrize("beta", [0.5, 1.5])
def test_prescribed_penetration_m2_1_matches_its_closed_form_normal_force(beta):
    params = ms.Parameters(m2=1.0, c_n=2e10)
    y0 = params.static_deflection
    freq = 1000.0
    model = ms.Model(params, excitation=ms.PrescribedPenetration(y0, beta * y0, freq))
    weight = params.mass * params.g

    def load(t):  # m2 = 1: N = m g (1 + β cos ωt), clipped at 0 (contact loss for β > 1)
        return max(0.0, weight * (1.0 + beta * math.cos(2.0 * math.pi * freq * t)))

    for force in (0.5, 0.8):
        reference, releases = _kinematic_reference(load, 1.0 / freq, force, params.mu)
        assert releases == 4
        assert ms.mean_velocity(model, force=force) == pytest.approx(reference, rel=1e-8)


def test_two_slips_per_period():
    """N(t) = m g (1 + b1 cos θ + b2 cos 2θ + b3 sin 2θ), θ = ωt: two dips of different depth."""
    b1, b2, b3 = 0.3, 0.5, 0.1
    freq = 1000.0
    w = 2.0 * math.pi * freq
    t = np.linspace(0.0, 1.0 / freq, 401)
    th = w * t
    g = P.g
    # ÿ = g - N/m = -g (b1 cos θ + b2 cos 2θ + b3 sin 2θ), integrated in closed form.
    y = g * (b1 * np.cos(th) + b2 * np.cos(2 * th) / 4 + b3 * np.sin(2 * th) / 4) / w**2
    v = -g * (b1 * np.sin(th) + b2 * np.sin(2 * th) / 2 - b3 * np.cos(2 * th) / 2) / w
    a = -g * (b1 * np.cos(th) + b2 * np.cos(2 * th) + b3 * np.sin(2 * th))
    table = sliding_table(t, y, v, a[:-1], a[1:], mass=P.mass, gravity=g)

    def load(s):
        x = w * s
        return P.mass * g * (1 + b1 * math.cos(x) + b2 * math.cos(2 * x) + b3 * math.sin(2 * x))

    force = 0.75
    slips = slip_intervals(table, P.mu, force)
    assert slips.shape == (2, 3)
    assert slips[0, 2] != pytest.approx(slips[1, 2], rel=0.05)  # two different slips
    reference, releases = _kinematic_reference(load, 1.0 / freq, force, P.mu)
    assert releases == 8
    mine = mean_velocities(table, P.mu, np.array([force]))[0]
    assert mine == pytest.approx(reference, rel=1e-8)
    assert mine == pytest.approx(slips[:, 2].sum() * freq, rel=1e-14)
