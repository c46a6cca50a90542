"""Flat punch (docs/theory/friction_reduction.md): m2 = 1, prescribed penetration
δ = δ_m (1 + β cos ωt), so N = N0 (1 + β cos ωt); constant k_t, Coulomb friction,
kinematic drive. For β <= 1: μ_eff/μ = 1 - β D(ṽ), ṽ = k_t v / (μ β N0 ω), D = 0 for
ṽ >= 1 (Popov, Popov & Popov 2017).

D is derived here again without the library: θ2 by scanning g(θ) = cos θ1 + ṽ (θ - θ1)
- cos θ for its first sign change after θ1 = π + arcsin ṽ (then brentq), and the stick
deficit ∫ [cos θ - cos θ1 - ṽ (θ - θ1)] dθ by quad. β > 1 (loss of contact) is checked
against the independent scipy integration of contact_point_reference.py.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from contact_point_reference import ContactPoint, average
from scipy.integrate import quad
from scipy.optimize import brentq

import microslip as ms

PUNCH = ms.Parameters(m2=1.0, c_n=1e8, area=1.0)  # K = S c_n = 1e8 N/m, μ = 0.1
K = PUNCH.stiffness_coefficient
MU = PUNCH.mu
MEAN, FREQ, KT = 1e-7, 1000.0, 1e6  # δ_m [m], f [Hz], k_t [N/m]
N0, OMEGA = K * MEAN, 2.0 * math.pi * FREQ
V_TILDES = np.array([0.01, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 0.99, 1.0, 1.1, 1.5])
BETAS = (0.1, 0.4, 0.75, 1.0)


def local_d(vt: float) -> float:
    """D(ṽ) from its definition (module docstring)."""
    if vt >= 1.0:
        return 0.0
    th1 = math.pi + math.asin(vt)

    def g(th: float) -> float:
        return math.cos(th1) + vt * (th - th1) - math.cos(th)

    grid = th1 + np.linspace(1e-3, 2.0 * math.pi, 4001)
    values = np.array([g(th) for th in grid])
    k = int(np.argmax(values >= 0.0))  # g < 0 right after θ1 (g'' = cos θ1 < 0)
    th2 = brentq(g, grid[k - 1], grid[k], xtol=1e-15, rtol=1e-15)
    deficit, _ = quad(lambda th: math.cos(th) - math.cos(th1) - vt * (th - th1), th1, th2,
                      epsabs=1e-13, epsrel=1e-12)  # fmt: skip
    return deficit / (2.0 * math.pi)


def punch(beta: float) -> ms.Model:
    exc = ms.PrescribedPenetration(mean=MEAN, amplitude=beta * MEAN, frequency=FREQ)
    return ms.Model(PUNCH, excitation=exc, tangential=ms.TangentialSpring(KT),
                    drive=ms.PrescribedVelocity(1e-4))  # fmt: skip


def speed(beta: float, vt):
    """v [m/s] for ṽ = k_t v / (μ max|Ṅ|), max|Ṅ| = β N0 ω."""
    return vt * MU * beta * N0 * OMEGA / KT


@pytest.mark.parametrize("beta", BETAS)
def test_reduction_is_one_minus_beta_d(beta):
    ds = ms.effective_friction_curve(punch(beta), speed(beta, V_TILDES))
    expected = 1.0 - beta * np.array([local_d(vt) for vt in V_TILDES])
    np.testing.assert_allclose(ds.ratio.values, expected, rtol=0.0, atol=1e-8)
    np.testing.assert_allclose(ds.v_tilde.values, V_TILDES, rtol=1e-12)
    np.testing.assert_allclose(ds.mean_normal_force.values, N0, rtol=1e-12)  # <N> = N0
    beyond = V_TILDES >= 1.0
    np.testing.assert_allclose(ds.ratio.values[beyond], 1.0, rtol=0.0, atol=1e-14)
    assert np.all(ds.stick_fraction.values[V_TILDES > 1.0] == 0.0)
    assert np.all(ds.stick_fraction.values[~beyond] > 0.0)


def test_reduction_is_linear_in_beta_with_a_common_stick_interval():
    """(1 - μ_eff/μ)/β and the stick fraction (θ2 - θ1)/2π do not depend on β."""
    vts = V_TILDES[V_TILDES < 1.0]
    per_beta = [ms.effective_friction_curve(punch(b), speed(b, vts)) for b in BETAS]
    slopes = np.array([(1.0 - ds.ratio.values) / b for ds, b in zip(per_beta, BETAS, strict=True)])
    np.testing.assert_allclose(slopes, np.broadcast_to(slopes[0], slopes.shape), rtol=1e-10)
    sticks = np.array([ds.stick_fraction.values for ds in per_beta])
    np.testing.assert_allclose(sticks, np.broadcast_to(sticks[0], sticks.shape), rtol=1e-10)


def test_library_closed_form_matches_the_local_derivation():
    vts = np.linspace(0.0, 1.5, 61)[1:]
    np.testing.assert_allclose(ms.flat_punch_reduction(vts), [local_d(v) for v in vts],
                               rtol=0.0, atol=1e-12)  # fmt: skip
    assert ms.flat_punch_reduction(0.0) == pytest.approx(1.0, abs=1e-15)  # D(0) = 1
    assert ms.flat_punch_reduction([[0.2, 0.5]]).shape == (1, 2)
    np.testing.assert_allclose(ms.flat_punch_reduction([0.2, 0.5]),
                               [0.5709617901, 0.2014522033], atol=1e-10)  # fmt: skip


def punch_reference(beta: float, velocity: float) -> ContactPoint:
    """The flat punch written out for the scipy reference: N = K max(δ, 0)."""

    def delta(t):
        return MEAN * (1.0 + beta * math.cos(OMEGA * t))

    return ContactPoint(
        normal=lambda t: K * max(delta(t), 0.0),
        normal_rate=lambda t: -K * MEAN * beta * OMEGA * math.sin(OMEGA * t),
        stiffness=lambda t: KT, contact=delta, velocity=velocity, mu_static=MU,
        mu_kinetic=MU, period=1.0 / FREQ, force_scale=N0,
    )  # fmt: skip


@pytest.mark.parametrize("beta", [1.3, 3.0])
def test_loss_of_contact_against_the_scipy_reference(beta):
    """β > 1: f = 0 in flight, a stuck point with a relaxed spring at touchdown."""
    vts = np.array([0.05, 0.3, 0.8, 1.5])
    ds = ms.effective_friction_curve(punch(beta), speed(beta, vts))
    for vt, ratio, stick in zip(vts, ds.ratio.values, ds.stick_fraction.values, strict=True):
        ref = average(punch_reference(beta, speed(beta, vt)), periods=3)
        assert ratio * MU == pytest.approx(ref["mu_eff"], rel=1e-9)
        assert stick == pytest.approx(ref["stick_fraction"], abs=1e-9)
    assert ds.ratio.values[-1] == pytest.approx(1.0, abs=1e-14)  # ṽ > 1: no reduction
    # with the contact lost, the reduction exceeds the linear law's β D(ṽ) at β = 1
    assert np.all(ds.ratio.values[:-1] < 1.0 - np.array([local_d(v) for v in vts[:-1]]))
