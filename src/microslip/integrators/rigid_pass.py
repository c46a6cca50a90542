"""The rigid lanes' passes over rows of a normal tape (the shared-normal kernel,
:mod:`microslip.integrators.shared_lanes`; its GPU twin takes the same spans).

Every lane advances over a piece as if it held no switch, by the rigid law's closed form
(:func:`~microslip.integrators.rigid_lane_law.free_piece`) in a branch-free loop that
LLVM vectorises, and is flagged where a switch may lie inside; a flagged lane is redone
alone (:func:`~microslip.integrators.rigid_lane_law.lane_piece`). That closed form and
its flags need of a piece only its length, the integrals ∫ N dt and ∫ (t1 - t) N dt and
the extremes of N, so the vector pass takes SPAN_ROWS rows of the tape at once
(:func:`~microslip.integrators.normal_tape.span`): a lane that does not switch there
is advanced once instead of once a row, and the flagged ones go through the span's rows
one by one (:func:`rows_one_by_one`). The vector loop is compiled without fastmath (no
FMA contraction), and the spans start at every SPAN_ROWS rows of a tape, whatever the
lanes: a lane's result is bit-identical whatever the other lanes, their number, their
order or the threads.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import normal_tape as nt
from microslip.integrators.rigid_lane_law import free_piece, lane_piece

# Status of a pass.
OK = 0
LANE_STALLED = 5  # a lane switched more than MAX_SWITCHES_PER_STEP times in one piece

# Rows of the lane array of a group (one array: a compiled call counts each array
# argument once, so the per-piece pass takes one).
FM, KM, N_RELEASE, N_BALANCE, DIRECTION, X, V, MODE, FLAG = range(9)  # FLAG last
LANE_ROWS = 9
# Rows the vector pass takes as one piece (normal_tape.span): a lane that does not switch
# in them is advanced once instead of once a row; 1: row by row. A divisor of
# normal_tape.TAPE_ROWS: a span never straddles two fills of a tape. 8 and 16 ran the
# bench's forced map alike, 4 slower (2026-11-28).
SPAN_ROWS = 8


@njit(cache=True, error_model="numpy")
def _vector_pass(lanes, n_range, h, h_int, h2_kint, p_min, p_max):
    """A piece, or a span of pieces (:func:`~microslip.integrators.normal_tape.span`),
    for lanes [0, n_range) as if it held no switch (:func:`free_piece`), vectorised: h
    its length [s], ``h_int`` = ∫ N dt [N s], ``h2_kint`` = ∫ (t1 - t) N dt [N s²],
    p_min, p_max the extremes of N [N]. A flagged lane keeps its state. Returns the
    number of flagged lanes and the last of them (-1 if none): the lanes a piece switches
    are few and close together in the sorted order, and the search for them starts
    there."""
    n_flagged = 0
    last = -1
    for i in range(n_range):
        vi = lanes[V, i]
        xi = lanes[X, i]
        f, x1, v1 = free_piece(
            lanes[MODE, i], vi, xi, lanes[FM, i], lanes[KM, i], lanes[N_RELEASE, i],
            lanes[N_BALANCE, i], h, h_int, h2_kint, p_min, p_max,
        )  # fmt: skip
        lanes[FLAG, i] = 1.0 if f else 0.0
        lanes[X, i] = xi if f else x1
        lanes[V, i] = vi if f else v1
        n_flagged += 1 if f else 0
        last = max(last, i if f else -1)
    return n_flagged, last


@njit(cache=True)
def active_end(lanes, n):
    """One past the last of lanes [0, n) that is not stuck (0 if none)."""
    while n > 0 and lanes[MODE, n - 1] == 0.0:
        n -= 1
    return n


@njit(cache=True)
def _releasable(lanes, n, p_min):
    """The lanes that a piece whose minimum of P is ``p_min`` [N] can release:
    |F|/μ_s > p_min, a prefix [0, lo) of lanes [0, n) (sorted by decreasing |F|/μ_s);
    returns lo (bisection)."""
    lo, hi = 0, n
    while lo < hi:
        mid = (lo + hi) // 2
        if lanes[N_RELEASE, mid] > p_min:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(cache=True)
def gather_flagged(lanes, last, sub, columns):
    """Copy the flagged lanes among lanes [0, last] (a lane array whose last
    row is its flag: the rigid, spring and Mindlin lanes' FLAG), in their order, to the
    first columns of ``sub``, and their indices to ``columns``; returns their number (an
    int64, never a literal: the row passes it goes to would compile for one). The
    indices are found without a branch (a flag is as likely as not: a branch on it
    mispredicts), then each row gathered."""
    flag = lanes.shape[0] - 1
    m = np.int64(0)
    for i in range(last + 1):
        columns[m] = i  # m <= i <= last: within columns; kept where lane i is flagged
        m += 1 if lanes[flag, i] != 0.0 else 0
    for row in range(lanes.shape[0]):
        for j in range(m):
            sub[row, j] = lanes[row, columns[j]]
    return m


@njit(cache=True)
def lanes_over_rows(tape, r0, r1, lanes, n, n_active, switches, flagged):
    """Lanes [0, n) (sorted by decreasing |F|/μ_s) through rows [r0, r1) of ``tape``,
    in place: only lanes [0, n_active) can be moving (past it every lane sticks; see
    :func:`~microslip.integrators.shared_lanes._run_group`). Returns (status, n_active).

    The rows go SPAN_ROWS at a time from r0 (module doc): the vector pass takes a span
    as one piece, and the lanes it flags go through the span's rows one by one
    (:func:`rows_one_by_one`) on a compact copy, in their order."""
    sub = np.empty((LANE_ROWS, n))
    columns = np.empty(n, dtype=np.int64)
    sub_switches = np.empty(n, dtype=np.int64)
    sub_flagged = np.empty(n, dtype=np.int64)
    for b0 in range(r0, r1, SPAN_ROWS):
        b1 = min(b0 + SPAN_ROWS, r1)
        length, h_int, h2_kint, p_min, p_max = nt.span(tape, b0, b1)
        n_range = max(n_active, _releasable(lanes, n, p_min))
        _, last = _vector_pass(lanes, n_range, length, h_int, h2_kint, p_min, p_max)
        m = gather_flagged(lanes, last, sub, columns)
        for j in range(m):
            sub_switches[j] = 0
            sub_flagged[j] = 0
        if m > 0:
            status, _ = rows_one_by_one(tape, b0, b1, sub, m, m, sub_switches, sub_flagged)
            if status != OK:
                return status, n_active
            for j in range(m):
                i = columns[j]
                lanes[X, i], lanes[V, i], lanes[MODE, i] = sub[X, j], sub[V, j], sub[MODE, j]
                switches[i] += sub_switches[j]
                flagged[i] += sub_flagged[j]
        n_active = active_end(lanes, n_range)
    return OK, n_active


@njit(cache=True)
def rows_one_by_one(tape, r0, r1, lanes, n, n_active, switches, flagged):
    """Lanes [0, n) (sorted by decreasing |F|/μ_s) through rows [r0, r1) of ``tape``,
    one row at a time, in place; ``n_active`` as in :func:`lanes_over_rows`. Returns
    (status, n_active)."""
    for r in range(r0, r1):
        h = tape[r, nt.H]
        p_min = tape[r, nt.PMIN]
        n_range = max(n_active, _releasable(lanes, n, p_min))
        n_flagged, last = _vector_pass(
            lanes, n_range, h, h * tape[r, nt.INT1], h * h * tape[r, nt.KINT1], p_min,
            tape[r, nt.PMAX],
        )  # fmt: skip
        a = nt.coefficients(tape, r)
        crit = nt.critical_points(tape, r)
        for i in range(last, -1, -1):  # lanes are independent: any order
            if n_flagged == 0:  # the rest of the lanes went through the vector pass
                break
            if lanes[FLAG, i] != 0.0:
                n_flagged -= 1
                flagged[i] += 1
                xi, vi, mi, k = lane_piece(
                    a, crit, h, lanes[FM, i], lanes[KM, i], lanes[N_RELEASE, i],
                    lanes[N_BALANCE, i], lanes[DIRECTION, i], lanes[X, i], lanes[V, i],
                    lanes[MODE, i],
                )  # fmt: skip
                if k < 0:
                    return LANE_STALLED, n_active
                switches[i] += k
                lanes[X, i], lanes[V, i], lanes[MODE, i] = xi, vi, mi
        n_active = active_end(lanes, n_range)
    return OK, n_active
