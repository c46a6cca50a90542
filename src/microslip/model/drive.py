"""Tangential drives of the body (docs/theory/stick_slip_drive.md).

    ConstantForce       F (the paper, Sec. 4; ``None``: the force is given per call)
    HarmonicDrive       F(t) = F0 + F1 sin(2π f_d t): sign-changing, backward sliding
    SpringDrive         F = k_d (v_d t - x): a spring whose far end moves at v_d
    PrescribedVelocity  x = v t (kinematic): the output is the force the contact
                        transmits and the effective friction coefficient <F_t>/<N>

Forces are on the body, positive towards +x. The compiled laws are :func:`drive_force`
and :func:`drive_force_rate`; :mod:`microslip.model.system` composes them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.coefficients import (
    DRIVE_AMPLITUDE,
    DRIVE_KIND,
    DRIVE_OMEGA,
    DRIVE_VELOCITY,
    FORCE,
)
from microslip.model.parameters import Parameters
from microslip.model.parts import Part, angular, part_field, relative_range

__all__ = [
    "ConstantForce",
    "HarmonicDrive",
    "PrescribedVelocity",
    "SpringDrive",
    "drive_force",
    "drive_force_rate",
    "is_kinematic",
]

CONSTANT = 0.0
HARMONIC = 1.0
SPRING = 2.0
KINEMATIC = 3.0

FREQUENCY_FACTOR = 1e3  # drive frequency within [1e-3 f0, 1e3 f0]
STIFFNESS_FACTOR = 1e6  # drive stiffness within [1e-6 K_n, 1e6 K_n]
_INF = math.inf


def _check_force(name: str, value: float, params: Parameters) -> None:
    limit = params.max_force
    relative_range(name, value, "N", -limit, limit, f"|F| <= 1e6 m g = {limit:.6g} N")


def _check_velocity(name: str, value: float, params: Parameters) -> None:
    limit = params.max_velocity
    relative_range(name, value, "m s-1", -limit, limit, f"|v| <= 1e6 g T0 = {limit:.6g} m s-1")


@dataclass(frozen=True)
class ConstantForce(Part):
    """A constant tangential force on the body (the paper, Sec. 4).

    With ``drive=None`` the force is given to each analysis (``force=``); with
    ConstantForce it is part of the model and those arguments must be left out.

    Attributes
    ----------
    force : float
        F [N], |F| <= 1e6 m g; negative pushes towards -x.
    """

    slot: ClassVar[str] = "drive"
    kind: ClassVar[float] = CONSTANT
    force: float = part_field(0.0, "N", "constant tangential force F", -_INF, _INF)

    def check(self, params: Parameters) -> None:
        _check_force("drive.force", self.force, params)

    def pack(self, c: np.ndarray, params: Parameters) -> None:
        c[DRIVE_KIND] = CONSTANT
        c[FORCE] = self.force


@dataclass(frozen=True)
class HarmonicDrive(Part):
    """Harmonic tangential force F(t) = F0 + F1 sin(2π f_d t) on the body.

    Attributes
    ----------
    mean : float
        F0 [N], |F0| <= 1e6 m g.
    amplitude : float
        F1 [N] >= 0, F1 <= 1e6 m g.
    frequency : float
        f_d [Hz] in [1e-3 f0, 1e3 f0].
    """

    slot: ClassVar[str] = "drive"
    kind: ClassVar[float] = HARMONIC
    mean: float = part_field(0.0, "N", "mean tangential force F0", -_INF, _INF)
    amplitude: float = part_field(0.0, "N", "tangential force amplitude F1", 0.0, _INF)
    frequency: float = part_field(100.0, "Hz", "drive frequency f_d", 0.0, _INF)

    def check(self, params: Parameters) -> None:
        _check_force("drive.mean", self.mean, params)
        _check_force("drive.amplitude", self.amplitude, params)
        f0 = params.natural_frequency
        relative_range(
            "drive.frequency", self.frequency, "Hz", f0 / FREQUENCY_FACTOR,
            f0 * FREQUENCY_FACTOR, f"1e-3 f0 to 1e3 f0, f0 = {f0:.6g} Hz",
        )  # fmt: skip

    def pack(self, c: np.ndarray, params: Parameters) -> None:
        c[DRIVE_KIND] = HARMONIC
        c[FORCE] = self.mean
        c[DRIVE_AMPLITUDE] = self.amplitude
        c[DRIVE_OMEGA] = angular(self.frequency)


@dataclass(frozen=True)
class SpringDrive(Part):
    """A drive spring k_d whose far end moves at v_d: F = k_d (v_d t - x) on the body
    (relaxed at t = 0, x = 0).

    Attributes
    ----------
    stiffness : float
        k_d [N/m] in [1e-6 K_n, 1e6 K_n].
    velocity : float
        v_d [m/s], |v_d| <= 1e6 g T0.
    """

    slot: ClassVar[str] = "drive"
    kind: ClassVar[float] = SPRING
    stiffness: float = part_field(1e5, "N m-1", "drive spring stiffness k_d", 0.0, _INF)
    velocity: float = part_field(1e-4, "m s-1", "drive velocity v_d", -_INF, _INF)

    def check(self, params: Parameters) -> None:
        k_n = params.contact_stiffness
        relative_range(
            "drive.stiffness", self.stiffness, "N m-1", k_n / STIFFNESS_FACTOR,
            k_n * STIFFNESS_FACTOR, f"1e-6 K_n to 1e6 K_n, K_n = {k_n:.6g} N m-1",
        )  # fmt: skip
        _check_velocity("drive.velocity", self.velocity, params)

    def pack(self, c: np.ndarray, params: Parameters) -> None:
        c[DRIVE_KIND] = SPRING
        c[DRIVE_AMPLITUDE] = self.stiffness
        c[DRIVE_VELOCITY] = self.velocity


@dataclass(frozen=True)
class PrescribedVelocity(Part):
    """Kinematic drive: the body moves at x = v t (ẋ = v); the contact's friction force
    is the output.

    Attributes
    ----------
    velocity : float
        v [m/s], |v| <= 1e6 g T0.
    """

    slot: ClassVar[str] = "drive"
    kind: ClassVar[float] = KINEMATIC
    velocity: float = part_field(1e-4, "m s-1", "prescribed body velocity v", -_INF, _INF)

    def check(self, params: Parameters) -> None:
        _check_velocity("drive.velocity", self.velocity, params)

    def pack(self, c: np.ndarray, params: Parameters) -> None:
        c[DRIVE_KIND] = KINEMATIC
        c[DRIVE_VELOCITY] = self.velocity


@njit(cache=True, error_model="numpy")
def is_kinematic(c):
    """True with a prescribed body velocity (:class:`PrescribedVelocity`)."""
    return c[DRIVE_KIND] == KINEMATIC


@njit(cache=True, error_model="numpy")
def drive_force(t, x, c):
    """Tangential drive force F(t, x) [N] on the body at time t [s], position x [m];
    0 for the kinematic drive (the body's motion is prescribed)."""
    kind = c[DRIVE_KIND]
    if kind == CONSTANT:
        return c[FORCE]
    if kind == HARMONIC:
        return c[FORCE] + c[DRIVE_AMPLITUDE] * math.sin(c[DRIVE_OMEGA] * t)
    if kind == SPRING:
        return c[DRIVE_AMPLITUDE] * (c[DRIVE_VELOCITY] * t - x)
    return 0.0


@njit(cache=True, error_model="numpy")
def drive_force_rate(t, x, xdot, c):
    """dF/dt [N/s] along the motion (body velocity ``xdot`` [m/s])."""
    kind = c[DRIVE_KIND]
    if kind == HARMONIC:
        return c[DRIVE_AMPLITUDE] * c[DRIVE_OMEGA] * math.cos(c[DRIVE_OMEGA] * t)
    if kind == SPRING:
        return c[DRIVE_AMPLITUDE] * (c[DRIVE_VELOCITY] - xdot)
    return 0.0
