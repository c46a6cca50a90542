"""The step methods by code, and one dispatcher used by every loop and root finder."""

from __future__ import annotations

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators.dop853 import dop853_step
from microslip.integrators.steppers import dp54_step, rk4_step

RK4 = 0  # classical Runge–Kutta, fixed step (the paper's method)
DP54 = 1  # Dormand–Prince 5(4), adaptive (also the orbit tables' fixed-step 5th order)
DOP853 = 2  # Dormand–Prince 8(5,3), adaptive: the "event" method

# Exponent of the step-size controller, -1/(order of the error estimate + 1).
CONTROLLER_EXPONENT = (0.0, -1.0 / 5.0, -1.0 / 8.0)


@njit(cache=True)
def advance(method, s, t, h, direction, c, rtol, atol):
    """One step of the chosen method; returns (state, error norm; 0 for RK4)."""
    if method == RK4:
        return rk4_step(s, t, h, direction, c), 0.0
    if method == DP54:
        return dp54_step(s, t, h, direction, c, rtol, atol)
    return dop853_step(s, t, h, direction, c, rtol, atol)
