"""The step methods by code, and one dispatcher used by every loop and root finder."""

from __future__ import annotations

import numpy as np
from numba import njit
from numba.core import types
from numba.extending import overload

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators.dop853 import dop853_step
from microslip.integrators.steppers import WORK_ROWS, dp54_step, rk4_step

__all__ = ["CONTROLLER_EXPONENT", "DOP853", "DP54", "RK4", "WORK_ROWS", "advance"]

RK4 = 0  # classical Runge–Kutta, fixed step (the paper's method)
DP54 = 1  # Dormand–Prince 5(4), adaptive (also the orbit tables' fixed-step 5th order)
DOP853 = 2  # Dormand–Prince 8(5,3), adaptive: the "event" method

# Exponent of the step-size controller, -1/(order of the error estimate + 1).
CONTROLLER_EXPONENT = (0.0, -1.0 / 5.0, -1.0 / 8.0)


@njit(cache=True)
def _advance(method, s, t, h, mode, c, rtol, atol, out, work):
    if method == RK4:
        rk4_step(s, t, h, mode, c, out, work)
        return 0.0
    if method == DP54:
        return dp54_step(s, t, h, mode, c, rtol, atol, out, work)
    return dop853_step(s, t, h, mode, c, rtol, atol, out, work)


@njit(cache=True)
def _advance_legacy(method, s, t, h, mode, c, rtol, atol):
    # The tuple form that analysis/orbit.py still calls: a 4-value state tuple in, a
    # (4-tuple, error) out. Allocates per call; remove once orbit.py passes arrays.
    n = len(s)
    state = np.empty(n)
    for i in range(n):
        state[i] = s[i]
    out = np.empty(n)
    err = _advance(method, state, t, h, mode, c, rtol, atol, out, np.empty((WORK_ROWS, n)))
    return (out[0], out[1], out[2], out[3]), err


def advance(method, s, t, h, mode, c, rtol, atol, out=None, work=None):
    """One step of the chosen method from (t, s) into ``out``; returns the error norm
    (0 for RK4). ``s`` and ``out`` are float64 state arrays of the same size, ``work``
    the steps' scratch, at least WORK_ROWS rows of that size; ``mode`` is the model's.

    Without ``out`` and ``work`` (deprecated, for analysis/orbit.py only): ``s`` is a
    4-tuple and (new 4-tuple, error norm) is returned.
    """
    if out is None:
        return _advance_legacy(method, s, t, h, mode, c, rtol, atol)
    return _advance(method, s, t, h, mode, c, rtol, atol, out, work)


@overload(advance, jit_options={"cache": True})
def _advance_overload(method, s, t, h, mode, c, rtol, atol, out=None, work=None):
    # Compiled callers: the form is chosen by type at compile time.
    if out is None or isinstance(out, (types.NoneType, types.Omitted)):

        def legacy(method, s, t, h, mode, c, rtol, atol, out=None, work=None):
            return _advance_legacy(method, s, t, h, mode, c, rtol, atol)

        return legacy

    def impl(method, s, t, h, mode, c, rtol, atol, out=None, work=None):
        return _advance(method, s, t, h, mode, c, rtol, atol, out, work)

    return impl
