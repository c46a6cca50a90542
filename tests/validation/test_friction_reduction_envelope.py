"""Friction reduction past the flat punch's closed form (docs/theory/friction_reduction.md):
β > 1 (loss of contact), static/kinetic friction and Mindlin's stiffness, against an
independent discrete envelope of the contact point's force, written here from the
physics (f can rise at most at k_t v and never exceed the friction limit). The closed
form itself (β <= 1) is checked in test_flat_punch_friction_reduction.py.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import microslip as ms

PUNCH = ms.Parameters(m2=1.0, c_n=1e8, area=1.0)  # y0 = 9.81e-8 m, K_n = 1e8 N/m
MEAN, FREQ, KT = 1e-7, 1000.0, 1e6  # δ_m [m], f [Hz], k_t [N/m]
N0 = PUNCH.stiffness_coefficient * MEAN
OMEGA = 2 * math.pi * FREQ


def punch(beta: float, v_tilde: float, **parts) -> ms.Model:
    velocity = v_tilde * PUNCH.mu * N0 * beta * OMEGA / KT
    return ms.Model(
        PUNCH,
        excitation=ms.PrescribedPenetration(mean=MEAN, amplitude=beta * MEAN, frequency=FREQ),
        tangential=parts.pop("tangential", ms.TangentialSpring(KT)),
        drive=ms.PrescribedVelocity(velocity),
        **parts,
    )


def envelope_mu_eff(model: ms.Model, normal, period: float, n: int = 200_000) -> float:
    """μ_eff of the contact point from a discrete envelope over N(t) = ``normal(t)``.

    Stick: f rises by k_t v dt; it slips when it would pass μ_s N, and then sits on
    μ_k N while that rises slower than k_t v; no contact: f = 0. Three periods, the
    last averaged (trapezoid); error O(dt^2) per switch.
    """
    c = model.pack()
    mu_s, mu_k = c[16], c[4]  # MU_STATIC, MU
    v = model.drive.velocity
    t = np.linspace(0.0, 3 * period, 3 * n + 1)
    dt = t[1] - t[0]
    big_n = normal(t)
    if isinstance(model.tangential, ms.MindlinSpring):
        stiffness = model.tangential.ratio * normal.stiffness(t)
    else:
        stiffness = np.full(t.size, model.tangential.stiffness)
    f = np.empty(t.size)
    f[0], slipping = 0.0, False
    for k in range(1, t.size):
        if big_n[k] <= 0.0:
            f[k], slipping = 0.0, False
            continue
        load = 0.5 * (stiffness[k] + stiffness[k - 1]) * v * dt
        if slipping and mu_k * (big_n[k] - big_n[k - 1]) <= load:
            f[k] = mu_k * big_n[k]
            continue
        f[k] = f[k - 1] + load
        slipping = False
        if f[k] > mu_s * big_n[k]:
            f[k], slipping = mu_k * big_n[k], True
    last = slice(2 * n, 3 * n + 1)
    return np.trapezoid(f[last], t[last]) / np.trapezoid(big_n[last], t[last])


def punch_normal(beta: float):
    def normal(t):
        return np.maximum(N0 * (1.0 + beta * np.cos(OMEGA * t)), 0.0)

    normal.stiffness = lambda t: np.where(normal(t) > 0, PUNCH.stiffness_coefficient, 0.0)
    return normal


@pytest.mark.parametrize(("beta", "v_tilde"), [(1.5, 0.3), (2.5, 0.6)])
def test_loss_of_contact_against_the_envelope(beta, v_tilde):
    model = punch(beta, v_tilde)
    exact = ms.effective_friction(model).mu_eff
    assert exact == pytest.approx(envelope_mu_eff(model, punch_normal(beta), 1 / FREQ),
                                  rel=2e-6)  # fmt: skip
    # past β = 1 the reduction exceeds the closed form's β D(ṽ) at β = 1
    assert exact < PUNCH.mu * (1 - float(ms.flat_punch_reduction(v_tilde)))


def test_static_kinetic_and_mindlin_against_the_envelope():
    sk = ms.StaticKinetic(mu_static=0.15, mu_kinetic=0.1)
    for model in (punch(0.8, 0.3, friction=sk), punch(1.4, 0.4, friction=sk),
                  punch(0.8, 0.3, tangential=ms.MindlinSpring(0.01))):  # fmt: skip
        beta = model.excitation.amplitude / MEAN
        exact = ms.effective_friction(model).mu_eff
        assert exact == pytest.approx(
            envelope_mu_eff(model, punch_normal(beta), 1 / FREQ), rel=2e-6
        )
