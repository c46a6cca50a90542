"""The bracketed search for a sign change on re-stepped trials, shared by every located
search: the core one (:mod:`microslip.integrators.switching`), the normal tape's
(:mod:`microslip.integrators.normal_step`) and the normal flow's
(:mod:`microslip.analysis.normal_flow`), so that their switch instants are the same
bits where their trials are.

A search keeps a bracket [lo, hi] of fractions θ of the step, tries Newton steps inside
it where the value's rate is known and Illinois false position elsewhere, and ends once
the bracket is a few ulps of t wide, with a last trial just past the root. Nothing here
takes a step: the callers do, and hand in each trial's value.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)

__all__ = ["NONE_RETAINED", "bracket_start", "bracket_step", "hermite_start", "theta_tolerance"]

_EPS = 2.220446049250313e-16
# No end of the bracket kept yet (:func:`bracket_step`): a NumPy integer, or the first
# call would pass a literal 0 and compile bracket_step a second time.
NONE_RETAINED = np.int64(0)


@njit(cache=True, inline="always")
def _inside_bracket(theta, lo, hi):
    """θ where it lies inside (lo, hi), else the middle (a bisection)."""
    return theta if lo < theta < hi else 0.5 * (lo + hi)


@njit(cache=True, inline="always")
def _false_position(lo, hi, f_lo, f_hi):
    """The false-position trial in (lo, hi) from the ends' values (the middle where they
    are equal or the trial falls outside)."""
    theta = hi - f_hi * (hi - lo) / (f_hi - f_lo) if f_hi != f_lo else 0.5 * (lo + hi)
    return _inside_bracket(theta, lo, hi)


@njit(cache=True, inline="always")
def theta_tolerance(t, h):
    """The tolerance in θ of a located switch in a step from t [s] of length h [s]: a
    few ulps of t."""
    return 4.0 * _EPS * (abs(t) + abs(h)) / abs(h)


@njit(cache=True)
def bracket_start(t, h, lo, hi, f_lo, f_hi):
    """(θ, tolerance, retained) that start a search of :func:`bracket_step` for a sign
    change in [lo, hi] of a step from t [s] of length h [s], with values ``f_lo``,
    ``f_hi`` at the ends: the false-position trial, the tolerance in θ (a few ulps of
    t) and no end kept yet."""
    return _false_position(lo, hi, f_lo, f_hi), theta_tolerance(t, h), NONE_RETAINED


@njit(cache=True)
def hermite_start(theta, lo, hi, f_lo, f_hi, r_lo, r_hi):
    """A first trial in (lo, hi) better than false position's ``theta``: the root of
    the cubic Hermite interpolant of the ends' values and rates in θ (``r_lo``, ``r_hi``
    = h·ġ), by Newton from ``theta``; ``theta`` where a rate is NaN or the root falls
    outside. A poor start costs trials, never the result: the bracket is kept."""
    if math.isnan(r_lo) or math.isnan(r_hi):
        return theta
    d = hi - lo
    a_lo, a_hi = r_lo * d, r_hi * d  # rates in u = (θ - lo) / d
    u = (theta - lo) / d
    for _ in range(8):  # from false position, 3-4 iterations reach rounding
        u2 = u * u
        u3 = u2 * u
        value = ((2.0 * u3 - 3.0 * u2 + 1.0) * f_lo + (u3 - 2.0 * u2 + u) * a_lo
                 + (3.0 * u2 - 2.0 * u3) * f_hi + (u3 - u2) * a_hi)  # fmt: skip
        slope = ((6.0 * u2 - 6.0 * u) * (f_lo - f_hi) + (3.0 * u2 - 4.0 * u + 1.0) * a_lo
                 + (3.0 * u2 - 2.0 * u) * a_hi)  # fmt: skip
        if not slope != 0.0:
            return theta
        step = value / slope
        u -= step
        if abs(step) <= 1e-15:
            break
    if not 0.0 < u < 1.0:
        return theta
    return _inside_bracket(lo + u * d, lo, hi)


@njit(cache=True)
def bracket_step(theta, lo, hi, f_lo, f_hi, retained, f_mid, same_side, slope, tolerance):
    """One iteration of a search after a trial at fraction ``theta``
    with value ``f_mid`` (on the side of ``f_lo`` when ``same_side``): the bracket
    [lo, hi] and its values updated (Illinois: the end kept twice in a row has its value
    halved), and the next trial. ``slope`` is the value's derivative in θ at the trial
    (NaN: none, false position only); ``retained`` (-1, 0, 1) is the end kept last.
    Returns (θ, lo, hi, f_lo, f_hi, retained), θ inside (lo, hi)."""
    if same_side:
        lo, f_lo = theta, f_mid
        if retained == -1:
            f_hi *= 0.5
        retained = -1
    else:
        hi, f_hi = theta, f_mid
        if retained == 1:
            f_lo *= 0.5
        retained = 1
    if not math.isnan(slope):
        step = f_mid / slope if slope != 0.0 else 0.0
        if slope != 0.0 and abs(step) <= 0.25 * tolerance:
            # Converged: probe just past the root to close the bracket from the far side.
            theta = theta - step + (0.5 * tolerance if retained == -1 else -0.5 * tolerance)
            return _inside_bracket(theta, lo, hi), lo, hi, f_lo, f_hi, retained
        newton = theta - step
        if slope != 0.0 and lo < newton < hi:
            return newton, lo, hi, f_lo, f_hi, retained
    return _false_position(lo, hi, f_lo, f_hi), lo, hi, f_lo, f_hi, retained
