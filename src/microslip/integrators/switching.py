"""Located switching: the instants where the model's mode or smoothness changes.

The mode (opaque here: :mod:`microslip.model.system` defines it) is held fixed over a
step. After each trial step every active switching function g of the model is checked;
where one changes sides its root is found by re-stepping the same method from the step
start over a fraction θ of the step (Newton on the rate ġ along the motion, Illinois
false position as the fallback), so the switching instant carries the method's own
accuracy and a fixed-step method keeps its order (docs/model-facts.md, "Numerical
pitfalls").

A switching function can cross zero twice inside one step and show no sign change at
the step ends. That needs an interior extremum: its rate ġ changes sign inside the step,
turning g back towards zero. Since g moves by at most about h·max|ġ| inside the step, a
crossing is possible only if min(|g0|, |g1|) <= 2h(|ġ0| + |ġ1|) (a factor 2 of safety
over the linear-rate bound h(|ġ0| + |ġ1|)/2). Then the extremum (a root of ġ, located by
Illinois false position, no Newton) is checked, and a crossing before it located.

A mode that exists only on the inside of its function (sliding in direction s: s·ẋ > 0)
can start on the boundary: right after a release the sliding speed is exactly 0. The
speed must first rise, so only a return to zero after its maximum counts.

Nothing here knows what the state variables mean or how many there are.

Every step runs the screening (the switching functions and their rates at the step
ends) on state tuples (:func:`~microslip.model.system.state_tuple`), which go by value
through compiled calls; the state arrays reach only the locating, when a switch may be
inside the step. An array argument is reference-counted at every compiled call, with
atomic operations that would cost more per step than the laws.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators.bracket import (
    bracket_start,
    bracket_step,
    hermite_start,
    theta_tolerance,
)
from microslip.integrators.methods import RK4, RK4_GRADED, advance
from microslip.model.switching_functions import (
    graded_switch,
    holds_only_inside,
    inside,
    switch_active,
    switching_rate,
    switching_value,
)
from microslip.model.system import EVENT_NAMES, N_SWITCHES, state_tuple

__all__ = [
    "EVENT_NAMES",
    "NO_SWITCH",
    "first_switch",
    "locate",
    "may_switch",
    "method_for",
    "two_sided_may_flip",
]

NO_SWITCH = 2.0  # θ returned when a step holds no switch
_BOUND_SAFETY = 2.0  # on the linear-rate bound of an interior excursion

# Verdicts of the screening of one switching function over a step.
_CLEAR = 0  # no switch inside the step
_CROSSING = 1  # g changes sides between the step ends
_EXTREMUM = 2  # g may cross at an interior extremum (a root of ġ)

# ``of_rate`` of :func:`locate` as NumPy booleans: a literal True/False would make numba
# compile locate (and the step it inlines) once per value.
_OF_RATE = np.bool_(True)
_OF_VALUE = np.bool_(False)


@njit(cache=True)
def _evaluate(which, of_rate, t, x, mode, c):
    if of_rate:
        return switching_rate(which, t, x, mode, c)
    return switching_value(which, t, x, mode, c)


@njit(cache=True)
def _side(which, of_rate, value):
    if of_rate:
        return value > 0.0
    return inside(which, value)


@njit(cache=True)
def locate(which, of_rate, method, s0, t, h, mode, c, rtol, atol, lo, hi, f_lo, f_hi, r_lo,
           r_hi, trial, work, at_hi):  # fmt: skip
    """(θ, held): the fraction θ in (lo, hi] of the step where switching function
    ``which`` flips (its rate ġ, when ``of_rate``), and whether ``at_hi`` holds the step
    of length θh from ``s0``. ``r_lo``, ``r_hi``: the rates in θ at the ends, where the
    caller has them for a first trial by :func:`hermite_start` (NaN: false position).

    Each trial state is a step of length θh from ``s0`` (written into ``trial``). For g
    itself Newton steps use ġ; the bracket [lo, hi] is kept, and a trial outside it falls
    back to Illinois false position (the only iteration for ġ): :func:`bracket_step`.
    Returns the first θ known to lie past the flip, to within a few ulps of t. Each
    trial that becomes the bracket's far end is copied into ``at_hi``: the caller steps
    to the flip from there instead of taking that step once more (the same bits: a step
    depends only on its start, length, mode and coefficients).
    """
    side_lo = _side(which, of_rate, f_lo)
    theta, tolerance, retained = bracket_start(t, h, lo, hi, f_lo, f_hi)
    theta = hermite_start(theta, lo, hi, f_lo, f_hi, r_lo, r_hi)
    held = False
    for _ in range(200):
        if hi - lo <= tolerance:
            break
        advance(method, s0, t, theta * h, mode, c, rtol, atol, trial, work)
        t_mid = t + theta * h
        x_mid = state_tuple(trial)
        f_mid = _evaluate(which, of_rate, t_mid, x_mid, mode, c)
        slope = math.nan if of_rate else switching_rate(which, t_mid, x_mid, mode, c) * h
        same_side = _side(which, of_rate, f_mid) == side_lo
        if not same_side:  # this trial becomes hi
            for i in range(trial.shape[0]):
                at_hi[i] = trial[i]
            held = True
        theta, lo, hi, f_lo, f_hi, retained = bracket_step(
            theta, lo, hi, f_lo, f_hi, retained, f_mid, same_side, slope, tolerance
        )
    return hi, held


# Inlined into its two callers (may_switch, every step; first_switch): a compiled call
# passed the coefficient tuple and both state tuples by value (docs/design.md).
@njit(cache=True, error_model="numpy", inline="always")
def _screen(which, t, h, mode, c, x0, x1):
    """(verdict, g0, g1, ġ0, ġ1) of switching function ``which`` over the step from
    (t, x0) to (t + h, x1) (state tuples): _CLEAR, _CROSSING (a sign change between the
    step ends) or _EXTREMUM (an interior extremum may hide a crossing; ġ0, ġ1 bracket
    it)."""
    g0 = switching_value(which, t, x0, mode, c)
    g1 = switching_value(which, t + h, x1, mode, c)
    in0 = inside(which, g0)
    in1 = inside(which, g1)
    if (not in0) and holds_only_inside(which):
        r1 = switching_rate(which, t + h, x1, mode, c)
        # On the boundary of a mode entered right here: g must first rise; a flip can
        # only come after its maximum, and only if g ends outside.
        if in1 or r1 > 0.0:
            return _CLEAR, g0, g1, 0.0, r1
        r0 = abs(switching_rate(which, t, x0, mode, c))
        if r0 == 0.0:
            r0 = 1e-300  # ġ(0) is zero up to rounding at a release: rising by definition
        return _EXTREMUM, g0, g1, r0, r1
    if in1 != in0:
        return _CROSSING, g0, g1, 0.0, 0.0
    # Only an extremum that turns g back towards zero can hide a double crossing:
    # a minimum from the inside (g > 0), a maximum from the outside.
    towards = 1.0 if in0 else -1.0
    r0 = switching_rate(which, t, x0, mode, c)
    if not towards * r0 < 0.0:
        return _CLEAR, g0, g1, r0, 0.0
    r1 = switching_rate(which, t + h, x1, mode, c)
    if _extremum_may_cross(towards, g0, g1, r0, r1, h):
        return _EXTREMUM, g0, g1, r0, r1
    return _CLEAR, g0, g1, r0, r1


@njit(cache=True)
def _extremum_may_cross(towards, g0, g1, r0, r1, h):
    """For g heading towards zero at the step start (towards·ġ0 < 0): True when ġ has
    turned by the step end and the linear-rate bound lets the extremum reach zero."""
    if not towards * r1 > 0.0:
        return False
    return not min(abs(g0), abs(g1)) > _BOUND_SAFETY * h * (abs(r0) + abs(r1))


@njit(cache=True)
def two_sided_may_flip(g0, g1, r0, r1, h):
    """The screening of a two-sided switching function (CONTACT_GAP, SEPARATION: inside
    iff g > 0) from its values g0, g1 and rates ġ0, ġ1 at the ends of a step of length
    h [s]: True where :func:`_screen` would not clear the step. For a caller that has
    all four already (the normal tape)."""
    in0 = g0 > 0.0
    if (g1 > 0.0) != in0:
        return True
    towards = 1.0 if in0 else -1.0
    return towards * r0 < 0.0 and _extremum_may_cross(towards, g0, g1, r0, r1, h)


@njit(cache=True)
def _resolve(
    verdict, which, method, s0, t, h, mode, c, rtol, atol, g0, g1, r0, r1, trial, extremum, work
):  # fmt: skip
    """(θ, held): θ of the first flip of switching function ``which`` in the step after
    a verdict of :func:`_screen` other than _CLEAR, or NO_SWITCH; held where
    ``extremum`` holds the step to θ (:func:`locate`). ``r0``, ``r1``: for an extremum
    the rates in θ at the ends; for a crossing those rates where the caller computed
    them (:func:`first_switch`), else NaN."""
    if verdict == _CROSSING:
        return locate(
            which, _OF_VALUE, method, s0, t, h, mode, c, rtol, atol, 0.0, 1.0, g0, g1, r0, r1,
            trial, work, extremum,
        )  # fmt: skip
    in0 = inside(which, g0)
    rising = (not in0) and holds_only_inside(which)
    theta_x, held = locate(
        which, _OF_RATE, method, s0, t, h, mode, c, rtol, atol, 0.0, 1.0, r0, r1, math.nan,
        math.nan, trial, work, extremum,
    )  # fmt: skip
    if not (0.0 < theta_x < 1.0):
        return NO_SWITCH, False
    if not held:
        advance(method, s0, t, theta_x * h, mode, c, rtol, atol, extremum, work)
    gx = switching_value(which, t + theta_x * h, state_tuple(extremum), mode, c)
    if rising:
        if inside(which, gx):  # rose, then falls back through zero by the step end
            return locate(
                which, _OF_VALUE, method, s0, t, h, mode, c, rtol, atol, theta_x, 1.0, gx, g1,
                math.nan, math.nan, trial, work, extremum,
            )  # fmt: skip
        return NO_SWITCH, False
    if inside(which, gx) != in0:
        return locate(
            which, _OF_VALUE, method, s0, t, h, mode, c, rtol, atol, 0.0, theta_x, g0, gx,
            math.nan, math.nan, trial, work, extremum,
        )  # fmt: skip
    return NO_SWITCH, False


@njit(cache=True, error_model="numpy")
def may_switch(t, h, mode, c, x0, x1):
    """False when no switching function of the model can flip inside the step from
    (t, x0) to (t + h, x1) (state tuples): the common step, screened without arrays."""
    for which in range(N_SWITCHES):
        if switch_active(which, mode, c) and _screen(which, t, h, mode, c, x0, x1)[0] != _CLEAR:
            return True
    return False


@njit(cache=True)
def method_for(method, which, c):
    """The method that locates, and steps to, a flip of switching function ``which``:
    RK4 on sub-steps graded towards the flip (``RK4_GRADED``) where the model grades
    that function (:func:`~microslip.model.switching_functions.graded_switch`), else
    ``method`` itself."""
    if method == RK4 and graded_switch(which, c):
        return RK4_GRADED
    return method


@njit(cache=True)
def first_switch(method, s0, s1, t, h, mode, c, rtol, atol, trial, extremum, work):
    """Earliest switching inside a trial step from (t, s0) to (t + h, s1).

    ``trial`` and ``extremum`` are scratch states, ``work`` the steps' scratch (see
    :func:`microslip.integrators.methods.advance`). Returns (θ, which, held) with θ in
    (0, 1], or (NO_SWITCH, -1, False) when the step holds no switch; held where
    ``extremum`` holds the step of length θh from ``s0`` (its locating's last trial past
    the flip). On a tie (flips within two tolerances of each other) the function listed
    first by the model wins. A flip is located with :func:`method_for`'s method, which
    the caller also takes to step to it.

    The functions go in the model's order, the normal motion's (the contact) first.
    Once one flips at θ, each later one is screened and located only on the sub-step
    up to just before θ: a flip after θ cannot come first, and past a
    loss of contact the tangential functions' laws change, so their values and rates
    jump there. Screened over the whole step, such a jump looked like a crossing or an
    extremum, and its search crawled up to it (on a Hertz Mindlin contact, ~50 trial
    steps for a sliding point at every lift-off, up to the 200-iteration cap for a rate).
    """
    x0 = state_tuple(s0)
    x1 = state_tuple(s1)
    best = NO_SWITCH
    which_best = -1
    # The (sub-)step screened: the whole one, or up to two tolerances short of the
    # earliest flip found (one call site of the inlined screening either way). A
    # sub-step is stepped once for each earliest flip and method, not once a function.
    end, h_end, x_end = 1.0, h, x1
    sub_best, sub_method = NO_SWITCH, -1
    best_held = False
    for which in range(N_SWITCHES):
        if not switch_active(which, mode, c):
            continue
        located_by = method_for(method, which, c)
        if best < NO_SWITCH and (best != sub_best or located_by != sub_method):
            end = best - 2.0 * theta_tolerance(t, h)
            if not end > 0.0:
                continue
            h_end = end * h
            advance(located_by, s0, t, h_end, mode, c, rtol, atol, trial, work)
            x_end = state_tuple(trial)
            sub_best, sub_method = best, located_by
        verdict, g0, g1, r0, r1 = _screen(which, t, h_end, mode, c, x0, x_end)
        if verdict == _CLEAR:
            continue
        if verdict == _CROSSING:
            # A start from the ends' rates saves one of ~4 trials: worth two rate
            # evaluations on graded trials only (docs/design.md, "The state and the
            # integrators": plain RK4's cost as much, DOP853's keep their grazing stops).
            r0, r1 = math.nan, math.nan
            if located_by == RK4_GRADED:
                r0 = switching_rate(which, t, x0, mode, c) * h_end
                r1 = switching_rate(which, t + h_end, x_end, mode, c) * h_end
        theta, held = _resolve(
            verdict, which, located_by, s0, t, h_end, mode, c, rtol, atol, g0, g1, r0, r1,
            trial, extremum, work,
        )  # fmt: skip
        if theta < NO_SWITCH:
            theta *= end  # a fraction of the whole step (exact for the whole step)
        if theta < best:
            best = theta
            which_best = which
            # On a sub-step, (θ·end)·h may round apart from θ·(end·h): step again.
            best_held = held and end == 1.0
        else:
            best_held = False  # ``extremum`` may have been written over
    return best, which_best, best_held
