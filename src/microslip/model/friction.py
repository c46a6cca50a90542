"""Friction laws at the contact: Coulomb (eq. 2.2), static/kinetic and Stribeck.

Stick is set-valued in every law (true stick, never regularised): the contact transmits
any force up to the static limit μ_s N; sliding at speed |v| transmits μ(|v|) N against
the motion (docs/theory/friction_reduction.md):

    Coulomb        μ_s = μ_k = μ (the paper's ``Parameters.mu``; ``None`` or Coulomb())
    StaticKinetic  μ_s >= μ_k, each constant
    Stribeck       μ(v) = μ_k + (μ_s - μ_k) exp(-(|v| / v_s)^q),  μ(0) = μ_s

N is the composed normal force of :mod:`microslip.model.normal`; the compiled functions
here take N [N] (and its rate) as arguments so that the normal law is evaluated once per
state by :mod:`microslip.model.system`. The laws with their own coefficients make
``Parameters.mu`` unused: the model refuses to change it (it would change nothing).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.coefficients import (
    FRICTION_KIND,
    MU,
    MU_STATIC,
    STRIBECK_EXPONENT,
    STRIBECK_VELOCITY,
    as_tuple,
)
from microslip.model.parameters import FIELD_RANGES, Parameters
from microslip.model.parts import Part, part_field

__all__ = [
    "Coulomb",
    "StaticKinetic",
    "Stribeck",
    "friction_force",
    "friction_limit",
    "friction_limit_rate",
    "kinetic_coefficient",
    "kinetic_coefficient_at_rest",
    "kinetic_coefficients",
]

COULOMB = 0.0
STATIC_KINETIC = 1.0
STRIBECK = 2.0

_MU_LOW, _MU_HIGH = FIELD_RANGES["mu"]


@dataclass(frozen=True)
class Coulomb(Part):
    """Coulomb friction with the coefficient ``Parameters.mu`` (the paper, eq. 2.2).

    Equivalent to ``friction=None``.
    """

    slot: ClassVar[str] = "friction"
    kind: ClassVar[float] = COULOMB
    paper_equivalent: ClassVar[bool] = True

    def pack(self, c: np.ndarray, params: Parameters) -> None:
        c[FRICTION_KIND] = COULOMB


@dataclass(frozen=True)
class _TwoCoefficients(Part):
    """A law with its own static and kinetic coefficients (``Parameters.mu`` unused)."""

    slot: ClassVar[str] = "friction"
    owns_mu: ClassVar[bool] = True
    mu_static: float = part_field(0.15, "1", "static friction coefficient mu_s", _MU_LOW, _MU_HIGH)
    mu_kinetic: float = part_field(0.1, "1", "kinetic friction coefficient mu_k", _MU_LOW, _MU_HIGH)

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.mu_static < self.mu_kinetic:
            raise ValueError(
                f"friction.mu_static={self.mu_static!r} must be >= "
                f"friction.mu_kinetic={self.mu_kinetic!r}"
            )

    def pack(self, c: np.ndarray, params: Parameters) -> None:
        c[FRICTION_KIND] = self.kind
        c[MU] = self.mu_kinetic
        c[MU_STATIC] = self.mu_static


@dataclass(frozen=True)
class StaticKinetic(_TwoCoefficients):
    """Static/kinetic friction: stick up to μ_s N, sliding against μ_k N.

    Attributes
    ----------
    mu_static : float
        Static coefficient μ_s [-], >= ``mu_kinetic``.
    mu_kinetic : float
        Kinetic coefficient μ_k [-].
    """

    kind: ClassVar[float] = STATIC_KINETIC


@dataclass(frozen=True)
class Stribeck(_TwoCoefficients):
    """Stribeck friction μ(v) = μ_k + (μ_s - μ_k) exp(-(|v|/v_s)^q); stick up to μ_s N.

    Needs a rigid tangential contact (a massless contact point under velocity-weakening
    friction has no unique motion).

    Attributes
    ----------
    mu_static, mu_kinetic : float
        μ_s = μ(0) and μ_k = μ(∞) [-], μ_s >= μ_k.
    velocity : float
        Stribeck velocity v_s [m/s] > 0.
    exponent : float
        Shape exponent q [-] in [0.1, 10] (2: Gaussian).
    """

    kind: ClassVar[float] = STRIBECK
    velocity: float = part_field(1e-4, "m s-1", "Stribeck velocity v_s", 1e-300, 1e6)
    exponent: float = part_field(2.0, "1", "Stribeck shape exponent q", 0.1, 10.0)

    def pack(self, c: np.ndarray, params: Parameters) -> None:
        super().pack(c, params)
        c[STRIBECK_VELOCITY] = self.velocity
        c[STRIBECK_EXPONENT] = self.exponent


@njit(cache=True, error_model="numpy")
def friction_limit(normal: float, c: np.ndarray) -> float:
    """Largest friction force the contact transmits in stick, μ_s N [N] (eq. 2.2),
    for the normal force ``normal`` = N >= 0 [N]."""
    return c[MU_STATIC] * normal


@njit(cache=True, error_model="numpy")
def friction_limit_rate(normal_rate: float, c: np.ndarray) -> float:
    """d(μ_s N)/dt [N/s] from dN/dt [N/s] along the motion."""
    return c[MU_STATIC] * normal_rate


@njit(cache=True, error_model="numpy")
def kinetic_coefficient(speed: float, c: np.ndarray) -> float:
    """μ [-] while sliding at ``speed`` = |v| [m/s]: μ_k, or Stribeck's μ(|v|)."""
    if c[FRICTION_KIND] == STRIBECK:
        ratio = abs(speed) / c[STRIBECK_VELOCITY]
        return c[MU] + (c[MU_STATIC] - c[MU]) * math.exp(-(ratio ** c[STRIBECK_EXPONENT]))
    return c[MU]


@njit(cache=True, error_model="numpy")
def kinetic_coefficient_at_rest(c: np.ndarray) -> float:
    """μ [-] of :func:`kinetic_coefficient` at speed 0, with the same bits: μ_k, or
    Stribeck's μ(0) = μ_k + (μ_s - μ_k) (its factor exp(-0) is exactly 1).

    The kinetic limit of a compliant contact point, which starts and ends its slips at
    rest. Written without the Stribeck law's power and exponential: called with the
    constant speed 0 inside a step's loop, those were loop-invariant, and LLVM hoisted
    the (speculatable) calls out of the loop, so every RK4 step paid a pow and an exp
    whatever the friction law (~5% of a Hertz Mindlin time map with flights)."""
    if c[FRICTION_KIND] == STRIBECK:
        return c[MU] + (c[MU_STATIC] - c[MU])
    return c[MU]


@njit(cache=True)
def kinetic_coefficients(speeds: np.ndarray, c: np.ndarray) -> np.ndarray:
    """μ [-] at each sliding speed of ``speeds`` [m/s] (:func:`kinetic_coefficient` in a
    compiled loop: a map's velocity axis costs one call, not one per speed)."""
    laws = as_tuple(c)
    out = np.empty(speeds.shape[0])
    for i in range(speeds.shape[0]):
        out[i] = kinetic_coefficient(speeds[i], laws)
    return out


def friction_force(direction: np.ndarray, limit: np.ndarray, drive: np.ndarray) -> np.ndarray:
    """Friction force F_t [N] acting on a rigid-contact slider, signed as in (2.5):
    m ẍ = F + F_t.

    Sliding: F_t = -μN sgn ẋ (``limit`` = μN); stick: F_t = -F (static equilibrium, the
    paper's F_tr).
    """
    direction = np.asarray(direction, dtype=float)
    return np.where(direction != 0.0, -direction * limit, -np.asarray(drive, dtype=float))
