"""The explicit switching loop: trial step, locate the first switch, switch, go on.

One compiled loop serves every method: fixed-step RK4 on the grid t0 + k·dt, and the
adaptive Dormand–Prince pairs. It fills caller-owned output buffers and returns when
they are full, so the Python driver can stream a long run in bounded memory. The state
is an array of any size; the model (:mod:`microslip.model.system`) gives it meaning.

Speed. A compiled function that takes arrays reference-counts them (atomic increments
and decrements of the arrays' counters) on entry and exit unless numba can prove the
pair useless, which it cannot once the function calls other compiled functions or has
a raising branch; a row view (``work[0]``) is counted too, as are the arguments of a
function inlined by numba. A common step therefore makes no such call: the steps are
called directly (not through ``advance``), have the model inlined and no raising branch
(error_model="numpy"), and the switching screen
(:func:`~microslip.integrators.switching.may_switch`) takes state tuples; the arrays go
to the locating (:func:`piece_end`) only when a switch may be inside the step.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators.dop853 import dop853_step
from microslip.integrators.methods import CONTROLLER_EXPONENT, RK4, WORK_ROWS, advance
from microslip.integrators.steppers import GRADED_FINEST, rk4_step
from microslip.integrators.switching import NO_SWITCH, first_switch, may_switch, method_for
from microslip.model.coefficients import as_tuple
from microslip.model.switches import apply_switch
from microslip.model.switching_functions import graded_after
from microslip.model.system import NO_EVENT, state_tuple

# Slots of the carry vector that holds the loop state between calls; the state follows.
C_T, C_MODE, C_H, C_K, C_BOUNDARY, C_TEVAL, C_T0, C_STEPS, C_REJECTS = range(9)
C_GRADING, C_GRADED_FROM = 9, 10  # leaving a graded switch (1.0) made at t [s]
C_STATE = 11

# Return status.
DONE = 0
OUTPUT_FULL = 1
EVENTS_FULL = 2
STALLED = 3
STEP_UNDERFLOW = 4

MAX_SWITCHES_PER_STEP = 64


def carry_size(n_state: int) -> int:
    """Length of the carry vector for a state of ``n_state`` values."""
    return C_STATE + n_state


@njit(cache=True)
def next_grid_point(t, t0, k, dt, t_end):
    """(target [s], k): the first point t0 + k·dt of the fixed-step grid past t (from
    index k on), or t_end when that is past, or within 1e-9 dt of, the end."""
    while True:
        target = t0 + k * dt
        if target >= t_end or t_end - target < 1e-9 * dt:
            target = t_end
        if target > t:
            return target, k
        k += 1


@njit(cache=True)
def time_grid(t_end, dt):
    """Step ends of the RK4 grid from t = 0: k·dt, the last one clipped to ``t_end``
    (:func:`next_grid_point`, the rule of ``integrate_chunk``)."""
    out = np.empty(int(t_end / dt) + 3)
    t, k, count = 0.0, 1, 0
    while t < t_end:
        t, k = next_grid_point(t, 0.0, k, dt, t_end)
        out[count] = t
        count += 1
        k += 1
    return out[:count]


@njit(cache=True)
def graded_target(t, target, graded_from, dt):
    """(end [s], on the grid, still grading) of a fixed step from t [s] towards the grid
    point ``target`` [s] while leaving a graded switch made at ``graded_from`` [s]: the
    step is as long as the time since the switch (at least GRADED_FINEST·dt), so steps
    double from the switch until they reach the grid (docs/theory/numerics.md, "Order
    at a touchdown"). A doubled step that would end within half of itself of the grid
    point goes to the grid point. Grading ends with the step to the first grid point at
    least dt/2 past the switch."""
    length = max(t - graded_from, dt * GRADED_FINEST)
    if t + 1.5 * length < target:
        return t + length, False, True
    return target, True, target - graded_from < 0.5 * dt


@njit(cache=True)
def copy_state(src, dst):
    for i in range(src.shape[0]):
        dst[i] = src[i]


@njit(cache=True)
def piece_end(method, s, s1, t, h, mode, c, rtol, atol, piece, trial, extremum, work):
    """The first switch in the trial step (t, s) -> (t + h, s1) and the state there.

    Writes into ``piece`` the state at the end of the piece: at the switch, or ``s1``
    when the step holds none. Returns (θ, which) as
    :func:`~microslip.integrators.switching.first_switch`. The one piece of loop body
    shared by :func:`integrate_chunk` and the batched kernel, which call it only when
    :func:`~microslip.integrators.switching.may_switch` says a switch may be inside.
    """
    theta, which, held = first_switch(
        method, s, s1, t, h, mode, c, rtol, atol, trial, extremum, work
    )
    if which >= 0 and theta < 1.0:
        if held:  # the locating's last trial past the flip: that very step
            copy_state(extremum, piece)
        else:
            advance(method_for(method, which, c), s, t, theta * h, mode, c, rtol, atol, piece,
                    work)  # fmt: skip
    else:
        copy_state(s1, piece)
    return theta, which


@njit(cache=True)  # not inlined: the arguments of an inlined function are counted
def _write(out_t, out_s, out_mode, n, t, s, mode):
    out_t[n] = t
    for j in range(s.shape[0]):
        out_s[n, j] = s[j]
    out_mode[n] = mode
    return n + 1


@njit(cache=True)
def integrate_chunk(
    method, carry, t_end, dt, h_max, rtol, atol, c, t_eval, save_every,
    out_t, out_s, out_mode, ev_t, ev_kind, ev_s,
):  # fmt: skip
    """Advance the carried state towards ``t_end`` [s]; returns (n_out, n_events, status).

    Outputs: at each requested time in ``t_eval`` if it is non-empty, else at every
    ``save_every``-th step boundary (a boundary is a step end or a switching instant)
    and at ``t_end``. Every switching instant that changes the mode or the contact is
    recorded in the event buffers.
    """
    # The coefficients as a tuple: passed by value through the inlined laws, where an
    # array would be reference-counted at every call (atomic operations per law).
    c = as_tuple(c)
    n_state = carry.shape[0] - C_STATE
    cap = out_t.shape[0]
    ev_cap = ev_t.shape[0]
    n_out = np.int64(0)  # not a literal 0: one compile of _write (docs/design.md)
    n_ev = 0
    # Scratch for the whole call: no allocation per step.
    s = carry[C_STATE:].copy()
    s1 = np.empty(n_state)
    piece = np.empty(n_state)
    s_eval = np.empty(n_state)
    trial = np.empty(n_state)
    extremum = np.empty(n_state)
    work = np.empty((WORK_ROWS, n_state))
    t = carry[C_T]
    mode = carry[C_MODE]
    h_ctrl = carry[C_H]
    k = int(carry[C_K])
    boundary = int(carry[C_BOUNDARY])
    i_eval = int(carry[C_TEVAL])
    t0 = carry[C_T0]
    n_steps = int(carry[C_STEPS])
    n_rejects = int(carry[C_REJECTS])
    use_t_eval = t_eval.shape[0] > 0
    exponent = CONTROLLER_EXPONENT[method]
    grading = carry[C_GRADING] != 0.0
    graded_from = carry[C_GRADED_FROM]
    on_grid = True
    switches_in_step = 0
    aimed = False  # the last trial step was aimed at a switch of a rejected one
    status = DONE
    while t < t_end:
        if n_out >= cap - 1:
            status = OUTPUT_FULL
            break
        if method == RK4:
            target, k = next_grid_point(t, t0, k, dt, t_end)
            on_grid = True
            if grading:
                target, on_grid, grading = graded_target(t, target, graded_from, dt)
            h = target - t
        else:
            h = min(h_ctrl, h_max)
            target = t + h
            if target >= t_end:
                h = t_end - t
                target = t_end
        # The steps called directly, not through ``advance`` (module doc, "Speed").
        if method == RK4:
            rk4_step(s, t, h, mode, c, s1, work)
            err = 0.0
        else:
            err = dop853_step(s, t, h, mode, c, rtol, atol, s1, work)
        if method != RK4 and not err <= 1.0:
            n_rejects += 1
            factor = 0.2 if err != err else max(0.2, 0.9 * err**exponent)
            h_ctrl = h * factor
            # A rejected trial step may cross a switch where the right-hand side has a
            # kink (a friction or contact law changing form): its error is then no guide
            # to a smooth step, and shrinking by it alone can creep towards the switch
            # without ever reaching it (step underflow). Aim once at the switch instead:
            # the step to it is smooth, and the switch is then located as usual.
            if not aimed and may_switch(t, h, mode, c, state_tuple(s), state_tuple(s1)):
                theta, which, _held = first_switch(
                    method, s, s1, t, h, mode, c, rtol, atol, trial, extremum, work
                )
                if which >= 0 and factor < theta < 1.0:
                    h_ctrl = theta * h
                    aimed = True
                    continue
            aimed = False
            if h_ctrl <= 1e-14 * (abs(t) + abs(h)):
                status = STEP_UNDERFLOW
                break
            continue
        aimed = False
        if may_switch(t, h, mode, c, state_tuple(s), state_tuple(s1)):
            theta, which = piece_end(
                method, s, s1, t, h, mode, c, rtol, atol, piece, trial, extremum, work
            )
        else:
            theta, which = NO_SWITCH, -1
            copy_state(s1, piece)
        t_piece = t + theta * h if which >= 0 and theta < 1.0 else target
        if use_t_eval:
            # A time equal to the piece end is written by the next piece (or the final
            # flush), from the state after any switch there.
            while i_eval < t_eval.shape[0] and t_eval[i_eval] < t_piece:
                if n_out >= cap - 1:
                    status = OUTPUT_FULL
                    break
                te = t_eval[i_eval]
                if te <= t:
                    n_out = _write(out_t, out_s, out_mode, n_out, te, s, mode)
                else:
                    advance(method, s, t, te - t, mode, c, rtol, atol, s_eval, work)
                    n_out = _write(out_t, out_s, out_mode, n_out, te, s_eval, mode)
                i_eval += 1
            if status == OUTPUT_FULL:
                break
        if which >= 0:
            if n_ev >= ev_cap:
                status = EVENTS_FULL
                break
            switches_in_step += 1
            if switches_in_step > MAX_SWITCHES_PER_STEP:
                status = STALLED
                break
            mode, kind = apply_switch(which, t_piece, piece, mode, c)
            if method == RK4 and graded_after(which, mode, c):
                grading = True  # leave it by graded steps too (graded_target)
                graded_from = t_piece
            if kind != NO_EVENT:
                ev_t[n_ev] = t_piece
                ev_kind[n_ev] = kind
                for j in range(n_state):
                    ev_s[n_ev, j] = piece[j]
                n_ev += 1
        if which < 0 or theta >= 1.0:
            switches_in_step = 0
            n_steps += 1
            if method == RK4:
                if on_grid:
                    k += 1
            elif err > 0.0:
                h_ctrl = h * min(10.0, 0.9 * err**exponent)
            else:
                h_ctrl = h * 10.0
        t = t_piece
        copy_state(piece, s)
        boundary += 1
        if not use_t_eval and (boundary % save_every == 0 or t >= t_end):
            n_out = _write(out_t, out_s, out_mode, n_out, t, s, mode)
    if status == DONE and use_t_eval:
        while i_eval < t_eval.shape[0] and t_eval[i_eval] <= t:
            if n_out >= cap:
                status = OUTPUT_FULL
                break
            n_out = _write(out_t, out_s, out_mode, n_out, t_eval[i_eval], s, mode)
            i_eval += 1
    carry[C_T] = t
    for j in range(n_state):
        carry[C_STATE + j] = s[j]
    carry[C_MODE] = mode
    carry[C_H] = h_ctrl
    carry[C_K] = k
    carry[C_BOUNDARY] = boundary
    carry[C_TEVAL] = i_eval
    carry[C_STEPS] = n_steps
    carry[C_REJECTS] = n_rejects
    carry[C_GRADING] = 1.0 if grading else 0.0
    carry[C_GRADED_FROM] = graded_from
    return n_out, n_ev, status
