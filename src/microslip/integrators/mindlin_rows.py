"""The Mindlin lanes through tape rows one at a time (:func:`run_rows`): the row engine of
:mod:`microslip.integrators.mindlin_lanes`, under its spans
(:mod:`~microslip.integrators.mindlin_spans`) and, at a contact exponent outside
:func:`supports_exponent`, with the windows of
:mod:`~microslip.integrators.mindlin_windows` across each lift-off and touchdown.

A contact row takes the branch-free pass over the lanes
(:func:`~microslip.integrators.mindlin_pass.vector_pass`) and the law of
:mod:`microslip.integrators.mindlin_lane_law` for the lanes it flags; a row in flight
moves them all (:func:`~microslip.integrators.spring_lanes.fly`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import mindlin_lane_law as law
from microslip.integrators import mindlin_windows as windows
from microslip.integrators import normal_tape as nt
from microslip.integrators.mindlin_pass import vector_pass
from microslip.integrators.shared_lanes import OK
from microslip.integrators.spring_lanes import FLAG, FM, FORCE, FS, KM, MODE, MU_K, MU_S, V, X, fly
from microslip.integrators.tape_row import flight_piece
from microslip.model.coefficients import EXPONENT

STEP_TOO_COARSE = 7  # a set-up's status: θ = h sqrt(k_t/m) > MAX_THETA on a piece
LEFT_ROUGH_CONTACT = 8  # a set-up's status: a flight at an m2 outside supports_exponent


@njit(cache=True)
def supports_exponent(m2):
    """True for the contact exponents m2 [-] whose set-ups this kernel runs through a
    flight: 1, 2 and >= 3 (module doc)."""
    return m2 == 1.0 or m2 == 2.0 or m2 >= 3.0


# The flags and codes of run_rows as NumPy scalars, not literals, which would compile it
# once per value (docs/design.md).
TABLE = np.int64(0)  # base of run_rows: row r's piece is pieces[r]
NOT_CACHED = np.int64(-1)  # base of run_rows: each row's piece written into pieces[0]
FINAL = np.bool_(True)
NOT_FINAL = np.bool_(False)
NO_COARSE_ROW = np.int64(-1)


@njit(cache=True)
def run_rows(lanes, n, rows, lo, hi, pieces, base, coarse, laws, flying, switches, flagged,
             window, in_sight, final, dt, windowed):  # fmt: skip
    """Lanes [0, n) over tape rows [lo, hi) of ``rows``, in place: a row in flight moves
    them all (:func:`~microslip.integrators.spring_lanes.fly`), a contact row takes the
    vector pass and the law for the lanes it flags. A contact row's piece is
    pieces[r - ``base``] (``coarse``: the first row too coarse, NO_COARSE_ROW if none),
    or with ``base`` NOT_CACHED written into pieces[0] here from ``laws``, the
    coefficient tuple. At an m2 outside
    :func:`supports_exponent` the lanes cross each lift-off and touchdown by a window
    (:func:`~microslip.integrators.mindlin_windows.cross`: ``window`` its buffers, rows
    [0, ``in_sight``) in sight, ``final`` where they end the run, ``dt`` [s] the rows'
    grid step), where ``windowed``; at each grid point in contact it looks a few rows
    ahead for a lift-off to start one at (a window moves every lane of ``lanes``: such a
    set-up's rows take all of them, n = lanes.shape[1]; only the spans of the other
    set-ups pass a compact copy). Returns (status, whether the lanes are in flight);
    LEFT_ROUGH_CONTACT where a window does not fit the rows in sight."""
    rough = not supports_exponent(laws[EXPONENT])
    for r in range(lo, hi):
        h = rows[r, nt.H]
        a = nt.coefficients(rows, r)
        in_flight = flight_piece(a)
        if rough and not windowed:
            if in_flight:
                return LEFT_ROUGH_CONTACT, flying
        elif rough:
            t0 = rows[r, nt.T0]
            if windows.integrated_ahead(window, t0):
                continue
            r_switch = -1
            if in_flight != flying:
                if in_flight:  # a lift-off not seen coming (rows out of sight)
                    return LEFT_ROUGH_CONTACT, flying
                r_switch = r  # a touchdown
            elif not in_flight and windows.on_grid(t0, dt):
                r_switch = windows.lift_off_ahead(rows, r, in_sight, dt)
                if r_switch == -2 and not final:
                    return LEFT_ROUGH_CONTACT, flying
            if r_switch >= 0:
                done, flying = windows.cross(
                    window, lanes, switches, flagged, rows, r, r_switch, in_sight, final, dt
                )
                if not done:
                    return LEFT_ROUGH_CONTACT, flying
                continue
        if in_flight:
            fly(lanes, n, h, flying)
            flying = True
            continue
        flying = False
        if base >= 0:
            if r == coarse:
                return STEP_TOO_COARSE, flying
            piece = pieces[r - base]
        else:
            piece = pieces[0]
            if law.set_piece(piece, a, rows, r, laws) != 0:
                return STEP_TOO_COARSE, flying
        n_flagged, first = vector_pass(
            lanes, n, a, piece, h * rows[r, nt.INT1], h * h * rows[r, nt.KINT1]
        )
        for i in range(first, n):
            if n_flagged == 0:
                break
            if lanes[FLAG, i] != 0.0:
                n_flagged -= 1
                if lanes[X, i] != lanes[X, i]:
                    continue  # a lane that stalled (below): only flagged at a landing
                flagged[i] += 1
                xi, vi, fi, mi, k = law.lane_piece(
                    a, piece, lanes[FORCE, i], lanes[FM, i], lanes[KM, i],
                    lanes[MU_S, i], lanes[MU_K, i], lanes[X, i], lanes[V, i],
                    lanes[FS, i], lanes[MODE, i],
                )  # fmt: skip
                if k < 0:
                    if windowed and windows.step_lane(
                        window, lanes, switches, flagged, i, rows, r, dt
                    ):
                        continue  # the row on the scalar step instead
                    # Handed back alone (run_mindlin_lanes): NaN from here on, which the
                    # vector pass carries without a flag; the other lanes go on.
                    lanes[X, i], lanes[V, i], lanes[FS, i] = math.nan, math.nan, math.nan
                    continue
                switches[i] += k
                lanes[X, i], lanes[V, i], lanes[FS, i], lanes[MODE, i] = xi, vi, fi, mi
    return OK, flying
