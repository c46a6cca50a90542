"""Layout of the flat coefficient vector handed to the compiled kernels.

Compiled kernels take the model as one float64 array so that a single cached
compilation serves every parameter set. Each law reads its own slots; a new law
appends slots here instead of changing integrator signatures.
"""

from __future__ import annotations

import numpy as np

from microslip.model.parameters import Parameters

MASS = 0  # m [kg]
GRAVITY = 1  # g [m/s^2]
AREA_CN = 2  # S c_n [N/m^m2]
EXPONENT = 3  # m2 [-]
MU = 4  # μ [-]
FORCE = 5  # constant tangential drive F [N]
SIZE = 6


def pack(params: Parameters, force: float) -> np.ndarray:
    """The coefficient vector for ``params`` driven by a constant force ``force`` [N]."""
    c = np.empty(SIZE)
    c[MASS] = params.mass
    c[GRAVITY] = params.g
    c[AREA_CN] = params.stiffness_coefficient
    c[EXPONENT] = params.m2
    c[MU] = params.mu
    c[FORCE] = force
    return c
