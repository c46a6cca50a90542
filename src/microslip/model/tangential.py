"""Tangential contact: rigid (the paper) or a compliant massless contact point
(docs/theory/friction_reduction.md, docs/design.md).

Rigid (``None`` or :class:`Rigid`): the friction force acts on the body directly
(eqs. 2.2, 2.5). Compliant: a massless contact point at u is joined to the body at x by
a tangential spring; the spring force f [N] (positive when it holds the body back from
+x) acts on the body as -f. The contact point sticks (u̇ = 0, ḟ = k_t ẋ) while
|f| <= μ_s N and slides with f = μ_k N sgn u̇ otherwise; on loss of contact the spring is
relaxed (f = 0, u̇ = ẋ). Its stiffness is

    TangentialSpring   k_t constant [N/m]
    MindlinSpring      k_t = λ dN/dδ (Mindlin 1949: the tangential stiffness follows the
                       normal contact stiffness; λ = 2(1 - ν)/(2 - ν) for elastic spheres),
                       with the incremental law df = k_t(N) d(x - u) while stuck.

The compiled law is :func:`tangential_stiffness`; :mod:`microslip.model.system` uses it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.coefficients import EXPONENT, TANGENTIAL_KIND, TANGENTIAL_STIFFNESS
from microslip.model.contact import elastic_stiffness
from microslip.model.parameters import Parameters
from microslip.model.parts import Part, part_field, relative_range

__all__ = [
    "MindlinSpring",
    "Rigid",
    "TangentialSpring",
    "is_compliant",
    "stiffness_rough_at_touch",
    "tangential_stiffness",
]

RIGID = 0.0
SPRING = 1.0
MINDLIN = 2.0

STIFFNESS_FACTOR = 1e6  # k_t within [1e-6 K_n, 1e6 K_n]


@dataclass(frozen=True)
class Rigid(Part):
    """Rigid tangential contact (the paper): friction acts on the body directly.

    Equivalent to ``tangential=None``.
    """

    slot: ClassVar[str] = "tangential"
    kind: ClassVar[float] = RIGID
    paper_equivalent: ClassVar[bool] = True

    def pack(self, c: np.ndarray, params: Parameters) -> None:
        c[TANGENTIAL_KIND] = RIGID


@dataclass(frozen=True)
class TangentialSpring(Part):
    """Compliant tangential contact of constant stiffness.

    Attributes
    ----------
    stiffness : float
        Tangential contact stiffness k_t [N/m], in [1e-6 K_n, 1e6 K_n] (K_n the normal
        contact stiffness at the static deflection).
    """

    slot: ClassVar[str] = "tangential"
    kind: ClassVar[float] = SPRING
    stiffness: float = part_field(1e7, "N m-1", "tangential contact stiffness k_t", 0.0, np.inf)

    def check(self, params: Parameters) -> None:
        k_n = params.contact_stiffness
        relative_range(
            "tangential.stiffness", self.stiffness, "N m-1", k_n / STIFFNESS_FACTOR,
            k_n * STIFFNESS_FACTOR, f"1e-6 K_n to 1e6 K_n, K_n = {k_n:.6g} N m-1",
        )  # fmt: skip

    def pack(self, c: np.ndarray, params: Parameters) -> None:
        c[TANGENTIAL_KIND] = SPRING
        c[TANGENTIAL_STIFFNESS] = self.stiffness


@dataclass(frozen=True)
class MindlinSpring(Part):
    """Compliant tangential contact whose stiffness follows the normal one (Mindlin).

    k_t = λ dN/dδ [N/m], with dN/dδ = m2 S c_n δ^(m2-1) the stiffness of the elastic
    contact law (2.3); k_t = 0 out of contact.

    Attributes
    ----------
    ratio : float
        λ [-] in [1e-3, 10]; 2(1 - ν)/(2 - ν) for elastic spheres of Poisson ratio ν
        (0.8235 for ν = 0.3).
    """

    slot: ClassVar[str] = "tangential"
    kind: ClassVar[float] = MINDLIN
    ratio: float = part_field(0.8235, "1", "ratio lambda of k_t = lambda dN/ddelta", 1e-3, 10.0)

    def pack(self, c: np.ndarray, params: Parameters) -> None:
        c[TANGENTIAL_KIND] = MINDLIN
        c[TANGENTIAL_STIFFNESS] = self.ratio


@njit(cache=True, error_model="numpy")
def is_compliant(c):
    """True with a compliant tangential contact (a contact point and a spring)."""
    return c[TANGENTIAL_KIND] != RIGID


# Above this contact exponent a Mindlin stiffness ∝ δ^(m2-1) has the three bounded
# derivatives at δ = 0+ that a 4th-order step needs of a rate.
SMOOTH_MINDLIN_EXPONENT = 4.0


@njit(cache=True)
def stiffness_rough_at_touch(c):
    """True when k_t has a corner of fractional order at δ = 0+: a Mindlin stiffness
    λ dN/dδ ∝ δ^(m2-1) with m2 not an integer and below 4, so that a derivative of
    order 3 or less is unbounded there. A point that sticks from a touchdown then loads
    at a rate ∝ δ^(m2-1) (singular for m2 < 2; docs/theory/numerics.md, "Order at a
    touchdown")."""
    m2 = c[EXPONENT]
    return c[TANGENTIAL_KIND] == MINDLIN and m2 < SMOOTH_MINDLIN_EXPONENT and m2 != np.floor(m2)


@njit(cache=True, error_model="numpy")
def tangential_stiffness(delta, c):
    """k_t [N/m] at the penetration ``delta`` = δ [m] (0 out of contact, δ <= 0)."""
    if delta <= 0.0:
        return 0.0
    if c[TANGENTIAL_KIND] == MINDLIN:
        return c[TANGENTIAL_STIFFNESS] * elastic_stiffness(delta, c)
    return c[TANGENTIAL_STIFFNESS]
