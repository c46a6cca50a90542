"""Reading a periodic orbit's table: the state at any instant by quintic Hermite
interpolation on its nodes (the tables of :func:`microslip.analysis.periodic.periodic_orbit`
and of the free vibration's half orbit, read by :mod:`microslip.analysis.normal_pieces`).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)

__all__ = ["orbit_state"]

_WALK = 4  # interval steps from the proportional guess before a binary search


@njit(cache=True, inline="always")
def _interval(t, t_nodes):
    """The last k in [0, n - 2] with t_nodes[k] <= t (0 if none): numpy's
    searchsorted(side="right") - 1, clipped. The tables are near-uniform (a fixed step
    with a few switches inserted), so the proportional guess is within a step or two:
    a short walk from it replaces the binary search, whose ~11 unpredictable branches
    on a table of ~1000 nodes cost several times the interpolation itself."""
    n = t_nodes.shape[0]
    span = t_nodes[n - 1] - t_nodes[0]
    guess = (t - t_nodes[0]) / span * (n - 1) if span > 0.0 else 0.0
    k = int(min(max(guess, 0.0), n - 2.0)) if guess == guess else 0  # clipped before int
    for _ in range(_WALK):
        if k < n - 2 and t_nodes[k + 1] <= t:
            k += 1
        elif k > 0 and t_nodes[k] > t:
            k -= 1
        else:
            return k
    k = np.searchsorted(t_nodes, t, side="right") - 1
    return min(max(k, 0), n - 2)


@njit(cache=True, inline="always")
def orbit_state(t, t_nodes, y, ydot, accel_start, accel_end):
    """(y [m], ẏ [m/s]) at t in [t_nodes[0], t_nodes[-1]] by quintic Hermite interpolation
    on the interval holding t (values, slopes and accelerations at both ends)."""
    k = _interval(t, t_nodes)
    n = t_nodes.shape[0]
    while k < n - 2 and t_nodes[k + 1] <= t_nodes[k]:
        k += 1  # a zero-length interval (switch on a grid point)
    h = t_nodes[k + 1] - t_nodes[k]
    if h <= 0.0:
        return y[k], ydot[k]
    u = (t - t_nodes[k]) / h
    u2 = u * u
    u3 = u2 * u
    u4 = u3 * u
    u5 = u4 * u
    p0, p1 = y[k], y[k + 1]
    v0, v1 = ydot[k] * h, ydot[k + 1] * h
    a0, a1 = accel_start[k] * h * h, accel_end[k] * h * h
    value = (
        (1.0 - 10.0 * u3 + 15.0 * u4 - 6.0 * u5) * p0
        + (u - 6.0 * u3 + 8.0 * u4 - 3.0 * u5) * v0
        + 0.5 * (u2 - 3.0 * u3 + 3.0 * u4 - u5) * a0
        + 0.5 * (u3 - 2.0 * u4 + u5) * a1
        + (-4.0 * u3 + 7.0 * u4 - 3.0 * u5) * v1
        + (10.0 * u3 - 15.0 * u4 + 6.0 * u5) * p1
    )
    slope = (
        (-30.0 * u2 + 60.0 * u3 - 30.0 * u4) * p0
        + (1.0 - 18.0 * u2 + 32.0 * u3 - 15.0 * u4) * v0
        + 0.5 * (2.0 * u - 9.0 * u2 + 12.0 * u3 - 5.0 * u4) * a0
        + 0.5 * (3.0 * u2 - 8.0 * u3 + 5.0 * u4) * a1
        + (-12.0 * u2 + 28.0 * u3 - 15.0 * u4) * v1
        + (30.0 * u2 - 60.0 * u3 + 30.0 * u4) * p1
    )
    return value, slope / h
