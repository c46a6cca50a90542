"""k_t → ∞: the compliant contact tends to the rigid one, μ_eff → μ
(docs/theory/friction_reduction.md, critical speed and touchdown).

Where N is smooth the reduction vanishes exactly once ṽ >= 1 (the paper's free vibration,
m2 = 2, contact lost every period). Where N jumps at touchdown (Kelvin–Voigt damping,
N+ = c δ̇ > 0 at δ = 0) the point sticks at every touchdown for any k_t and the reduction
falls as 1/k_t; its asymptote follows from that stick alone,
μ - μ_eff ≈ μ² N+² / (2 (k_t v - μ Ṅ+) T <N>), here with every quantity in closed form.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import microslip as ms

PUNCH = ms.Parameters(m2=1.0, c_n=1e8, area=1.0)  # K = 1e8 N/m, μ = 0.1, m = 1 kg
K, MU = PUNCH.stiffness_coefficient, PUNCH.mu
MEAN, FREQ, BETA, ZETA, V = 1e-7, 1000.0, 1.5, 0.2, 1e-5
OMEGA, T = 2.0 * math.pi * FREQ, 1.0 / FREQ
C = 2.0 * ZETA * math.sqrt(K * PUNCH.mass)  # c = 2 ζ sqrt(K_n m), K_n = K for m2 = 1


def kelvin_voigt_asymptote() -> tuple[float, float, float]:
    """(N+ [N], Ṅ+ [N/s], <N> [N]) of N = K δ + c δ̇ (clipped), δ = δ_m (1 + β cos ωt)."""
    touchdown = math.pi + math.acos(1.0 / BETA)  # δ = 0, δ̇ > 0
    rate = MEAN * BETA * OMEGA * math.sqrt(1.0 - 1.0 / BETA**2)  # δ̇ there
    jump, jump_rate = C * rate, K * rate + C * MEAN * OMEGA**2  # δ̈ = δ_m ω² there

    def raw(th):  # K δ + c δ̇ at θ = ωt
        return K * MEAN * (1.0 + BETA * math.cos(th)) - C * MEAN * BETA * OMEGA * math.sin(th)

    separation = brentq(raw, 0.0, math.acos(-1.0 / BETA), xtol=1e-16)  # N_raw = 0, δ > 0

    def primitive(th):  # ∫ raw dθ
        return K * MEAN * (th + BETA * math.sin(th)) + C * MEAN * BETA * OMEGA * math.cos(th)

    mean = (primitive(separation) - primitive(0.0) + primitive(2 * math.pi)
            - primitive(touchdown)) / (2.0 * math.pi)  # fmt: skip
    return jump, jump_rate, mean


def test_kelvin_voigt_touchdown_reduction_falls_as_one_over_kt():
    model = ms.Model(
        PUNCH, damping=ms.Viscous(ZETA), drive=ms.PrescribedVelocity(V),
        excitation=ms.PrescribedPenetration(mean=MEAN, amplitude=BETA * MEAN, frequency=FREQ),
    )  # fmt: skip
    jump, jump_rate, mean = kelvin_voigt_asymptote()
    stiffnesses = 4e9 * 4.0 ** np.arange(5)
    results = [ms.effective_friction(model.replace(tangential=ms.TangentialSpring(k)))
               for k in stiffnesses]  # fmt: skip
    reduction = np.array([MU - r.mu_eff for r in results])
    predicted = MU**2 * jump**2 / (2.0 * (stiffnesses * V - MU * jump_rate) * T * mean)
    deviation = np.abs(reduction / predicted - 1.0)
    assert all(r.v_tilde > 1.0 for r in results)  # no stick but the touchdown's
    assert np.all(reduction > 0.0) and np.all(np.diff(reduction) < 0.0)
    steps = reduction[:-1] / reduction[1:]  # -> 4: first order in 1/k_t
    assert np.all(np.diff(np.abs(steps - 4.0)) < 0.0) and abs(steps[-1] - 4.0) < 0.02
    assert np.all(np.diff(deviation) < 0.0)  # the asymptote is approached monotonically
    assert deviation[-1] < 1e-6
    assert all(r.mean_normal_force == pytest.approx(mean, rel=1e-12) for r in results)


def test_smooth_normal_force_reduction_vanishes_at_the_critical_speed():
    """The paper's free vibration with loss of contact (m2 = 2: N and Ṅ vanish at
    touchdown): μ_eff rises monotonically with k_t and equals μ exactly for ṽ >= 1."""
    p = ms.Parameters()
    amplitude = 1.5 * p.static_deflection
    model = ms.Model(p, drive=ms.PrescribedVelocity(1e-4))
    stiffnesses = np.geomspace(1e5, 1e9, 9)
    results = [ms.effective_friction(model.replace(tangential=ms.TangentialSpring(k)),
                                     amplitude=amplitude) for k in stiffnesses]  # fmt: skip
    ratios = np.array([r.ratio for r in results])
    v_tilde = np.array([r.v_tilde for r in results])
    np.testing.assert_allclose(v_tilde / stiffnesses, v_tilde[0] / stiffnesses[0], rtol=1e-12)
    below = v_tilde < 1.0
    assert below.sum() >= 4 and (~below).sum() >= 2
    assert np.all(np.diff(ratios[below]) > 0.0) and ratios[0] < 0.3
    np.testing.assert_allclose(ratios[~below], 1.0, rtol=0.0, atol=1e-14)
