"""The free normal vibration as a reusable table: one half period, from the top to the bottom.

The normal motion (2.4) does not depend on x (docs/model-facts.md, fact 6), is conservative and
time-symmetric about its turning points. One half period, from the highest point (rest,
y = y0 - A) to the lowest (rest, y = y_max), therefore describes the whole periodic motion:
y(T - t) = y(t) and ẏ(T - t) = -ẏ(t). A loss of contact (y < 0, A > y0) is a free-fall
parabola and is kept in closed form; the contact phase is integrated once with fixed
Dormand–Prince 5th-order steps and read back by quintic Hermite interpolation
(values, slopes and the exact accelerations of (2.4) at the nodes).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators.methods import DP54, WORK_ROWS, advance
from microslip.model.coefficients import AREA_CN, EXPONENT, GRAVITY, MASS
from microslip.model.normal import normal_acceleration
from microslip.model.system import N_STATE, YDOT, Y

# Summary slots of an orbit.
O_TOP = 0  # y at the highest point [m]
O_FLIGHT = 1  # time from the top to first contact [s] (0 without loss of contact)
O_STEP = 2  # table step [s]
O_NODES = 3  # number of table nodes
O_HALF = 4  # half period T/2 [s]
O_BOTTOM = 5  # y at the lowest point [m]
O_SIZE = 6


@njit(cache=True)
def static_deflection(c):
    return (c[MASS] * c[GRAVITY] / c[AREA_CN]) ** (1.0 / c[EXPONENT])


@njit(cache=True)
def potential(y, c):
    """V(y) [J]: elastic energy of (2.3) minus the work of gravity, per the sign of y."""
    elastic = 0.0
    if y > 0.0:
        elastic = c[AREA_CN] * y ** (c[EXPONENT] + 1.0) / (c[EXPONENT] + 1.0)
    return elastic - c[MASS] * c[GRAVITY] * y


@njit(cache=True)
def lowest_point(y_top, c):
    """y_max > y0 with V(y_max) = V(y_top): Newton from above on the convex V."""
    y0 = static_deflection(c)
    energy = potential(y_top, c)
    y = 2.0 * y0 + 4.0 * (y0 - y_top)
    for _ in range(200):
        slope = c[AREA_CN] * y ** c[EXPONENT] - c[MASS] * c[GRAVITY]
        step = (potential(y, c) - energy) / slope
        y -= step
        if abs(step) <= 1e-15 * y:
            break
    return y


@njit(cache=True, inline="always")
def _hermite(y0, v0, a0, y1, v1, a1, h, s):
    """Quintic Hermite value and derivative on [0, h] at fraction s."""
    s2 = s * s
    s3 = s2 * s
    s4 = s3 * s
    s5 = s4 * s
    h0 = 1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5
    h1 = s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5
    h2 = 0.5 * (s2 - 3.0 * s3 + 3.0 * s4 - s5)
    h3 = 0.5 * (s3 - 2.0 * s4 + s5)
    h4 = -4.0 * s3 + 7.0 * s4 - 3.0 * s5
    h5 = 10.0 * s3 - 15.0 * s4 + 6.0 * s5
    d0 = -30.0 * s2 + 60.0 * s3 - 30.0 * s4
    d1 = 1.0 - 18.0 * s2 + 32.0 * s3 - 15.0 * s4
    d2 = 0.5 * (2.0 * s - 9.0 * s2 + 12.0 * s3 - 5.0 * s4)
    d3 = 0.5 * (3.0 * s2 - 8.0 * s3 + 5.0 * s4)
    d4 = -12.0 * s2 + 28.0 * s3 - 15.0 * s4
    d5 = -d0
    value = y0 * h0 + h * v0 * h1 + h * h * a0 * h2 + h * h * a1 * h3 + h * v1 * h4 + y1 * h5
    slope = (y0 * d0 + y1 * d5) / h + v0 * d1 + h * a0 * d2 + h * a1 * d3 + v1 * d4
    return value, slope


@njit(cache=True)
def build_half_orbit(amplitude, c, steps_per_half, ys, yds, summary):
    """Fill ``ys``, ``yds`` [m, m/s] and ``summary`` (O_* slots) for amplitude A [m].

    The table step is π / (ω_max · steps_per_half), ω_max the largest local angular
    frequency sqrt(dR/dy / m) on the orbit. Returns False if the buffers are too short.
    """
    g = c[GRAVITY]
    y0 = static_deflection(c)
    y_top = y0 - amplitude
    y_bottom = lowest_point(y_top, c)
    stiffness = c[EXPONENT] * c[AREA_CN] * y_bottom ** (c[EXPONENT] - 1.0)
    h = math.pi / (math.sqrt(stiffness / c[MASS]) * steps_per_half)
    # The normal motion in the model's state (x, ẋ stay 0 in stick, mode 0).
    s = np.zeros(N_STATE)
    if y_top < 0.0:
        t_flight = math.sqrt(-2.0 * y_top / g)
        s[YDOT] = g * t_flight
    else:
        t_flight = 0.0
        s[Y] = y_top
    s_next = np.empty(N_STATE)
    work = np.empty((WORK_ROWS, N_STATE))
    atol = np.ones(N_STATE)  # fixed steps: the error norm is not used
    capacity = ys.shape[0]
    ys[0] = s[Y]
    yds[0] = s[YDOT]
    n = 1
    while True:
        if n >= capacity:
            return False
        advance(DP54, s, 0.0, h, 0.0, c, 1.0, atol, s_next, work)
        s, s_next = s_next, s
        ys[n] = s[Y]
        yds[n] = s[YDOT]
        n += 1
        if s[YDOT] <= 0.0:
            break
    # The bottom (ẏ = 0) lies in the last interval: bisect the interpolated slope.
    a0 = normal_acceleration(0.0, ys[n - 2], 0.0, c)
    a1 = normal_acceleration(0.0, ys[n - 1], 0.0, c)
    lo, hi = 0.0, 1.0
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        _v, slope = _hermite(ys[n - 2], yds[n - 2], a0, ys[n - 1], yds[n - 1], a1, h, mid)
        if slope > 0.0:
            lo = mid
        else:
            hi = mid
    summary[O_TOP] = y_top
    summary[O_FLIGHT] = t_flight
    summary[O_STEP] = h
    summary[O_NODES] = n
    summary[O_HALF] = t_flight + (n - 2 + 0.5 * (lo + hi)) * h
    summary[O_BOTTOM] = y_bottom
    return True


@njit(cache=True)
def orbit_state(t, ys, yds, summary, c):
    """(y [m], ẏ [m/s]) at time t [s] after the top, for any t in [0, T]."""
    half = summary[O_HALF]
    direction = 1.0
    if t > half:
        t = 2.0 * half - t
        direction = -1.0
    if t < 0.0:
        t = 0.0
    t_flight = summary[O_FLIGHT]
    if t < t_flight:
        g = c[GRAVITY]
        return summary[O_TOP] + 0.5 * g * t * t, direction * g * t
    h = summary[O_STEP]
    u = (t - t_flight) / h
    i = int(u)
    last = int(summary[O_NODES]) - 2
    if i > last:
        i = last
    y_a, y_b = ys[i], ys[i + 1]
    value, slope = _hermite(
        y_a,
        yds[i],
        normal_acceleration(0.0, y_a, 0.0, c),
        y_b,
        yds[i + 1],
        normal_acceleration(0.0, y_b, 0.0, c),
        h,
        u - i,
    )
    return value, direction * slope


@njit(cache=True)
def time_at_height(y_target, ys, yds, summary, c):
    """The time t in [0, T/2] [s] at which the descending motion passes y = y_target [m].

    Requires y_top < y_target < y_bottom.
    """
    t_flight = summary[O_FLIGHT]
    if y_target <= 0.0:  # in free fall: closed form
        return math.sqrt(2.0 * (y_target - summary[O_TOP]) / c[GRAVITY])
    n = int(summary[O_NODES])
    lo_i, hi_i = 0, n - 2  # ys increases up to the bottom interval
    while hi_i - lo_i > 1:
        mid = (lo_i + hi_i) // 2
        if ys[mid] <= y_target:
            lo_i = mid
        else:
            hi_i = mid
    h = summary[O_STEP]
    lo = t_flight + lo_i * h
    hi = min(t_flight + (lo_i + 1) * h, summary[O_HALF])
    if ys[lo_i + 1] <= y_target:  # target in the last, partly used interval
        lo = t_flight + (lo_i + 1) * h
        hi = summary[O_HALF]
    t = 0.5 * (lo + hi)
    for _ in range(100):
        y, yd = orbit_state(t, ys, yds, summary, c)
        if y < y_target:
            lo = t
        else:
            hi = t
        step = (y - y_target) / yd if yd > 0.0 else 0.0
        t_new = t - step
        if not (lo < t_new < hi):
            t_new = 0.5 * (lo + hi)
        if abs(t_new - t) <= 1e-15 * (t + h) or hi - lo <= 1e-15 * (t + h):
            t = t_new
            break
        t = t_new
    return t


def orbit_capacity(steps_per_half: int) -> int:
    """Table length that always suffices for ``steps_per_half``."""
    return 16 * steps_per_half + 16
