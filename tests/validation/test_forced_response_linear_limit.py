"""MODEL.md identity 3: small forcing and damping give the linear oscillator.

The amplitude tends to P0 / sqrt((K_n - m ω²)² + (c ω)²), K_n = m2 m g / y0, c = 2 ζ
sqrt(K_n m); the nonlinear correction is of relative order P0 / (m g).
"""

from __future__ import annotations

import math

import numpy as np

import microslip as ms
from microslip.analysis.forced_response import forced_response

P = ms.Parameters()
F0 = P.natural_frequency
ZETA = 0.01


def _error(p0):
    model = ms.Model(P, ms.Viscous(ZETA), ms.HarmonicForce(p0, F0))
    ds = forced_response(model, frequencies=(0.5 * F0, 1.5 * F0))
    assert float(ds.frequency[0]) == 0.5 * F0 and float(ds.frequency[-1]) == 1.5 * F0
    assert ds.sizes["point"] >= 10 and bool(ds.stable.all()) and not ds.attrs["folds"].size
    omega = 2.0 * math.pi * ds.frequency.values
    k_n = P.m2 * P.mass * P.g / P.static_deflection
    c = 2.0 * ZETA * math.sqrt(k_n * P.mass)
    linear = p0 / np.sqrt((k_n - P.mass * omega**2) ** 2 + (c * omega) ** 2)
    return float(np.max(np.abs(ds.amplitude.values / linear - 1.0)))


def test_amplitude_tends_to_the_linear_oscillator():
    large, small = _error(1e-3), _error(1e-4)
    assert large <= 1e-4  # P0 = 1e-4 m g, through the resonance
    assert small <= 1e-5
    assert large / small > 5.0  # the correction shrinks with P0 (here ~ P0², even order)
