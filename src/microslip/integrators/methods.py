"""The step methods by code, and one dispatcher used by every loop and root finder."""

from __future__ import annotations

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators.dop853 import dop853_step
from microslip.integrators.steppers import WORK_ROWS, rk4_graded_step, rk4_step

__all__ = ["CONTROLLER_EXPONENT", "DOP853", "RK4", "RK4_GRADED", "WORK_ROWS", "advance"]

# NumPy integers, not Python ones: numba types a module-level int passed to a jitted
# function as a literal and compiles the callee once per value (docs/design.md).
RK4 = np.int64(0)  # classical Runge–Kutta, fixed step (the paper's method)
DOP853 = np.int64(1)  # Dormand–Prince 8(5,3), adaptive: the "event" method
# RK4 on sub-steps graded towards the step end: how a fixed-step loop reaches a switch
# whose function the model grades (model.switching_functions.graded_switch).
RK4_GRADED = np.int64(2)

# Exponent of the step-size controller, -1/(order of the error estimate + 1).
CONTROLLER_EXPONENT = (0.0, -1.0 / 8.0, 0.0)


@njit(cache=True)
def advance(method, s, t, h, mode, c, rtol, atol, out, work):
    """One step of the chosen method from (t, s) into ``out``; returns the error norm
    (0 for RK4).

    ``s`` and ``out`` are distinct float64 state arrays of the same size, ``work`` the
    steps' scratch, a C-contiguous 2-D array of at least WORK_ROWS rows of that size;
    ``mode`` is the model's, ``c`` its coefficient vector (an array, or a tuple:
    :func:`microslip.integrators.kernel.as_tuple`). ``rtol`` [1] and ``atol`` (one per
    state variable, in its units) scale the error norm of the adaptive methods.
    """
    if method == RK4:
        rk4_step(s, t, h, mode, c, out, work)
        return 0.0
    if method == RK4_GRADED:
        rk4_graded_step(s, t, h, mode, c, out, work)
        return 0.0
    return dop853_step(s, t, h, mode, c, rtol, atol, out, work)
