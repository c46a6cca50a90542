"""Normal contact law: the power-law compliant interface, eqs. (2.1)–(2.4).

Sign convention: y > 0 is penetration (y measured downward), y <= 0 a loss of contact.
microslip reports the compressive magnitude |R| >= 0 of the paper's reaction
R(y) = -S c_n y^m2 (2.3); the normal equation (2.4) then reads m ÿ = m g - |R|.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.coefficients import AREA_CN, EXPONENT
from microslip.model.parameters import Parameters

__all__ = [
    "contact_side_stiffness",
    "elastic_force",
    "elastic_stiffness",
    "normal_reaction",
    "potential_energy",
    "reaction_array",
]


@njit(cache=True, error_model="numpy")
def elastic_force(delta, c):
    """The power law S c_n max(δ, 0)^m2 [N] of eq. (2.3) at penetration δ [m].

    The only implementation of the power law in compiled code; the damping laws
    (:mod:`microslip.model.damping`) and the composed normal force
    (:mod:`microslip.model.normal`) build on it.
    """
    if delta <= 0.0:
        return 0.0
    m2 = c[EXPONENT]
    if m2 == 2.0:
        return c[AREA_CN] * delta * delta
    if m2 == 1.5:  # Hertz: a square root costs a fraction of a power (within an ulp)
        return c[AREA_CN] * delta * math.sqrt(delta)
    return c[AREA_CN] * delta**m2


@njit(cache=True, error_model="numpy")
def elastic_stiffness(delta, c):
    """d(S c_n δ^m2)/dδ = m2 S c_n δ^(m2-1) [N/m] (0 for δ <= 0)."""
    if delta <= 0.0:
        return 0.0
    m2 = c[EXPONENT]
    if m2 == 2.0:
        return 2.0 * c[AREA_CN] * delta
    if m2 == 1.5:
        return 1.5 * c[AREA_CN] * math.sqrt(delta)
    return m2 * c[AREA_CN] * delta ** (m2 - 1.0)


@njit(cache=True, error_model="numpy")
def contact_side_stiffness(delta, c):
    """The stiffness [N/m] seen from inside the contact: :func:`elastic_stiffness` for
    δ > 0 and, for δ <= 0, its limit as δ -> 0+: S c_n for m2 = 1, 0 for m2 > 1.

    A contact switch is located to just past δ = 0 (δ <= 0 there), and the side still in
    contact needs the law's rate at its end: for m2 = 1 the force leaves with slope
    S c_n δ̇, not 0. For m2 < 1 the limit is infinite; 0 is returned (no polynomial
    follows δ^m2 at δ = 0).
    """
    if delta > 0.0:
        return elastic_stiffness(delta, c)
    if c[EXPONENT] == 1.0:
        return c[AREA_CN]
    return 0.0


def reaction_array(params: Parameters, y: np.ndarray) -> np.ndarray:
    """|R(y)| [N] for an array of normal positions y [m] (NumPy, eq. 2.3)."""
    y = np.asarray(y, dtype=float)
    return params.stiffness_coefficient * np.maximum(y, 0.0) ** params.m2


def normal_reaction(params: Parameters, y: float) -> float:
    """|R(y)| [N] for one normal position y [m], eq. (2.3)."""
    return float(reaction_array(params, np.asarray(y)))


def potential_energy(params: Parameters, y: np.ndarray) -> np.ndarray:
    """V(y) = S c_n max(y,0)^(m2+1)/(m2+1) - m g y [J], the potential of (2.4)."""
    y = np.asarray(y, dtype=float)
    elastic = params.stiffness_coefficient * np.maximum(y, 0.0) ** (params.m2 + 1) / (params.m2 + 1)
    return elastic - params.mass * params.g * y
