"""The free normal vibration as a reusable table: one half period, from the top to the bottom.

The normal motion (2.4) does not depend on x (docs/model-facts.md, fact 6), is conservative and
time-symmetric about its turning points. One half period, from the highest point (rest,
y = y0 - A) to the lowest (rest, y = y_max), therefore describes the whole periodic motion:
y(T - t) = y(t) and ẏ(T - t) = -ẏ(t). A loss of contact (y < 0, A > y0) is a free-fall
parabola and is kept in closed form; the contact phase is integrated once with fixed
Dormand–Prince 5th-order steps and read back by quintic Hermite interpolation
(values, slopes and the exact accelerations of (2.4) at the nodes).

:func:`steady_slip` reads the steady stick–slip cycle off the table: each crossing (release
at y*, stop at ẋ = 0) is located by bisection over the nodes, where y, ẏ and ẋ are known
exactly, and solved by Newton on that one interval (:func:`interval_root`), with the node
accelerations precomputed (:func:`node_accelerations`): no transcendental call per point.
"""

from __future__ import annotations

import math

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)

# The Dormand–Prince 5(4) tableau: _dp54 below is its arithmetic on the two normal states.
from microslip.integrators.dp54_tableau import (
    _A21,
    _A31,
    _A32,
    _A41,
    _A42,
    _A43,
    _A51,
    _A52,
    _A53,
    _A54,
    _A61,
    _A62,
    _A63,
    _A64,
    _A65,
    _B1,
    _B3,
    _B4,
    _B5,
    _B6,
)
from microslip.integrators.kernel import as_tuple
from microslip.model.coefficients import AREA_CN, EXPONENT, GRAVITY, MASS
from microslip.model.contact import elastic_force, elastic_stiffness
from microslip.model.normal import normal_acceleration
from microslip.model.system import normal_acceleration_call

# Summary slots of an orbit.
O_TOP = 0  # y at the highest point [m]
O_FLIGHT = 1  # time from the top to first contact [s] (0 without loss of contact)
O_STEP = 2  # table step [s]
O_NODES = 3  # number of table nodes
O_HALF = 4  # half period T/2 [s]
O_BOTTOM = 5  # y at the lowest point [m]
O_SIZE = 6

_F_NOISE = 4.0 * 2.220446049250313e-16  # rounding of a root function, per unit of its terms


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
    """y_max > y0 with V(y_max) = V(y_top): Newton from above on the convex V, whose
    slope is the contact law less the weight. ``c``: the coefficient tuple."""
    y0 = static_deflection(c)
    energy = potential(y_top, c)
    y = 2.0 * y0 + 4.0 * (y0 - y_top)
    for _ in range(200):
        slope = elastic_force(y, c) - c[MASS] * c[GRAVITY]
        step = (potential(y, c) - energy) / slope
        y -= step
        if abs(step) <= 1e-15 * y:
            break
    return y


@njit(cache=True, inline="always")
def _dp54(y, v, h, c):
    """One 5th-order Dormand–Prince step of (2.4) from (y [m], ẏ [m/s]) over h [s].

    The same arithmetic as the y, ẏ components of the general stepper, on the two normal
    states only (the free normal motion is autonomous and does not depend on x). The
    stages call the acceleration through a compiled boundary: the composed law inlined
    six times made one compile of the table take ~7 s instead of ~2 s.
    """
    a1 = normal_acceleration_call(0.0, y, v, c)
    y2 = y + h * (_A21 * v)
    v2 = v + h * (_A21 * a1)
    a2 = normal_acceleration_call(0.0, y2, v2, c)
    y3 = y + h * (_A31 * v + _A32 * v2)
    v3 = v + h * (_A31 * a1 + _A32 * a2)
    a3 = normal_acceleration_call(0.0, y3, v3, c)
    y4 = y + h * (_A41 * v + _A42 * v2 + _A43 * v3)
    v4 = v + h * (_A41 * a1 + _A42 * a2 + _A43 * a3)
    a4 = normal_acceleration_call(0.0, y4, v4, c)
    y5 = y + h * (_A51 * v + _A52 * v2 + _A53 * v3 + _A54 * v4)
    v5 = v + h * (_A51 * a1 + _A52 * a2 + _A53 * a3 + _A54 * a4)
    a5 = normal_acceleration_call(0.0, y5, v5, c)
    y6 = y + h * (_A61 * v + _A62 * v2 + _A63 * v3 + _A64 * v4 + _A65 * v5)
    v6 = v + h * (_A61 * a1 + _A62 * a2 + _A63 * a3 + _A64 * a4 + _A65 * a5)
    a6 = normal_acceleration_call(0.0, y6, v6, c)
    y_new = y + h * (_B1 * v + _B3 * v3 + _B4 * v4 + _B5 * v5 + _B6 * v6)
    v_new = v + h * (_B1 * a1 + _B3 * a3 + _B4 * a4 + _B5 * a5 + _B6 * a6)
    return y_new, v_new


@njit(cache=True, inline="always")
def _hermite(y0, v0, a0, y1, v1, a1, h, s):
    """Quintic Hermite value and derivative on [0, h] at fraction s.

    The slope takes y0 - y1 first: y0 d0 / h alone is ~|y| / h, far above ẏ, and would
    leave ẏ with that term's rounding.
    """
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
    value = y0 * h0 + h * v0 * h1 + h * h * a0 * h2 + h * h * a1 * h3 + h * v1 * h4 + y1 * h5
    slope = (y0 - y1) * d0 / h + v0 * d1 + h * a0 * d2 + h * a1 * d3 + v1 * d4
    return value, slope


@njit(cache=True, nogil=True)
def build_half_orbit(amplitude, c, steps_per_half, ys, yds, summary):
    """Fill ``ys``, ``yds`` [m, m/s] and ``summary`` (O_* slots) for amplitude A [m].

    The table step is π / (ω_max · steps_per_half), ω_max the largest local angular
    frequency sqrt(dR/dy / m) on the orbit. Returns False if the buffers are too short.
    """
    # The laws take the coefficients as a tuple, as every other path passes them: one
    # compiled form of each (docs/design.md, "Compile time").
    laws = as_tuple(c)
    g = laws[GRAVITY]
    y0 = static_deflection(laws)
    y_top = y0 - amplitude
    y_bottom = lowest_point(y_top, laws)
    stiffness = elastic_stiffness(y_bottom, laws)
    h = math.pi / (math.sqrt(stiffness / laws[MASS]) * steps_per_half)
    if y_top < 0.0:  # free fall down to the first contact at y = 0
        t_flight = math.sqrt(-2.0 * y_top / g)
        y, v = 0.0, g * t_flight
    else:
        t_flight = 0.0
        y, v = y_top, 0.0
    capacity = ys.shape[0]
    ys[0] = y
    yds[0] = v
    n = 1
    while True:
        if n >= capacity:
            return False
        y, v = _dp54(y, v, h, laws)
        ys[n] = y
        yds[n] = v
        n += 1
        if v <= 0.0:
            break
    # The bottom (ẏ = 0) lies in the last interval: bisect the interpolated slope.
    a0 = normal_acceleration(0.0, ys[n - 2], 0.0, laws)
    a1 = normal_acceleration(0.0, ys[n - 1], 0.0, laws)
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
def node_accelerations(ys, summary, c, ydds):
    """ydds[k] = ÿ [m/s^2] of (2.4) at the table nodes (the Hermite data of table_state)."""
    laws = as_tuple(c)
    for k in range(int(summary[O_NODES])):
        ydds[k] = normal_acceleration(0.0, ys[k], 0.0, laws)


@njit(cache=True, inline="always")
def _interval_polynomial(k, ys, yds, ydds, h):
    """(c0, ..., c5): the quintic Hermite of :func:`_hermite` on table interval k as a
    polynomial in s, y(s) = Σ c_j s^j [m]. Built once per root, so that each Newton step
    is three Horner sums instead of the eleven basis polynomials. The node difference
    y1 - y0 is taken first (the node values are ~|y|, far above the increments)."""
    d = ys[k + 1] - ys[k]
    p0, p1 = h * yds[k], h * yds[k + 1]
    q0, q1 = h * h * ydds[k], h * h * ydds[k + 1]
    c3 = 10.0 * d - 6.0 * p0 - 4.0 * p1 - 1.5 * q0 + 0.5 * q1
    c4 = -15.0 * d + 8.0 * p0 + 7.0 * p1 + 1.5 * q0 - q1
    c5 = 6.0 * d - 3.0 * p0 - 3.0 * p1 - 0.5 * q0 + 0.5 * q1
    return ys[k], p0, 0.5 * q0, c3, c4, c5


@njit(cache=True, inline="always")
def _polynomial_state(c, h, s):
    """(y [m], ẏ [m/s], ÿ [m/s^2]) at fraction s of the interval of polynomial ``c``."""
    y = c[0] + s * (c[1] + s * (c[2] + s * (c[3] + s * (c[4] + s * c[5]))))
    slope = c[1] + s * (2.0 * c[2] + s * (3.0 * c[3] + s * (4.0 * c[4] + s * 5.0 * c[5])))
    curvature = 2.0 * c[2] + s * (6.0 * c[3] + s * (12.0 * c[4] + s * 20.0 * c[5]))
    return y, slope / h, curvature / (h * h)


@njit(cache=True, inline="always")
def table_state(k, s, ys, yds, ydds, h):
    """(y [m], ẏ [m/s]) at fraction s of table interval k (node times k h, k h + h)."""
    y, yd, _ydd = _polynomial_state(_interval_polynomial(k, ys, yds, ydds, h), h, s)
    return y, yd


@njit(cache=True, inline="always")
def interval_guess(k, w_y, w_v, gamma, const, ys, yds, ydds, h):
    """First guess of the root s in [0, 1] of f(s) = w_y y + w_v ẏ + gamma s + const on
    interval k (f increasing, f(0) <= 0 <= f(1)): the cubic Hermite interpolant of the
    inverse function s(f) through the node values of f and of df/ds (O(h^4), so Newton
    from it needs one step fewer than from the linear guess); the linear guess where
    df/ds is not positive at both ends or the cubic one leaves (0, 1)."""
    f0 = w_y * ys[k] + w_v * yds[k] + const
    f1 = w_y * ys[k + 1] + w_v * yds[k + 1] + gamma + const
    if not f1 > f0:
        return 0.5
    u = -f0 / (f1 - f0)  # the linear guess
    d0 = h * (w_y * yds[k] + w_v * ydds[k]) + gamma
    d1 = h * (w_y * yds[k + 1] + w_v * ydds[k + 1]) + gamma
    if not (d0 > 0.0 and d1 > 0.0):
        return u
    span = f1 - f0
    u2 = u * u
    s = (
        (u2 * u - 2.0 * u2 + u) * (span / d0)
        + (3.0 * u2 - 2.0 * u2 * u)
        + (u2 * u - u2) * (span / d1)
    )
    return s if 0.0 < s < 1.0 else u


@njit(cache=True, inline="always")
def interval_root(k, s, s_lo, s_hi, w_y, w_v, gamma, const, tol, ys, yds, ydds, h):
    """Root s in [s_lo, s_hi] of f(s) = w_y y + w_v ẏ + gamma s + const on interval k.

    y, ẏ are the Hermite interpolant at fraction s of interval k; f must increase from
    f(s_lo) <= 0 to f(s_hi) >= 0. Newton from the guess s, with bisection whenever a step
    leaves the bracket, until a step or the bracket is below ``tol`` (fraction units).
    """
    poly = _interval_polynomial(k, ys, yds, ydds, h)
    if not (s_lo < s < s_hi):
        s = 0.5 * (s_lo + s_hi)
    for _ in range(100):
        y, yd, ydd = _polynomial_state(poly, h, s)
        f = w_y * y + w_v * yd + gamma * s + const
        if f < 0.0:
            s_lo = s
        else:
            s_hi = s
        # f at the rounding of its terms: s is as good as f can tell (Newton would only
        # creep on in steps of that noise, ~1e-11 of the interval near a turning point).
        if abs(f) <= _F_NOISE * (abs(w_y * y) + abs(w_v * yd) + abs(gamma * s) + abs(const)):
            break
        slope = w_y * yd * h + gamma + w_v * h * ydd
        s_new = s - f / slope if slope > 0.0 else 0.5 * (s_lo + s_hi)
        if not (s_lo < s_new < s_hi):
            s_new = 0.5 * (s_lo + s_hi)
        converged = abs(s_new - s) <= tol or s_hi - s_lo <= tol
        s = s_new
        if converged:
            break
    return s


# Inlined into its callers (a compiled call per point passes four arrays, whose reference
# counting cost ~25 ns of ~155 per point); those are small loops, not the map's parallel
# loop, whose compile it made ~7 s longer.
@njit(cache=True, error_model="numpy", inline="always")
def steady_slip(y_release, accel, mu, ys, yds, ydds, summary):
    """(slip time [s], slip distance [m], peak speed [m/s], t_d [s]) of the steady cycle.

    For μ min|R| < F <= μ m g, with y* = ``y_release`` [m] and a = ``accel`` [m/s^2]. Both
    crossings (release at y*, stop at ẋ = 0) are located by bisection over the table
    nodes, where y, ẏ and ẋ are known without interpolation, then solved by Newton on the
    quintic Hermite of that one interval (:func:`interval_root`).
    """
    h = summary[O_STEP]
    t_flight = summary[O_FLIGHT]
    half = summary[O_HALF]
    period = 2.0 * half
    last = int(summary[O_NODES]) - 2  # the bottom lies in interval `last`
    s_half = (half - (t_flight + last * h)) / h
    # Release: the descending motion passes y* at t_d (ys increases up to the bottom).
    k_d, hi = 0, last
    while hi - k_d > 1:
        mid = (k_d + hi) >> 1
        if ys[mid] <= y_release:
            k_d = mid
        else:
            hi = mid
    if ys[k_d + 1] <= y_release:  # in the last, partly used interval
        k_d += 1
    guess = interval_guess(k_d, 1.0, 0.0, 0.0, -y_release, ys, yds, ydds, h)
    s_top = s_half if k_d == last else 1.0
    tol = 1e-15 * (t_flight / h + k_d + 2.0)
    s_d = interval_root(k_d, guess, 0.0, s_top, 1.0, 0.0, 0.0, -y_release, tol, ys, yds, ydds, h)
    t_d = t_flight + (k_d + s_d) * h
    _y, speed_d = table_state(k_d, s_d, ys, yds, ydds, h)
    # ẋ(t) = a (t + t_d) + μ (ẏ(t) + speed_d) with the release at t = -t_d (top at 0); it
    # decreases on [t_d, T - t_d], from its peak to a T <= 0. Its zero lies in the descent
    # (t <= T/2) or in the rise, t = T - σ, with σ read on the same half-orbit table.
    base = accel * t_d + mu * speed_d
    descent = accel * (half + t_d) + mu * speed_d <= 0.0
    k, hi = k_d, last + 1
    while hi - k > 1:
        mid = (k + hi) >> 1
        t_mid = t_flight + mid * h
        if descent:
            before = accel * t_mid + base + mu * yds[mid] > 0.0
        else:
            before = accel * (period - t_mid) + base - mu * yds[mid] <= 0.0
        if before:
            k = mid
        else:
            hi = mid
    # f = -ẋ(t_k + s h) in the descent, ẋ(T - t_k - s h) in the rise: increasing in s.
    t_k = t_flight + k * h
    const = -(accel * t_k + base) if descent else accel * (period - t_k) + base
    gamma = -accel * h
    guess = interval_guess(k, 0.0, -mu, gamma, const, ys, yds, ydds, h)
    s_lo = s_d if k == k_d else 0.0
    s_hi = s_half if k == last else 1.0
    tol = 2e-16 * period / h
    s = interval_root(k, guess, s_lo, s_hi, 0.0, -mu, gamma, const, tol, ys, yds, ydds, h)
    y_stop, _yd = table_state(k, s, ys, yds, ydds, h)
    t = t_flight + (k + s) * h
    if not descent:
        t = period - t
    slip_time = t + t_d
    distance = (
        0.5 * accel * slip_time * slip_time + mu * (y_stop - y_release) + mu * speed_d * slip_time
    )
    # Just above the threshold these terms cancel down to rounding of y (~1e-13 y0); the
    # slider never moves backwards (F >= 0), so a negative residue is no slip at all.
    return slip_time, max(distance, 0.0), max(2.0 * base, 0.0), t_d


def orbit_capacity(steps_per_half: int) -> int:
    """Table length that always suffices for ``steps_per_half``."""
    return 16 * steps_per_half + 16
