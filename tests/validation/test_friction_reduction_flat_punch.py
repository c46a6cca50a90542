"""Friction reduction by normal vibration (docs/theory/friction_reduction.md).

- Identity 6: rigid tangential contact, kinematic drive: μ_eff = μ for any normal motion.
- Flat punch (m2 = 1, N = N0 (1 + β cos ωt), constant k_t, Coulomb): μ_eff/μ = 1 − β D(ṽ)
  for β <= 1, D = 0 for ṽ >= 1; D from a test-local derivation (scipy quad + brentq).
- β > 1 (loss of contact), static/kinetic friction, Mindlin, forced normal motion:
  against an independent discrete envelope of the contact point's force, written here
  from the physics (f can rise at most at k_t v and never exceed the friction limit).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad, simpson
from scipy.optimize import brentq

import microslip as ms

PUNCH = ms.Parameters(m2=1.0, c_n=1e8, area=1.0)  # y0 = 9.81e-8 m, K_n = 1e8 N/m
MEAN, FREQ, KT = 1e-7, 1000.0, 1e6  # δ_m [m], f [Hz], k_t [N/m]
N0 = PUNCH.stiffness_coefficient * MEAN
OMEGA = 2 * math.pi * FREQ


def local_d(vt: float) -> float:
    """D(ṽ) from its definition: the stick deficit integrated with quad."""
    if vt >= 1.0:
        return 0.0
    t1 = math.pi + math.asin(vt)

    def catch_up(t):
        return math.cos(t1) + vt * (t - t1) - math.cos(t)

    t2 = brentq(catch_up, 1.5 * math.pi + 1e-9, t1 + 2 * math.pi, xtol=1e-14)
    deficit, _ = quad(lambda t: math.cos(t) - math.cos(t1) - vt * (t - t1), t1, t2,
                      epsabs=1e-14, epsrel=1e-13)  # fmt: skip
    return deficit / (2 * math.pi)


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


@pytest.mark.parametrize("beta", [0.25, 0.6, 1.0])
@pytest.mark.parametrize("v_tilde", [0.03, 0.2, 0.5, 0.8, 0.99, 1.0, 1.3])
def test_flat_punch_reduction_matches_the_closed_form(beta, v_tilde):
    result = ms.effective_friction(punch(beta, v_tilde))
    assert result.method == "exact"
    assert result.ratio == pytest.approx(1.0 - beta * local_d(v_tilde), abs=1e-8)
    assert result.v_tilde == pytest.approx(v_tilde, rel=1e-4)
    if v_tilde >= 1.0:
        assert result.ratio == pytest.approx(1.0, abs=1e-12)  # no reduction past ṽ = 1
        assert result.stick_fraction < (1e-9 if v_tilde > 1.0 else 1e-5)  # ṽ = 1: tangency


def test_library_closed_form_matches_the_local_derivation():
    vts = np.array([0.0, 1e-3, 0.1, 0.37, 0.75, 0.999, 1.0, 2.0])
    expected = [1.0 if vt == 0 else local_d(vt) for vt in vts]
    np.testing.assert_allclose(ms.flat_punch_reduction(vts), expected, rtol=0, atol=1e-10)


@pytest.mark.parametrize(("beta", "v_tilde"), [(1.5, 0.3), (2.5, 0.6)])
def test_loss_of_contact_against_the_envelope(beta, v_tilde):
    model = punch(beta, v_tilde)
    exact = ms.effective_friction(model).mu_eff
    assert exact == pytest.approx(envelope_mu_eff(model, punch_normal(beta), 1 / FREQ),
                                  rel=2e-6)  # fmt: skip
    assert exact < PUNCH.mu * (1 - local_d(v_tilde))  # past β = 1 the reduction keeps growing


def test_static_kinetic_and_mindlin_against_the_envelope():
    sk = ms.StaticKinetic(mu_static=0.15, mu_kinetic=0.1)
    for model in (punch(0.8, 0.3, friction=sk), punch(1.4, 0.4, friction=sk),
                  punch(0.8, 0.3, tangential=ms.MindlinSpring(0.01))):  # fmt: skip
        beta = model.excitation.amplitude / MEAN
        exact = ms.effective_friction(model).mu_eff
        assert exact == pytest.approx(
            envelope_mu_eff(model, punch_normal(beta), 1 / FREQ), rel=2e-6
        )


@pytest.mark.parametrize(
    "normal_part",
    [{"amplitude": 4e-7}, {"excitation": ms.HarmonicForce(amplitude=15.0, frequency=1400.0)},
     {"excitation": ms.HarmonicForce(amplitude=3.0, frequency=1400.0),
      "damping": ms.Viscous(0.05)}],
)  # fmt: skip
def test_identity6_rigid_kinematic_drive_gives_mu(normal_part):
    """Exact path and an independent time average of a simulate run (Simpson)."""
    amplitude = normal_part.pop("amplitude", None)
    model = ms.Model(ms.Parameters(), drive=ms.PrescribedVelocity(2e-4), **normal_part)
    assert ms.effective_friction(model, amplitude=amplitude).mu_eff == model.params.mu
    t = np.linspace(0.0, 0.01, 40_001)
    kwargs = {} if amplitude is None else {"amplitude": amplitude}
    run = ms.simulate(model, duration=t[-1], t_eval=t, **kwargs)
    assert run.N.min() == 0.0 or amplitude is None  # the free case loses contact
    ratio = simpson(-run.Ft, x=t) / simpson(run.N, x=t)
    assert ratio == pytest.approx(model.params.mu, rel=1e-12)


def test_stiff_tangential_contact_tends_to_the_rigid_one():
    """k_t -> ∞ on the paper's free vibration (m2 = 2, contact lost every period):
    μ_eff rises monotonically to μ and equals it once ṽ >= 1."""
    p = ms.Parameters()
    ratios, v_tildes = [], []
    for kt in (1e5, 1e6, 1e7, 1e8, 1e9):
        model = ms.Model(p, tangential=ms.TangentialSpring(kt), drive=ms.PrescribedVelocity(1e-4))
        result = ms.effective_friction(model, amplitude=1.5 * p.static_deflection)
        ratios.append(result.ratio)
        v_tildes.append(result.v_tilde)
    assert np.all(np.diff(ratios) > 0) or ratios[-1] == pytest.approx(1.0, abs=1e-12)
    assert ratios[0] < 0.2
    assert v_tildes[-1] > 1.0 and ratios[-1] == pytest.approx(1.0, abs=1e-10)


def test_forced_normal_motion_against_a_time_average():
    """Mindlin contact on a damped forced orbit: exact path vs a long simulate run.

    Hunt–Crossley damping: N has no jump at touchdown, so the trapezoid average of the
    test converges at second order (measured: 2e-8 at 2000 samples per period, 4x less
    at 4000)."""
    p = ms.Parameters()
    model = ms.Model(
        p, damping=ms.HuntCrossley(0.05),
        excitation=ms.HarmonicForce(amplitude=5.0, frequency=1400.0),
        tangential=ms.MindlinSpring(0.8), drive=ms.PrescribedVelocity(1e-4),
    )  # fmt: skip
    exact = ms.effective_friction(model)
    period = 1 / 1400.0
    t = np.linspace(100 * period, 110 * period, 10 * 4000 + 1)
    run = ms.simulate(model, duration=t[-1], t_eval=t)
    average = np.trapezoid(-run.Ft, t) / np.trapezoid(run.N, t)
    assert 0.3 < exact.ratio < 0.9  # a real reduction
    assert exact.mu_eff == pytest.approx(average, rel=1e-7)
