"""The explicit stick–slip loop: trial step, locate the first switch, switch, go on.

One compiled loop serves every method: fixed-step RK4 on the grid t0 + k·dt, and the
adaptive Dormand–Prince pairs. It fills caller-owned output buffers and returns when
they are full, so the Python driver can stream a long run in bounded memory.
"""

from __future__ import annotations

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators.methods import CONTROLLER_EXPONENT, RK4, advance
from microslip.integrators.switching import apply_switch, first_switch

# Slots of the carry vector that holds the loop state between calls.
C_T, C_Y, C_YD, C_X, C_XD, C_DIR, C_H, C_K, C_BOUNDARY, C_TEVAL, C_T0, C_STEPS, C_REJECTS = range(
    13
)
CARRY_SIZE = 13

# Return status.
DONE = 0
OUTPUT_FULL = 1
EVENTS_FULL = 2
STALLED = 3
STEP_UNDERFLOW = 4

_MAX_SWITCHES_PER_STEP = 64


@njit(cache=True, inline="always")
def _write(out_t, out_s, out_dir, n, t, s, direction):
    out_t[n] = t
    out_s[n, 0] = s[0]
    out_s[n, 1] = s[1]
    out_s[n, 2] = s[2]
    out_s[n, 3] = s[3]
    out_dir[n] = direction
    return n + 1


@njit(cache=True)
def integrate_chunk(
    method, carry, t_end, dt, h_max, rtol, atol, c, t_eval, save_every,
    out_t, out_s, out_dir, ev_t, ev_kind, ev_s,
):  # fmt: skip
    """Advance the carried state towards ``t_end`` [s]; returns (n_out, n_events, status).

    Outputs: at each requested time in ``t_eval`` if it is non-empty, else at every
    ``save_every``-th step boundary (a boundary is a step end or a switching instant)
    and at ``t_end``. Every switching instant is recorded in the event buffers.
    """
    cap = out_t.shape[0]
    ev_cap = ev_t.shape[0]
    n_out = 0
    n_ev = 0
    t = carry[C_T]
    s = (carry[C_Y], carry[C_YD], carry[C_X], carry[C_XD])
    direction = carry[C_DIR]
    h_ctrl = carry[C_H]
    k = int(carry[C_K])
    boundary = int(carry[C_BOUNDARY])
    i_eval = int(carry[C_TEVAL])
    t0 = carry[C_T0]
    n_steps = int(carry[C_STEPS])
    n_rejects = int(carry[C_REJECTS])
    use_t_eval = t_eval.shape[0] > 0
    exponent = CONTROLLER_EXPONENT[method]
    switches_in_step = 0
    status = DONE
    while t < t_end:
        if n_out >= cap - 1:
            status = OUTPUT_FULL
            break
        if method == RK4:
            target = t0 + k * dt
            if target >= t_end or t_end - target < 1e-9 * dt:
                target = t_end
            if target <= t:
                k += 1
                continue
            h = target - t
        else:
            h = min(h_ctrl, h_max)
            target = t + h
            if target >= t_end:
                h = t_end - t
                target = t_end
        s1, err = advance(method, s, t, h, direction, c, rtol, atol)
        if method != RK4 and not err <= 1.0:
            n_rejects += 1
            factor = 0.2 if err != err else max(0.2, 0.9 * err**exponent)
            h_ctrl = h * factor
            if h_ctrl <= 1e-14 * (abs(t) + abs(h)):
                status = STEP_UNDERFLOW
                break
            continue
        theta, which = first_switch(method, s, s1, t, h, direction, c, rtol, atol)
        if which >= 0 and theta < 1.0:
            t_piece = t + theta * h
            s_piece, _err = advance(method, s, t, theta * h, direction, c, rtol, atol)
        else:
            t_piece = target
            s_piece = s1
        if use_t_eval:
            # A time equal to the piece end is written by the next piece (or the final
            # flush), from the state after any switch there.
            while i_eval < t_eval.shape[0] and t_eval[i_eval] < t_piece:
                if n_out >= cap - 1:
                    status = OUTPUT_FULL
                    break
                te = t_eval[i_eval]
                if te <= t:
                    se = s
                else:
                    se, _err = advance(method, s, t, te - t, direction, c, rtol, atol)
                n_out = _write(out_t, out_s, out_dir, n_out, te, se, direction)
                i_eval += 1
            if status == OUTPUT_FULL:
                break
        if which >= 0:
            if n_ev >= ev_cap:
                status = EVENTS_FULL
                break
            switches_in_step += 1
            if switches_in_step > _MAX_SWITCHES_PER_STEP:
                status = STALLED
                break
            s_piece, direction, kind = apply_switch(which, s_piece, t_piece, direction, c)
            ev_t[n_ev] = t_piece
            ev_kind[n_ev] = kind
            for j in range(4):
                ev_s[n_ev, j] = s_piece[j]
            n_ev += 1
        if which < 0 or theta >= 1.0:
            switches_in_step = 0
            n_steps += 1
            if method == RK4:
                k += 1
            elif err > 0.0:
                h_ctrl = h * min(10.0, 0.9 * err**exponent)
            else:
                h_ctrl = h * 10.0
        t = t_piece
        s = s_piece
        boundary += 1
        if not use_t_eval and (boundary % save_every == 0 or t >= t_end):
            n_out = _write(out_t, out_s, out_dir, n_out, t, s, direction)
    if status == DONE and use_t_eval:
        while i_eval < t_eval.shape[0] and t_eval[i_eval] <= t:
            if n_out >= cap:
                status = OUTPUT_FULL
                break
            n_out = _write(out_t, out_s, out_dir, n_out, t_eval[i_eval], s, direction)
            i_eval += 1
    carry[C_T] = t
    carry[C_Y], carry[C_YD], carry[C_X], carry[C_XD] = s
    carry[C_DIR] = direction
    carry[C_H] = h_ctrl
    carry[C_K] = k
    carry[C_BOUNDARY] = boundary
    carry[C_TEVAL] = i_eval
    carry[C_STEPS] = n_steps
    carry[C_REJECTS] = n_rejects
    return n_out, n_ev, status
