"""The flat punch's friction reduction in closed form (docs/theory/friction_reduction.md):
a reference for the exact and time-average paths and the master-curve figure."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["flat_punch_reduction"]


def flat_punch_reduction(v_tilde: Any) -> np.ndarray:
    """D(ṽ) [-] of the flat punch: μ_eff/μ = 1 - β D(ṽ) (docs/theory/friction_reduction.md).

    m2 = 1, prescribed penetration N = N0 (1 + β cos ωt) with β <= 1, Coulomb friction,
    constant k_t, kinematic drive, ṽ = k_t |v| / (μ β N0 ω). With θ = ωt the contact
    point sticks from θ1 = π + arcsin ṽ to the first θ2 > θ1 with
    cos θ1 + ṽ (θ2 - θ1) = cos θ2, and
    D = [sin θ2 - sin θ1 - (θ2 - θ1) cos θ1 - ṽ (θ2 - θ1)²/2] / (2π); D(0) = 1, D = 0 for
    ṽ >= 1.

    Parameters
    ----------
    v_tilde : float or array
        ṽ >= 0 [-].

    Returns
    -------
    ndarray
        D(ṽ) [-], the shape of ``v_tilde``.
    """
    from scipy.optimize import brentq

    values = np.asarray(v_tilde, dtype=float)
    if np.any(~np.isfinite(values)) or np.any(values < 0.0):
        raise ValueError(f"v_tilde must be finite and >= 0, got {v_tilde!r}")
    out = np.zeros(values.shape)
    for index, vt in np.ndenumerate(values):
        if vt >= 1.0:
            continue
        theta1 = math.pi + math.asin(vt)
        c1 = math.cos(theta1)

        def gap(theta: float, vt: float = vt, theta1: float = theta1, c1: float = c1) -> float:
            return c1 + vt * (theta - theta1) - math.cos(theta)

        # gap is tangent to 0 at θ1 and falls to its minimum at 2π - arcsin ṽ first
        theta2 = brentq(gap, 2.0 * math.pi - math.asin(vt), theta1 + 2.0 * math.pi, xtol=1e-15)
        span = theta2 - theta1
        out[index] = (math.sin(theta2) - math.sin(theta1) - span * c1 - 0.5 * vt * span * span) / (
            2.0 * math.pi
        )
    return out
