"""Normal excitation of the contact (docs/design.md; the paper's Sec. 5 outlook).

Signs: y is positive downward (into the slideway), N >= 0 compressive; the normal
equation is m ÿ = m g + P(t) - N(δ, δ̇) with the penetration δ = y - z(t).

    HarmonicForce          P(t) = P0 sin(2π f t) on the body, positive downward
    BaseMotion             z(t) = Z sin(2π f t), the slideway surface moves
    PrescribedPenetration  δ(t) = δ_m + Δ cos(2π f t): the normal degree of freedom is
                           removed and N follows from the contact law (with m2 = 1,
                           N = N0 (1 + β cos 2π f t), β = Δ/δ_m)

``None`` is the paper's free vibration. Frequencies are in Hz and must lie within
[1e-3 f0, 1e3 f0] of the contact's natural frequency f0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.coefficients import (
    EXCITATION_AMPLITUDE,
    EXCITATION_KIND,
    EXCITATION_MEAN,
    EXCITATION_OMEGA,
)
from microslip.model.parameters import AMPLITUDE_LIMIT_FACTOR, FORCE_LIMIT_FACTOR, Parameters
from microslip.model.parts import Part, angular, part_field, relative_range

__all__ = [
    "BaseMotion",
    "HarmonicForce",
    "PrescribedPenetration",
    "applied_force",
    "applied_force_rate",
    "is_prescribed",
    "prescribed_gap",
    "surface_motion",
]

NONE = 0.0
HARMONIC_FORCE = 1.0
BASE_MOTION = 2.0
PRESCRIBED = 3.0

FREQUENCY_FACTOR = 1e3  # f within [f0 / 1e3, 1e3 f0]
_INF = math.inf


class _Harmonic(Part):
    """Shared by the excitations: a frequency f [Hz] within [1e-3 f0, 1e3 f0]."""

    slot: ClassVar[str] = "excitation"
    frequency: float

    @property
    def period(self) -> float:
        """Excitation period 1/f [s]."""
        return 1.0 / self.frequency

    def check(self, params: Parameters) -> None:
        f0 = params.natural_frequency
        relative_range(
            "excitation.frequency", self.frequency, "Hz", f0 / FREQUENCY_FACTOR,
            f0 * FREQUENCY_FACTOR, f"1e-3 f0 to 1e3 f0, f0 = {f0:.6g} Hz",
        )  # fmt: skip
        self._check_amplitudes(params)

    def _check_amplitudes(self, params: Parameters) -> None:
        raise NotImplementedError


def _check_length(name: str, value: float, params: Parameters, low: float = 0.0) -> None:
    limit = AMPLITUDE_LIMIT_FACTOR * params.static_deflection
    what = f"at most 1e3 y0, y0 = {params.static_deflection:.6g} m"
    relative_range(name, value, "m", low, limit, what)


@dataclass(frozen=True)
class HarmonicForce(_Harmonic):
    """Harmonic normal force on the body, P(t) = P0 sin(2π f t), positive downward.

    Attributes
    ----------
    amplitude : float
        P0 [N], 0 <= P0 <= 1e6 m g.
    frequency : float
        f [Hz] in [1e-3 f0, 1e3 f0].
    """

    kind: ClassVar[float] = HARMONIC_FORCE
    amplitude: float = part_field(0.0, "N", "force amplitude P0", 0.0, _INF)
    frequency: float = part_field(1000.0, "Hz", "excitation frequency f", 0.0, _INF)

    def _check_amplitudes(self, params: Parameters) -> None:
        limit = FORCE_LIMIT_FACTOR * params.mass * params.g
        relative_range("excitation.amplitude", self.amplitude, "N", 0.0, limit, "at most 1e6 m g")

    def pack(self, c: np.ndarray, params: Parameters) -> None:
        c[EXCITATION_KIND] = self.kind
        c[EXCITATION_AMPLITUDE] = self.amplitude
        c[EXCITATION_OMEGA] = angular(self.frequency)


@dataclass(frozen=True)
class BaseMotion(_Harmonic):
    """Harmonic motion of the slideway surface, z(t) = Z sin(2π f t), positive downward.

    Attributes
    ----------
    amplitude : float
        Z [m], 0 <= Z <= 1e3 y0.
    frequency : float
        f [Hz] in [1e-3 f0, 1e3 f0].
    """

    kind: ClassVar[float] = BASE_MOTION
    amplitude: float = part_field(0.0, "m", "surface displacement amplitude Z", 0.0, _INF)
    frequency: float = part_field(1000.0, "Hz", "excitation frequency f", 0.0, _INF)

    def _check_amplitudes(self, params: Parameters) -> None:
        _check_length("excitation.amplitude", self.amplitude, params)

    def pack(self, c: np.ndarray, params: Parameters) -> None:
        c[EXCITATION_KIND] = self.kind
        c[EXCITATION_AMPLITUDE] = self.amplitude
        c[EXCITATION_OMEGA] = angular(self.frequency)


@dataclass(frozen=True)
class PrescribedPenetration(_Harmonic):
    """Prescribed penetration δ(t) = δ_m + Δ cos(2π f t); the normal motion is kinematic.

    Attributes
    ----------
    mean : float
        δ_m [m], 0 < δ_m <= 1e3 y0.
    amplitude : float
        Δ [m], 0 <= Δ <= 1e3 y0; Δ > δ_m means a loss of contact in every period.
    frequency : float
        f [Hz] in [1e-3 f0, 1e3 f0].
    """

    kind: ClassVar[float] = PRESCRIBED
    mean: float = part_field(1e-7, "m", "mean penetration delta_m", 0.0, _INF)
    amplitude: float = part_field(0.0, "m", "penetration amplitude Delta", 0.0, _INF)
    frequency: float = part_field(1000.0, "Hz", "excitation frequency f", 0.0, _INF)

    def _check_amplitudes(self, params: Parameters) -> None:
        if self.mean <= 0.0:
            raise ValueError(f"excitation.mean must be > 0 [m], got {self.mean!r}")
        _check_length("excitation.mean", self.mean, params)
        _check_length("excitation.amplitude", self.amplitude, params)

    def pack(self, c: np.ndarray, params: Parameters) -> None:
        c[EXCITATION_KIND] = self.kind
        c[EXCITATION_AMPLITUDE] = self.amplitude
        c[EXCITATION_OMEGA] = angular(self.frequency)
        c[EXCITATION_MEAN] = self.mean


@njit(cache=True, error_model="numpy")
def is_prescribed(c):
    """True when the penetration δ(t) is prescribed (no normal degree of freedom)."""
    return c[EXCITATION_KIND] == PRESCRIBED


@njit(cache=True, error_model="numpy")
def applied_force(t, c):
    """P(t) [N] on the body, positive downward (0 unless a harmonic force)."""
    if c[EXCITATION_KIND] == HARMONIC_FORCE:
        return c[EXCITATION_AMPLITUDE] * math.sin(c[EXCITATION_OMEGA] * t)
    return 0.0


@njit(cache=True, error_model="numpy")
def applied_force_rate(t, c):
    """dP/dt [N/s]."""
    if c[EXCITATION_KIND] == HARMONIC_FORCE:
        w = c[EXCITATION_OMEGA]
        return c[EXCITATION_AMPLITUDE] * w * math.cos(w * t)
    return 0.0


@njit(cache=True, error_model="numpy")
def surface_motion(t, c):
    """(z [m], ż [m/s], z̈ [m/s^2]) of the slideway surface (0 unless base motion)."""
    if c[EXCITATION_KIND] == BASE_MOTION:
        w = c[EXCITATION_OMEGA]
        z = c[EXCITATION_AMPLITUDE]
        s = math.sin(w * t)
        return z * s, z * w * math.cos(w * t), -z * w * w * s
    return 0.0, 0.0, 0.0


@njit(cache=True, error_model="numpy")
def prescribed_gap(t, c):
    """(δ [m], δ̇ [m/s], δ̈ [m/s^2]) of the prescribed penetration δ_m + Δ cos ωt."""
    w = c[EXCITATION_OMEGA]
    d = c[EXCITATION_AMPLITUDE]
    cos = math.cos(w * t)
    return c[EXCITATION_MEAN] + d * cos, -d * w * math.sin(w * t), -d * w * w * cos
