"""Single Runge–Kutta steps of the composed system in a fixed mode.

A state is a float64 array of any length (its meaning is the model's business:
:mod:`microslip.model.system`); ``mode`` is the model's opaque mode, held fixed within
a step: switching instants are located around these steps, never hidden inside them.
The steps write the new state into ``out`` (which must not be ``s``) and use the rows
of ``work`` (a C-contiguous 2-D array of at least :data:`WORK_ROWS` rows of the state
size) for their stages, so that no step allocates.
"""

from __future__ import annotations

import math

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.system import derivatives

# Rows of ``work`` a step may use (DOP853: 12 stages and one stage input).
WORK_ROWS = 13


@njit(cache=True)
def rk4_step(s, t, h, mode, c, out, work):
    """Classical 4th-order Runge–Kutta step of length h [s] (the paper's method)."""
    n = s.shape[0]
    k1 = work[0]
    k2 = work[1]
    k3 = work[2]
    k4 = work[3]
    tmp = work[4]
    derivatives(t, s, mode, c, k1)
    hh = 0.5 * h
    for i in range(n):
        tmp[i] = s[i] + hh * k1[i]
    derivatives(t + hh, tmp, mode, c, k2)
    for i in range(n):
        tmp[i] = s[i] + hh * k2[i]
    derivatives(t + hh, tmp, mode, c, k3)
    for i in range(n):
        tmp[i] = s[i] + h * k3[i]
    derivatives(t + h, tmp, mode, c, k4)
    w = h / 6.0
    for i in range(n):
        out[i] = s[i] + w * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])


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


@njit(cache=True)
def dp54_step(s, t, h, mode, c, rtol, atol, out, work):
    """Dormand–Prince 5(4) step of length h [s]; the 5th-order state goes to ``out``.

    Returns the RMS error norm of the embedded estimate, each component scaled by
    atol[i] + rtol * max(|s_i|, |out_i|) (1 means "at tolerance").
    """
    n = s.shape[0]
    k1, k2, k3, k4 = work[0], work[1], work[2], work[3]
    k5, k6, k7, tmp = work[4], work[5], work[6], work[7]
    derivatives(t, s, mode, c, k1)
    for i in range(n):
        tmp[i] = s[i] + h * (_A21 * k1[i])
    derivatives(t + _C2 * h, tmp, mode, c, k2)
    for i in range(n):
        tmp[i] = s[i] + h * (_A31 * k1[i] + _A32 * k2[i])
    derivatives(t + _C3 * h, tmp, mode, c, k3)
    for i in range(n):
        tmp[i] = s[i] + h * (_A41 * k1[i] + _A42 * k2[i] + _A43 * k3[i])
    derivatives(t + _C4 * h, tmp, mode, c, k4)
    for i in range(n):
        tmp[i] = s[i] + h * (_A51 * k1[i] + _A52 * k2[i] + _A53 * k3[i] + _A54 * k4[i])
    derivatives(t + _C5 * h, tmp, mode, c, k5)
    for i in range(n):
        tmp[i] = s[i] + h * (
            _A61 * k1[i] + _A62 * k2[i] + _A63 * k3[i] + _A64 * k4[i] + _A65 * k5[i]
        )
    derivatives(t + h, tmp, mode, c, k6)
    for i in range(n):
        out[i] = s[i] + h * (_B1 * k1[i] + _B3 * k3[i] + _B4 * k4[i] + _B5 * k5[i] + _B6 * k6[i])
    derivatives(t + h, out, mode, c, k7)
    total = 0.0
    for i in range(n):
        err = h * (
            _E1 * k1[i] + _E3 * k3[i] + _E4 * k4[i] + _E5 * k5[i] + _E6 * k6[i] + _E7 * k7[i]
        )
        scale = atol[i] + rtol * max(abs(s[i]), abs(out[i]))
        total += (err / scale) ** 2
    return math.sqrt(total / n)
