"""Layout of the flat coefficient vector handed to the compiled kernels.

Compiled kernels take the whole model as one float64 array so that a single cached
compilation serves every parameter set and every composition of parts. Each law reads
its own slots; the kind slots select the law of a part at run time (a branch on a
loop-invariant value, so the compiled loops unswitch it). A new law appends its slots
here and writes them in its own ``pack``; no integrator signature changes.
See docs/design.md for the parts and the state layout.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numba.np.unsafe.ndarray import to_fixed_tuple

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.parameters import Parameters

MASS = 0  # m [kg]
GRAVITY = 1  # g [m/s^2]
AREA_CN = 2  # S c_n [N/m^m2]
EXPONENT = 3  # m2 [-]
MU = 4  # kinetic friction coefficient μ_k [-] (Coulomb: the paper's μ, eq. 2.2)
FORCE = 5  # constant tangential drive F [N] (harmonic drive: its mean F0)
STATIC_DEFLECTION = 6  # y0 [m] (derived; scale of the gap switching function)
DAMPING_KIND = 7  # microslip.model.damping: NONE, VISCOUS, HUNT_CROSSLEY
DAMPING_COEFFICIENT = 8  # c [N s/m], c = 2 ζ sqrt(K_n m)
EXCITATION_KIND = 9  # microslip.model.excitation: NONE, HARMONIC_FORCE, BASE_MOTION, PRESCRIBED
EXCITATION_AMPLITUDE = 10  # P0 [N], Z [m] or Δ [m], per kind
EXCITATION_OMEGA = 11  # ω = 2π f [rad/s]
EXCITATION_MEAN = 12  # δ_m [m] (prescribed penetration)
TANGENTIAL_KIND = 13  # microslip.model.tangential: RIGID, SPRING, MINDLIN
TANGENTIAL_STIFFNESS = 14  # k_t [N/m] (spring) or the ratio λ [-] of k_t = λ dN/dδ (Mindlin)
FRICTION_KIND = 15  # microslip.model.friction: COULOMB, STATIC_KINETIC, STRIBECK
MU_STATIC = 16  # static friction coefficient μ_s [-] (Coulomb: μ)
STRIBECK_VELOCITY = 17  # v_s [m/s]
STRIBECK_EXPONENT = 18  # q [-]
DRIVE_KIND = 19  # microslip.model.drive: CONSTANT, HARMONIC, SPRING, KINEMATIC
DRIVE_AMPLITUDE = 20  # F1 [N] (harmonic) or k_d [N/m] (spring)
DRIVE_VELOCITY = 21  # v_d [m/s] (spring) or the body velocity v [m/s] (kinematic)
DRIVE_OMEGA = 22  # ω_d = 2π f_d [rad/s] (harmonic)
SIZE = 23


def pack(params: Parameters, force: float) -> np.ndarray:
    """The coefficient vector of the paper's model (no damping, no excitation) for
    ``params`` driven by a constant force ``force`` [N]. Parts write their own slots
    on top of this (:meth:`microslip.model.composition.Model.pack`)."""
    c = np.zeros(SIZE)
    c[MASS] = params.mass
    c[GRAVITY] = params.g
    c[AREA_CN] = params.stiffness_coefficient
    c[EXPONENT] = params.m2
    c[MU] = params.mu
    c[MU_STATIC] = params.mu
    c[FORCE] = force
    c[STATIC_DEFLECTION] = params.static_deflection
    return c


@njit(cache=True)
def as_tuple(c):
    """The coefficient vector ``c`` as a tuple of SIZE floats, the form every law takes:
    a tuple goes by value through compiled calls, where an array is reference-counted at
    each one, and a law compiled for one form is not compiled again for the other
    (docs/design.md, "Compile time")."""
    return to_fixed_tuple(c, SIZE)
