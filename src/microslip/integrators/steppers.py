"""Single Runge–Kutta steps of the full 2-DOF system (2.4)–(2.5) in a fixed friction mode.

A state is the tuple (y [m], ẏ [m/s], x [m], ẋ [m/s]). ``direction`` is the sliding
direction sgn ẋ (±1) or 0 for stick; within one step it is held fixed: switching
instants are located around these steps, never hidden inside them.
"""

from __future__ import annotations

import math

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.contact import normal_acceleration
from microslip.model.friction import slip_acceleration


@njit(cache=True, inline="always")
def derivatives(y, ydot, xdot, t, direction, c):
    """(ẏ, ÿ, ẋ, ẍ) from eqs. (2.4) and (2.5)."""
    return (
        ydot,
        normal_acceleration(y, ydot, c),
        xdot,
        slip_acceleration(y, ydot, t, direction, c),
    )


@njit(cache=True)
def rk4_step(s, t, h, direction, c):
    """Classical 4th-order Runge–Kutta step of length h [s] (the paper's method)."""
    y, yd, x, xd = s
    a0, a1, a2, a3 = derivatives(y, yd, xd, t, direction, c)
    hh = 0.5 * h
    b0, b1, b2, b3 = derivatives(y + hh * a0, yd + hh * a1, xd + hh * a3, t + hh, direction, c)
    c0, c1, c2, c3 = derivatives(y + hh * b0, yd + hh * b1, xd + hh * b3, t + hh, direction, c)
    d0, d1, d2, d3 = derivatives(y + h * c0, yd + h * c1, xd + h * c3, t + h, direction, c)
    w = h / 6.0
    return (
        y + w * (a0 + 2.0 * b0 + 2.0 * c0 + d0),
        yd + w * (a1 + 2.0 * b1 + 2.0 * c1 + d1),
        x + w * (a2 + 2.0 * b2 + 2.0 * c2 + d2),
        xd + w * (a3 + 2.0 * b3 + 2.0 * c3 + d3),
    )


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


@njit(cache=True, inline="always")
def _combine(s, h, k1, k2, k3, k4, k5, w1, w2, w3, w4, w5):
    return (
        s[0] + h * (w1 * k1[0] + w2 * k2[0] + w3 * k3[0] + w4 * k4[0] + w5 * k5[0]),
        s[1] + h * (w1 * k1[1] + w2 * k2[1] + w3 * k3[1] + w4 * k4[1] + w5 * k5[1]),
        s[2] + h * (w1 * k1[2] + w2 * k2[2] + w3 * k3[2] + w4 * k4[2] + w5 * k5[2]),
        s[3] + h * (w1 * k1[3] + w2 * k2[3] + w3 * k3[3] + w4 * k4[3] + w5 * k5[3]),
    )


@njit(cache=True, inline="always")
def _f(s, t, direction, c):
    return derivatives(s[0], s[1], s[3], t, direction, c)


@njit(cache=True)
def dp54_step(s, t, h, direction, c, rtol, atol):
    """Dormand–Prince 5(4) step of length h [s].

    Returns the 5th-order state and the RMS error norm of the embedded estimate, each
    component scaled by atol[i] + rtol * max(|s_i|, |s_new_i|) (1 means "at tolerance").
    """
    k1 = _f(s, t, direction, c)
    k2 = _f(_combine(s, h, k1, k1, k1, k1, k1, _A21, 0.0, 0.0, 0.0, 0.0), t + _C2 * h, direction, c)
    k3 = _f(
        _combine(s, h, k1, k2, k1, k1, k1, _A31, _A32, 0.0, 0.0, 0.0), t + _C3 * h, direction, c
    )
    k4 = _f(
        _combine(s, h, k1, k2, k3, k1, k1, _A41, _A42, _A43, 0.0, 0.0), t + _C4 * h, direction, c
    )
    k5 = _f(
        _combine(s, h, k1, k2, k3, k4, k1, _A51, _A52, _A53, _A54, 0.0), t + _C5 * h, direction, c
    )
    k6 = _f(_combine(s, h, k1, k2, k3, k4, k5, _A61, _A62, _A63, _A64, _A65), t + h, direction, c)
    new = _combine(s, h, k1, k3, k4, k5, k6, _B1, _B3, _B4, _B5, _B6)
    k7 = _f(new, t + h, direction, c)
    total = 0.0
    for i in range(4):
        err = h * (
            _E1 * k1[i] + _E3 * k3[i] + _E4 * k4[i] + _E5 * k5[i] + _E6 * k6[i] + _E7 * k7[i]
        )
        scale = atol[i] + rtol * max(abs(s[i]), abs(new[i]))
        total += (err / scale) ** 2
    return new, math.sqrt(total / 4.0)
