"""Dormand–Prince 8(5,3) step (the DOP853 scheme) for a state of any size.

The stage sums are written out over the nonzero coefficients of the tableau of
:mod:`dop853_tableau` (constant indices: compiled to constants), in the order of the
tableau and from 0.0, so that they have the bits of the plain sums over the tableau rows.
The model is called from one place in the stage loop (it is inlined there). Stage
derivatives live in the rows of a caller-owned ``work`` array (indexed, not taken as
views, which are reference-counted), so a step allocates nothing.
"""

import math

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators.dop853_tableau import E3, E5, N_STAGES, A, B, C
from microslip.model.system import derivatives, state_tuple


@njit(cache=True, error_model="numpy")
def dop853_step(s, t, h, mode, c, rtol, atol, out, work):
    """8th-order step of length h [s] into ``out``; returns the error norm (1 = at
    tolerance).

    The error norm is DOP853's blend of its 5th- and 3rd-order estimates, each
    component scaled by atol[i] + rtol * max(|s_i|, |out_i|), as in scipy's DOP853.
    A component with atol[i] = inf is not error-controlled and not counted in the RMS
    norm (the model says which components it holds constant).
    ``work`` needs at least N_STAGES = 12 rows of the state size; ``out`` (not ``s``)
    holds the stage inputs until the result.
    """
    x = state_tuple(s)
    n = len(x)
    t_stage = t
    for stage in range(N_STAGES):  # one call site of the (inlined) model
        if stage == 1:
            for i in range(n):
                out[i] = s[i] + h * (0.0 + A[1, 0] * work[0, i])
        elif stage == 2:
            for i in range(n):
                out[i] = s[i] + h * (0.0 + A[2, 0] * work[0, i] + A[2, 1] * work[1, i])
        elif stage == 3:
            for i in range(n):
                out[i] = s[i] + h * (0.0 + A[3, 0] * work[0, i] + A[3, 2] * work[2, i])
        elif stage == 4:
            for i in range(n):
                out[i] = s[i] + h * (
                    0.0 + A[4, 0] * work[0, i] + A[4, 2] * work[2, i] + A[4, 3] * work[3, i]
                )
        elif stage == 5:
            for i in range(n):
                out[i] = s[i] + h * (
                    0.0 + A[5, 0] * work[0, i] + A[5, 3] * work[3, i] + A[5, 4] * work[4, i]
                )
        elif stage == 6:
            for i in range(n):
                out[i] = s[i] + h * (
                    0.0
                    + A[6, 0] * work[0, i]
                    + A[6, 3] * work[3, i]
                    + A[6, 4] * work[4, i]
                    + A[6, 5] * work[5, i]
                )
        elif stage == 7:
            for i in range(n):
                out[i] = s[i] + h * (
                    0.0
                    + A[7, 0] * work[0, i]
                    + A[7, 3] * work[3, i]
                    + A[7, 4] * work[4, i]
                    + A[7, 5] * work[5, i]
                    + A[7, 6] * work[6, i]
                )
        elif stage == 8:
            for i in range(n):
                out[i] = s[i] + h * (
                    0.0
                    + A[8, 0] * work[0, i]
                    + A[8, 3] * work[3, i]
                    + A[8, 4] * work[4, i]
                    + A[8, 5] * work[5, i]
                    + A[8, 6] * work[6, i]
                    + A[8, 7] * work[7, i]
                )
        elif stage == 9:
            for i in range(n):
                out[i] = s[i] + h * (
                    0.0
                    + A[9, 0] * work[0, i]
                    + A[9, 3] * work[3, i]
                    + A[9, 4] * work[4, i]
                    + A[9, 5] * work[5, i]
                    + A[9, 6] * work[6, i]
                    + A[9, 7] * work[7, i]
                    + A[9, 8] * work[8, i]
                )
        elif stage == 10:
            for i in range(n):
                out[i] = s[i] + h * (
                    0.0
                    + A[10, 0] * work[0, i]
                    + A[10, 3] * work[3, i]
                    + A[10, 4] * work[4, i]
                    + A[10, 5] * work[5, i]
                    + A[10, 6] * work[6, i]
                    + A[10, 7] * work[7, i]
                    + A[10, 8] * work[8, i]
                    + A[10, 9] * work[9, i]
                )
        elif stage == 11:
            for i in range(n):
                out[i] = s[i] + h * (
                    0.0
                    + A[11, 0] * work[0, i]
                    + A[11, 3] * work[3, i]
                    + A[11, 4] * work[4, i]
                    + A[11, 5] * work[5, i]
                    + A[11, 6] * work[6, i]
                    + A[11, 7] * work[7, i]
                    + A[11, 8] * work[8, i]
                    + A[11, 9] * work[9, i]
                    + A[11, 10] * work[10, i]
                )
        if stage > 0:
            x = state_tuple(out)
            t_stage = t + C[stage] * h
        k = derivatives(t_stage, x, mode, c)
        for i in range(n):
            work[stage, i] = k[i]
    for i in range(n):
        out[i] = s[i] + h * (
            0.0
            + B[0] * work[0, i]
            + B[5] * work[5, i]
            + B[6] * work[6, i]
            + B[7] * work[7, i]
            + B[8] * work[8, i]
            + B[9] * work[9, i]
            + B[10] * work[10, i]
            + B[11] * work[11, i]
        )
    err5 = 0.0
    err3 = 0.0
    controlled = 0
    for i in range(n):
        if atol[i] == math.inf:  # not error-controlled, not counted in the norm
            continue
        controlled += 1
        scale = atol[i] + rtol * max(abs(s[i]), abs(out[i]))
        e5 = (
            0.0
            + E5[0] * work[0, i]
            + E5[5] * work[5, i]
            + E5[6] * work[6, i]
            + E5[7] * work[7, i]
            + E5[8] * work[8, i]
            + E5[9] * work[9, i]
            + E5[10] * work[10, i]
            + E5[11] * work[11, i]
        ) / scale
        e3 = (
            0.0
            + E3[0] * work[0, i]
            + E3[5] * work[5, i]
            + E3[6] * work[6, i]
            + E3[7] * work[7, i]
            + E3[8] * work[8, i]
            + E3[9] * work[9, i]
            + E3[10] * work[10, i]
            + E3[11] * work[11, i]
        ) / scale
        err5 += e5 * e5
        err3 += e3 * e3

    if err5 == 0.0 and err3 == 0.0:
        return 0.0
    return abs(h) * err5 / math.sqrt((err5 + 0.01 * err3) * controlled)
