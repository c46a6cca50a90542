"""Normal damping of the contact: Kelvin–Voigt and Hunt–Crossley (docs/design.md).

Both laws take the damping ratio ζ at the working point, c = 2 ζ sqrt(K_n m) with
K_n = m2 m g / y0, so that linearised about the static deflection they agree:

    Kelvin–Voigt   N_raw = S c_n δ^m2 + c δ̇              (force jump c δ̇ at touchdown)
    Hunt–Crossley  N_raw = S c_n δ^m2 (1 + c δ̇ / (m g))   (no jump at touchdown)

The contact force is N = max(0, N_raw) while δ > 0 and 0 otherwise (no adhesion):
the body separates where N_raw falls to 0, also while δ > 0. ``None`` (no damping) is
the paper's elastic law (2.3).

The compiled functions take the elastic force S c_n δ^m2 and its stiffness
m2 S c_n δ^(m2-1) from :mod:`microslip.model.contact` so that the power law is
written once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.coefficients import DAMPING_COEFFICIENT, DAMPING_KIND, GRAVITY, MASS
from microslip.model.parameters import Parameters
from microslip.model.parts import Part, part_field

__all__ = ["HuntCrossley", "Viscous", "damped_force", "damped_force_partials"]

NONE = 0.0
VISCOUS = 1.0
HUNT_CROSSLEY = 2.0

MAX_RATIO = 10.0  # ζ: far past critical damping (ζ = 1) of the linearised contact


def damping_coefficient(params: Parameters, ratio: float) -> float:
    """c = 2 ζ sqrt(K_n m) [N s/m] for the damping ratio ζ at the working point."""
    return 2.0 * ratio * math.sqrt(params.contact_stiffness * params.mass)


@dataclass(frozen=True)
class _RatioDamping(Part):
    """A damping law set by its damping ratio ζ at the working point."""

    slot: ClassVar[str] = "damping"
    kind: ClassVar[float]
    ratio: float = part_field(0.0, "1", "damping ratio zeta at the working point", 0.0, MAX_RATIO)

    def pack(self, c: np.ndarray, params: Parameters) -> None:
        c[DAMPING_KIND] = self.kind
        c[DAMPING_COEFFICIENT] = damping_coefficient(params, self.ratio)


@dataclass(frozen=True)
class Viscous(_RatioDamping):
    """Kelvin–Voigt damping, N = S c_n δ^m2 + c δ̇ (clipped at 0).

    Attributes
    ----------
    ratio : float
        Damping ratio ζ [-] of the contact linearised at the static deflection,
        c = 2 ζ sqrt(K_n m); in [0, 10].
    """

    kind: ClassVar[float] = VISCOUS


@dataclass(frozen=True)
class HuntCrossley(_RatioDamping):
    """Hunt–Crossley damping, N = S c_n δ^m2 (1 + c δ̇ / (m g)) (clipped at 0).

    Attributes
    ----------
    ratio : float
        Damping ratio ζ [-] of the contact linearised at the static deflection,
        c = 2 ζ sqrt(K_n m); in [0, 10].
    """

    kind: ClassVar[float] = HUNT_CROSSLEY


@njit(cache=True, error_model="numpy")
def damped_force(elastic, gap_rate, c):
    """Unclipped N_raw [N] from the elastic force S c_n δ^m2 [N] and δ̇ [m/s]."""
    kind = c[DAMPING_KIND]
    if kind == VISCOUS:
        return elastic + c[DAMPING_COEFFICIENT] * gap_rate
    if kind == HUNT_CROSSLEY:
        return elastic * (1.0 + c[DAMPING_COEFFICIENT] * gap_rate / (c[MASS] * c[GRAVITY]))
    return elastic


@njit(cache=True, error_model="numpy")
def damped_force_partials(elastic, stiffness, gap_rate, c):
    """(∂N_raw/∂δ [N/m], ∂N_raw/∂δ̇ [N s/m]) given the elastic force and its stiffness."""
    kind = c[DAMPING_KIND]
    if kind == VISCOUS:
        return stiffness, c[DAMPING_COEFFICIENT]
    if kind == HUNT_CROSSLEY:
        scale = c[DAMPING_COEFFICIENT] / (c[MASS] * c[GRAVITY])
        return stiffness * (1.0 + scale * gap_rate), elastic * scale
    return stiffness, 0.0


@njit(cache=True, error_model="numpy")
def can_separate_in_overlap(c):
    """True when N_raw can fall to 0 while δ > 0 (any damping with c > 0)."""
    return c[DAMPING_KIND] != NONE and c[DAMPING_COEFFICIENT] > 0.0
