"""Single Runge–Kutta steps of the composed system in a fixed mode.

A state is a float64 array of any length (its meaning is the model's business:
:mod:`microslip.model.system`); ``mode`` is the model's opaque mode, held fixed within
a step: switching instants are located around these steps, never hidden inside them.
The steps write the new state into ``out`` (which must not be ``s``; it also holds the
stage inputs), so that no step allocates. The model's :func:`derivatives` takes the
state as a tuple (:func:`~microslip.model.system.state_tuple`) and returns one: inside
a step no array crosses a compiled call, where it would be reference-counted (atomic
operations, dearer than the laws). ``work`` (a C-contiguous 2-D array of at least
:data:`WORK_ROWS` rows of the state size) holds the stages of DOP853; its rows are
indexed, never taken as views (a view is reference-counted too).
"""

from __future__ import annotations

import math

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.system import derivatives, state_tuple

# Rows of ``work`` a step may use (DOP853: 12 stages).
WORK_ROWS = 12

# The steps call the model from one place (a loop over the stages), where numba inlines
# it, and are compiled with error_model="numpy" (no ZeroDivisionError branch): a step
# then makes no compiled call and has no raising branch, so numba drops the reference
# counting of its array arguments. The divisions are by the mass (> 0) and, in the error
# norms, by atol_i + rtol·max(|s_i|, |out_i|); with atol_i = 0 and a component that
# stays exactly 0 the norm is NaN and the adaptive loop rejects the step (it raised
# ZeroDivisionError before).


@njit(cache=True, error_model="numpy")
def rk4_step(s, t, h, mode, c, out, work):
    """Classical 4th-order Runge–Kutta step of length h [s] (the paper's method)."""
    hh = 0.5 * h
    x = state_tuple(s)
    n = len(x)
    t_stage = t
    for stage in range(4):  # one call site of the (inlined) model: see the module doc
        if stage == 1:
            for i in range(n):
                out[i] = s[i] + hh * work[0, i]
            t_stage = t + hh
        elif stage == 2:
            for i in range(n):
                out[i] = s[i] + hh * work[1, i]
        elif stage == 3:
            for i in range(n):
                out[i] = s[i] + h * work[2, i]
            t_stage = t + h
        if stage > 0:
            x = state_tuple(out)
        k = derivatives(t_stage, x, mode, c)
        for i in range(n):
            work[stage, i] = k[i]
    w = h / 6.0
    for i in range(n):
        out[i] = s[i] + w * (work[0, i] + 2.0 * work[1, i] + 2.0 * work[2, i] + work[3, i])


# Dormand–Prince 5(4) tableau (Dormand & Prince 1980; the same as scipy's RK45).
_A21 = 1.0 / 5.0
_A31, _A32 = 3.0 / 40.0, 9.0 / 40.0
_A41, _A42, _A43 = 44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0
_A51, _A52, _A53, _A54 = 19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0
_A61, _A62, _A63, _A64, _A65 = (
    9017.0 / 3168.0,
    -355.0 / 33.0,
    46732.0 / 5247.0,
    49.0 / 176.0,
    -5103.0 / 18656.0,
)
_B1, _B3, _B4, _B5, _B6 = 35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0
_E1, _E3, _E4, _E5, _E6, _E7 = (
    -71.0 / 57600.0,
    71.0 / 16695.0,
    -71.0 / 1920.0,
    17253.0 / 339200.0,
    -22.0 / 525.0,
    1.0 / 40.0,
)
_C2, _C3, _C4, _C5 = 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0


@njit(cache=True, error_model="numpy")
def dp54_step(s, t, h, mode, c, rtol, atol, out, work):
    """Dormand–Prince 5(4) step of length h [s]; the 5th-order state goes to ``out``.

    Returns the RMS error norm of the embedded estimate, each component scaled by
    atol[i] + rtol * max(|s_i|, |out_i|) (1 means "at tolerance").
    """
    x = state_tuple(s)
    n = len(x)
    t_stage = t
    for stage in range(7):  # one call site of the (inlined) model: see the module doc
        if stage == 1:
            for i in range(n):
                out[i] = s[i] + h * (_A21 * work[0, i])
            t_stage = t + _C2 * h
        elif stage == 2:
            for i in range(n):
                out[i] = s[i] + h * (_A31 * work[0, i] + _A32 * work[1, i])
            t_stage = t + _C3 * h
        elif stage == 3:
            for i in range(n):
                out[i] = s[i] + h * (_A41 * work[0, i] + _A42 * work[1, i] + _A43 * work[2, i])
            t_stage = t + _C4 * h
        elif stage == 4:
            for i in range(n):
                out[i] = s[i] + h * (
                    _A51 * work[0, i] + _A52 * work[1, i] + _A53 * work[2, i] + _A54 * work[3, i]
                )
            t_stage = t + _C5 * h
        elif stage == 5:
            for i in range(n):
                out[i] = s[i] + h * (
                    _A61 * work[0, i]
                    + _A62 * work[1, i]
                    + _A63 * work[2, i]
                    + _A64 * work[3, i]
                    + _A65 * work[4, i]
                )
            t_stage = t + h
        elif stage == 6:  # the 5th-order result; its derivative closes the error estimate
            for i in range(n):
                out[i] = s[i] + h * (
                    _B1 * work[0, i]
                    + _B3 * work[2, i]
                    + _B4 * work[3, i]
                    + _B5 * work[4, i]
                    + _B6 * work[5, i]
                )
        if stage > 0:
            x = state_tuple(out)
        k = derivatives(t_stage, x, mode, c)
        for i in range(n):
            work[stage, i] = k[i]
    total = 0.0
    for i in range(n):
        err = h * (
            _E1 * work[0, i]
            + _E3 * work[2, i]
            + _E4 * work[3, i]
            + _E5 * work[4, i]
            + _E6 * work[5, i]
            + _E7 * work[6, i]
        )
        scale = atol[i] + rtol * max(abs(s[i]), abs(out[i]))
        total += (err / scale) ** 2
    return math.sqrt(total / n)
