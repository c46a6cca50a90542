"""MODEL.md identity 4: the backbone of the free vibration, f/f0 ≈ 1 + κ a², a = A/y0,

    κ = 3 a3/8 − 5 a2²/12,  a2 = (m2 − 1)/2,  a3 = (m2 − 1)(m2 − 2)/6

(Lindstedt–Poincaré for x'' + x + a2 x² + a3 x³ = 0, the contact law expanded about y0).
The frequency is even in the first-harmonic amplitude; A (the distance to the top) differs
from it at O(a²), so the residual f/f0 − 1 − κ a² is O(a³): halving a divides it by ~8
(measured 7.75, 7.86, 7.89 for m2 = 1.5, 2, 2.5), and at a = 0.02 it is below 1 % of κ a²
(0.3 %, 0.7 %, 1.0 %). A κ off by 5 % leaves an O(a²) residual (ratio 4) and fails both.
Checked on ``microslip.free_frequency`` and on the independent scipy reference.
"""

import pytest
from forced_reference import NormalReference

import microslip as ms

AMPLITUDES = (0.02, 0.04)


def kappa(m2):
    a2 = (m2 - 1.0) / 2.0
    a3 = (m2 - 1.0) * (m2 - 2.0) / 6.0
    return 3.0 * a3 / 8.0 - 5.0 * a2 * a2 / 12.0


def _check(residuals, m2):
    small, large = residuals
    assert abs(small) < 0.015 * abs(kappa(m2)) * AMPLITUDES[0] ** 2, residuals
    assert 6.5 < large / small < 9.5, residuals


@pytest.mark.parametrize("m2", [1.5, 2.0, 2.5])
def test_backbone_free_frequency(m2):
    p = ms.Parameters(m2=m2)
    residuals = [
        ms.free_frequency(p, a * p.static_deflection) / p.natural_frequency - 1.0 - kappa(m2) * a**2
        for a in AMPLITUDES
    ]
    _check(residuals, m2)


@pytest.mark.parametrize("m2", [1.5, 2.0, 2.5])
def test_backbone_reference(m2):
    ref = NormalReference(ms.Model(ms.Parameters(m2=m2)))
    residuals = []
    for a in AMPLITUDES:
        run = ref.integrate(0.0, [1.0 - a, 0.0], 1.5 * ref.natural_tau, extrema=True)
        period = next(t for t, eta in run.extrema if eta < 1.0 and t > 0.5 * ref.natural_tau)
        residuals.append(ref.natural_tau / period - 1.0 - kappa(m2) * a * a)
    _check(residuals, m2)


def test_softening_with_amplitude_for_m2_above_one():
    assert all(kappa(m2) < 0.0 for m2 in (1.5, 2.0, 2.5))
    p = ms.Parameters()
    f = [ms.free_frequency(p, a * p.static_deflection) for a in (0.1, 0.2, 0.4)]
    assert f[0] > f[1] > f[2]
