"""The sampled and refined maxima of dN/dt and (dN/dt)/K that a normal cycle stores
(analysis/normal_pieces.py, ``build_pieces``): the scales of the critical drive speed
(ṽ = k_t v / (μ max Ṅ), or v / (μ max Ṅ/K) for a Mindlin contact).

With a prescribed penetration δ(t) = δm + Δ cos ωt on the power law, N = S c δ^m2 and
K = m2 S c δ^(m2-1), so Ṅ/K = δ̇ = -Δ ω sin ωt: max Ṅ/K = Δ ω whatever m2 (while in
contact). max Ṅ = max of m2 S c δ^(m2-1) δ̇ is found here on a fine grid, refined by
golden section (independent of the pieces). A mix-up of the two rates, of the stiffness
with the force, or of a piece's end values with another's fails one of them."""

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

import microslip as ms
from microslip.analysis.normal_period import normal_cycle

P = ms.Parameters()


def rate(t, mean, delta, omega):
    """Ṅ [N/s] of the prescribed penetration on the power law (0 out of contact)."""
    d = mean + delta * math.cos(omega * t)
    if d <= 0.0:
        return 0.0
    stiffness = P.m2 * P.stiffness_coefficient * d ** (P.m2 - 1.0)
    return stiffness * (-delta * omega * math.sin(omega * t))


@pytest.mark.parametrize("mean, delta", [(1e-7, 0.5e-7), (1e-7, 1.5e-7)])
def test_rate_maxima_of_a_prescribed_penetration(mean, delta):
    frequency = 1000.0
    omega = 2.0 * math.pi * frequency
    model = ms.Model(
        P, excitation=ms.PrescribedPenetration(mean=mean, amplitude=delta, frequency=frequency)
    )
    cycle = normal_cycle(model, None)
    assert cycle.ratio_max == pytest.approx(delta * omega, rel=1e-9)
    grid = np.linspace(0.0, 1.0 / frequency, 20001)
    best = grid[np.argmax([rate(t, mean, delta, omega) for t in grid])]
    step = grid[1] - grid[0]
    refined = minimize_scalar(
        lambda t: -rate(t, mean, delta, omega), bounds=(best - step, best + step),
        method="bounded", options={"xatol": 1e-15},
    )  # fmt: skip
    assert cycle.rate_max == pytest.approx(-refined.fun, rel=1e-9)
