"""Dormand–Prince 8(5,3) step (the DOP853 scheme) for a state of any size.

The stages run over the tableau of :mod:`dop853_tableau` with its zero coefficients
skipped; stage derivatives live in the rows of a caller-owned ``work`` array, so a step
allocates nothing.
"""

import math

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators.dop853_tableau import E3, E5, N_STAGES, A, B, C
from microslip.model.system import derivatives

_INPUT = N_STAGES  # row of ``work`` holding the stage input


@njit(cache=True)
def dop853_step(s, t, h, mode, c, rtol, atol, out, work):
    """8th-order step of length h [s] into ``out``; returns the error norm (1 = at
    tolerance).

    The error norm is DOP853's blend of its 5th- and 3rd-order estimates, each
    component scaled by atol[i] + rtol * max(|s_i|, |out_i|), as in scipy's DOP853.
    ``work`` needs at least N_STAGES + 1 = 13 rows of the state size.
    """
    n = s.shape[0]
    derivatives(t, s, mode, c, work[0])
    stage_input = work[_INPUT]
    for stage in range(1, N_STAGES):
        for i in range(n):
            acc = 0.0
            for j in range(stage):
                a = A[stage, j]
                if a != 0.0:
                    acc += a * work[j, i]
            stage_input[i] = s[i] + h * acc
        derivatives(t + C[stage] * h, stage_input, mode, c, work[stage])
    err5 = 0.0
    err3 = 0.0
    for i in range(n):
        acc = 0.0
        for j in range(N_STAGES):
            b = B[j]
            if b != 0.0:
                acc += b * work[j, i]
        out[i] = s[i] + h * acc
    for i in range(n):
        scale = atol[i] + rtol * max(abs(s[i]), abs(out[i]))
        a5 = 0.0
        a3 = 0.0
        for j in range(N_STAGES):
            if E5[j] != 0.0:
                a5 += E5[j] * work[j, i]
            if E3[j] != 0.0:
                a3 += E3[j] * work[j, i]
        e5 = a5 / scale
        e3 = a3 / scale
        err5 += e5 * e5
        err3 += e3 * e3
    if err5 == 0.0 and err3 == 0.0:
        return 0.0
    return abs(h) * err5 / math.sqrt((err5 + 0.01 * err3) * n)
