"""The normal motion alone, step by step, with its contact switches located: the
per-step arithmetic of :func:`~microslip.integrators.normal_tape.fill_tape`.

A tape integrates (y, ẏ) of a copy of the model whose tangential side cannot switch
(:func:`~microslip.integrators.normal_tape.normal_coefficients`): the only switching
functions left are the contact functions of :mod:`microslip.model.switching_functions`,
CONTACT_GAP (δ) and, with a damping that can separate inside the overlap, SEPARATION
(N_raw). Both are two-sided (inside iff > 0), and neither is graded (the copy's contact
is rigid), so a flip is reached by a plain RK4 step.

Here they are screened and located as :mod:`~microslip.integrators.switching` does for
the whole model: the same screening (:func:`~microslip.integrators.switching.two_sided_may_flip`),
the same search (Newton on ġ inside the bracket, Illinois false position otherwise:
:func:`~microslip.integrators.bracket.bracket_step`), on trial steps of the same RK4
arithmetic, evaluated by the same law functions. The switch instants are so those of
``simulate(method="rk4")``. Why not call ``first_switch`` itself: it is written for every
switching function of the model and every method (DOP853 among them), and every kernel
that fills a tape compiled all of it, ~11 s of a time map's ~30 s cold compile
(docs/design.md, "Compile time").
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators.bracket import bracket_start, bracket_step
from microslip.integrators.switching import NO_SWITCH, two_sided_may_flip
from microslip.model.damping import can_separate_in_overlap
from microslip.model.excitation import is_prescribed
from microslip.model.normal import (
    acceleration_from_forcing,
    forcing,
    gap_from,
    normal_force_from,
    surface,
)
from microslip.model.switching_functions import (
    contact_side_rate,
    separation_rate,
    separation_value,
)
from microslip.model.system import CONTACT_GAP, SEPARATION

# ``of_rate`` of :func:`_locate` as NumPy booleans: a literal True/False would make numba
# compile it once per value (as switching.locate's).
_OF_RATE = np.bool_(True)
_OF_VALUE = np.bool_(False)


# fill_tape's per-step helpers are inlined into it (inline="always"), and it takes their
# error model: each compiled call passed the coefficient tuple (SIZE floats) by value, a
# third of a step's cost (docs/design.md, "Compile time").
@njit(cache=True, error_model="numpy", inline="always")
def end_values(t, y, ydot, terms, c):
    """(ÿ [m/s^2], N_raw [N], dN_raw/dt [N/s], δ [m], δ̇ [m/s], dN/dt in contact [N/s])
    at a piece end: the normal acceleration, the SEPARATION function and its rate (the
    raw law: continuous through a separation inside the overlap, where the clipped N has
    a kink), the CONTACT_GAP function and its rate, and the rate seen from inside the
    contact (:func:`~microslip.model.switching_functions.contact_side_rate`: at a loss
    of contact at δ = 0 the piece before it ends with the law's slope, S c_n δ̇ for
    m2 = 1, where SEPARATION's rate, past δ = 0, is 0). Computed once per boundary: the
    quartics on either side, the screening of the step and the next step's first RK4
    stage share them. ``terms`` are :func:`time_terms` at t, which the step's last
    stage shares."""
    delta, delta_rate, third = gap_from(terms[1], y, ydot, c)
    acceleration = acceleration_from_forcing(terms[0], normal_force_from(terms[1], y, ydot, c), c)
    delta_accel = third if is_prescribed(c) else acceleration - third
    return (
        acceleration,
        separation_value(delta, delta_rate, c),
        separation_rate(delta, delta_rate, delta_accel, c),
        delta,
        delta_rate,
        contact_side_rate(delta, delta_rate, delta_accel, c),
    )


@njit(cache=True, inline="always")
def time_terms(t, c):
    """What the normal motion's laws read of time at t (a nested tuple): the forcing
    term of the acceleration (:func:`~microslip.model.normal.forcing`) and the surface
    motion or prescribed penetration (:func:`~microslip.model.normal.surface`). Each is
    a sine (and cosine) of the excitation at most; the stages of a step that share a
    time share them."""
    return forcing(t, c), surface(t, c)


@njit(cache=True, inline="always")
def _held_acceleration(terms, y, v, c, flight):
    """ÿ [m/s^2] at a stage whose :func:`time_terms` are ``terms``: N = 0 in flight,
    else the law at the stage state."""
    if flight:
        return acceleration_from_forcing(terms[0], 0.0, c)
    return acceleration_from_forcing(terms[0], normal_force_from(terms[1], y, v, c), c)


@njit(cache=True, error_model="numpy", inline="always")
def rk4(t, h, t1, y, v, a1, terms_end, c, flight):
    """One RK4 step of the normal motion alone: the arithmetic of
    :func:`~microslip.integrators.steppers.rk4_step` on the (y, ẏ) components; ``a1`` is
    ÿ at the step start (from :func:`end_values`). In ``flight`` N = 0 at every stage
    (the mode holds the contact: :func:`~microslip.model.system.derivatives`). The last
    stage is at ``t1``, the step's end (its grid point), which is t + h to the bit
    wherever t >= t1/2 (then h = t1 - t is exact, by Sterbenz's lemma): every step but
    one that starts at a switch inside the first grid interval. What the laws read of
    time (:func:`time_terms`: the sine of a harmonic force, the sine and cosine of a
    base motion) is evaluated once for the two middle stages, and taken at ``t1`` as
    ``terms_end``, which the step's end values share (:func:`end_values`): two
    evaluations a step instead of four (a harmonic force) or seven (a base motion),
    the same bits."""
    hh = 0.5 * h
    terms_mid = time_terms(t + hh, c)
    y2, v2 = y + hh * v, v + hh * a1
    a2 = _held_acceleration(terms_mid, y2, v2, c, flight)
    y3, v3 = y + hh * v2, v + hh * a2
    a3 = _held_acceleration(terms_mid, y3, v3, c, flight)
    y4, v4 = y + h * v3, v + h * a3
    a4 = _held_acceleration(terms_end, y4, v4, c, flight)
    w = h / 6.0
    return y + w * (v + 2.0 * v2 + 2.0 * v3 + v4), v + w * (a1 + 2.0 * a2 + 2.0 * a3 + a4)


@njit(cache=True, inline="always")
def _function(which, ends):
    """(g, ġ) of contact function ``which`` from :func:`end_values`."""
    if which == CONTACT_GAP:
        return ends[3], ends[4]
    return ends[1], ends[2]


@njit(cache=True, inline="always")
def _may_flip(which, h, ends0, ends1):
    """The screening of :mod:`~microslip.integrators.switching` of contact function
    ``which`` over a step of length h [s], on the end values."""
    g0, r0 = _function(which, ends0)
    g1, r1 = _function(which, ends1)
    return two_sided_may_flip(g0, g1, r0, r1, h)


@njit(cache=True, inline="always")
def may_switch(h, ends0, ends1, c):
    """False when neither contact function can flip inside the step."""
    if _may_flip(CONTACT_GAP, h, ends0, ends1):
        return True
    return can_separate_in_overlap(c) and _may_flip(SEPARATION, h, ends0, ends1)


@njit(cache=True, error_model="numpy")
def _locate(which, of_rate, t, h, y, v, a0, c, flight, lo, hi, f_lo, f_hi):
    """Fraction θ in (lo, hi] of the step from (t, y, ẏ) of length h [s] where contact
    function ``which`` (its rate, when ``of_rate``) changes sign: the search of
    :func:`~microslip.integrators.switching.locate` on trial steps of :func:`rk4`
    (``a0`` = ÿ at the step start). Returns the first θ known to lie past the flip."""
    side_lo = f_lo > 0.0
    theta, tolerance, retained = bracket_start(t, h, lo, hi, f_lo, f_hi)
    for _ in range(200):
        if hi - lo <= tolerance:
            break
        t_mid = t + theta * h
        terms_mid = time_terms(t_mid, c)
        y_mid, v_mid = rk4(t, theta * h, t_mid, y, v, a0, terms_mid, c, flight)
        g, rate = _function(which, end_values(t_mid, y_mid, v_mid, terms_mid, c))
        f_mid = rate if of_rate else g
        slope = math.nan if of_rate else rate * h
        theta, lo, hi, f_lo, f_hi, retained = bracket_step(
            theta, lo, hi, f_lo, f_hi, retained, f_mid, (f_mid > 0.0) == side_lo, slope, tolerance
        )
    return hi


@njit(cache=True, error_model="numpy")
def contact_switch(t, h, y, v, ends0, ends1, c, flight):
    """(θ, which): the earliest flip of a contact function inside the step of length
    h [s] from (t, y [m], ẏ [m/s]), ``ends0``, ``ends1`` the :func:`end_values` at its
    ends, or (NO_SWITCH, -1). As :func:`~microslip.integrators.switching.first_switch`:
    a sign change between the ends is located; else an extremum that turns g back
    towards zero is (a root of ġ), and a crossing before it. On a tie CONTACT_GAP wins
    (listed first by the model)."""
    best = NO_SWITCH
    which_best = -1
    for which in (CONTACT_GAP, SEPARATION):
        if which == SEPARATION and not can_separate_in_overlap(c):
            continue
        if not _may_flip(which, h, ends0, ends1):
            continue
        g0, r0 = _function(which, ends0)
        g1, r1 = _function(which, ends1)
        in0 = g0 > 0.0
        if (g1 > 0.0) != in0:
            theta = _locate(which, _OF_VALUE, t, h, y, v, ends0[0], c, flight, 0.0, 1.0, g0, g1)
        else:
            theta = NO_SWITCH
            theta_x = _locate(which, _OF_RATE, t, h, y, v, ends0[0], c, flight, 0.0, 1.0, r0, r1)
            if 0.0 < theta_x < 1.0:
                t_x = t + theta_x * h
                terms_x = time_terms(t_x, c)
                y_x, v_x = rk4(t, theta_x * h, t_x, y, v, ends0[0], terms_x, c, flight)
                g_x = _function(which, end_values(t_x, y_x, v_x, terms_x, c))[0]
                if (g_x > 0.0) != in0:
                    theta = _locate(
                        which, _OF_VALUE, t, h, y, v, ends0[0], c, flight, 0.0, theta_x, g0, g_x
                    )
        if theta < best:
            best = theta
            which_best = which
    return best, which_best
