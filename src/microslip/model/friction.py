"""Tangential laws: the Coulomb friction law (2.2) and the constant drive force of Sec. 4.

The friction limit is μN with N the composed normal force of
:mod:`microslip.model.normal` (the paper's |R| of eq. 2.3 when there is no damping and
no excitation); the compiled functions here take N [N] and its rate as arguments so
that the normal law is evaluated once per state by :mod:`microslip.model.system`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.coefficients import FORCE, MASS, MU

__all__ = [
    "drive_force",
    "drive_force_rate",
    "friction_force",
    "friction_limit",
    "friction_limit_rate",
    "slip_acceleration",
]


@njit(cache=True, inline="always")
def drive_force(t: float, c: np.ndarray) -> float:
    """Tangential drive F(t) [N]; here the paper's constant force (Sec. 4)."""
    return c[FORCE]


@njit(cache=True, inline="always")
def drive_force_rate(t: float, c: np.ndarray) -> float:
    """dF/dt [N/s]; zero for the constant drive."""
    return 0.0


@njit(cache=True, inline="always")
def friction_limit(normal: float, c: np.ndarray) -> float:
    """Largest friction force the contact can transmit, μN [N], eq. (2.2), for the
    normal force ``normal`` = N >= 0 [N]."""
    return c[MU] * normal


@njit(cache=True, inline="always")
def friction_limit_rate(normal_rate: float, c: np.ndarray) -> float:
    """d(μN)/dt [N/s] from dN/dt [N/s] along the motion."""
    return c[MU] * normal_rate


@njit(cache=True, inline="always")
def slip_acceleration(normal: float, t: float, direction: float, c: np.ndarray) -> float:
    """ẍ [m/s^2] while sliding in ``direction`` = sgn ẋ (±1), eqs. (2.2) and (2.5).

    m ẍ = F + F_t with F_t = -μN sgn ẋ. ``direction`` = 0 means stick: ẍ = 0.
    """
    if direction == 0.0:
        return 0.0
    return (drive_force(t, c) - direction * friction_limit(normal, c)) / c[MASS]


def friction_force(direction: np.ndarray, limit: np.ndarray, drive: np.ndarray) -> np.ndarray:
    """Friction force F_t [N] acting on the slider, signed as in (2.5): m ẍ = F + F_t.

    Sliding: F_t = -μN sgn ẋ. Stick: F_t = -F (static equilibrium, the paper's F_tr).
    """
    direction = np.asarray(direction, dtype=float)
    return np.where(direction != 0.0, -direction * limit, -np.asarray(drive, dtype=float))
