"""The Mindlin lanes over spans of tape rows: SPAN_ROWS rows at a time from the tape's
first row (:func:`stepped_spans`, :func:`periodic_spans`), for the set-ups whose
contact exponent :func:`~microslip.integrators.mindlin_rows.supports_exponent` (the
others take their rows one by one, with windows across their flights).

A stuck lane's stick is linear in (ẋ, e), e = f - F, with the fundamental matrix Φ of
each piece (:mod:`microslip.integrators.mindlin_piece`); over a span it is their
product, composed once for all the lanes of the set-up
(:func:`~microslip.integrators.mindlin_pass.extend_stick`). A lane that provably sticks
throughout the span (its force bounded through the energy of its stick against the
least N of the span: :func:`~microslip.integrators.mindlin_pass.stick_span_constants`)
takes it as that one map (:func:`~microslip.integrators.spring_pass.span_pass`); the
others go through the span's rows one by one
(:func:`~microslip.integrators.mindlin_rows.run_rows`) on a compact copy, as the spring
lanes do (:mod:`~microslip.integrators.spring_lanes`).

Spans start at fixed rows of the whole tape (every SPAN_ROWS from t = 0, whatever the
blocks, the periods or the other lanes), and each lane decides alone: its bits depend
only on its own parameters and its set-up's tape, and the GPU lanes
(:mod:`~microslip.integrators.mindlin_lanes_cuda`) take the same spans. On a repeated
tape a span may straddle two periods: its rows are then two runs of the cycle.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import mindlin_lane_law as law
from microslip.integrators import normal_tape as nt
from microslip.integrators import threads
from microslip.integrators.mindlin_pass import EMPTY_STICK, extend_stick, stick_span_constants
from microslip.integrators.mindlin_rows import (
    FINAL,
    NO_COARSE_ROW,
    STEP_TOO_COARSE,
    TABLE,
    run_rows,
)
from microslip.integrators.rigid_pass import SPAN_ROWS, gather_flagged
from microslip.integrators.shared_lanes import OK, STOPPED
from microslip.integrators.spring_pass import FS, MODE, V, X, span_pass
from microslip.integrators.tape_row import flight_piece

ONE_RUN = np.int64(1)  # a stepped span's rows: one run (not a literal: docs/design.md)


@njit(cache=True, inline="always")
def extend_row(span, stick, rows, r, pieces, q):
    """``span`` (:func:`~microslip.integrators.normal_tape.span`) and ``stick``
    (:func:`~microslip.integrators.mindlin_pass.extend_stick`) followed by row r of
    ``rows``, whose piece is pieces[q] (read only where the row is in contact; read in
    place: a view of each row would cost its reference counting)."""
    span = nt.extend_span(
        span, rows[r, nt.H], rows[r, nt.INT1], rows[r, nt.KINT1], rows[r, nt.PMIN],
        rows[r, nt.PMAX],
    )  # fmt: skip
    if span[3] > 0.0:  # a row in flight ends every lane's span (N = 0): no Φ to read
        k = law.M_K
        stick = extend_stick(
            stick, pieces[q, law.M_H], pieces[q, law.M_PHI11], pieces[q, law.M_PHI12],
            pieces[q, law.M_PHI21], pieces[q, law.M_PHI22], pieces[q, law.M_PSI1],
            pieces[q, law.M_PSI2], pieces[q, k], pieces[q, k + 1], pieces[q, k + 2],
            pieces[q, k + 3], pieces[q, k + 4],
        )  # fmt: skip
    return span, stick


@njit(cache=True)
def run_span(lanes, rows, runs, n_runs, pieces, base, coarse, laws, flying, switches, flagged,
             window, dt, windowed, scratch):  # fmt: skip
    """The lanes over one span, in place: rows [runs[k, 0], runs[k, 1]) of ``rows`` for
    k < ``n_runs``, in that order, their pieces pieces[r - ``base``] (``coarse`` a row
    too coarse, or NO_COARSE_ROW). A lane stuck throughout takes the span as one map
    (module doc); the others take its rows one by one
    (:func:`~microslip.integrators.mindlin_rows.run_rows`, ``window``, ``dt``,
    ``windowed`` as there), on a compact copy unless no lane took the span (``scratch``
    = (sub, columns, counts) for it). Returns (status, flying)."""
    n = lanes.shape[1]
    span, stick = nt.EMPTY_SPAN, EMPTY_STICK
    takes = True  # no row too coarse (run_rows reports it)
    for k in range(n_runs):
        for r in range(runs[k, 0], runs[k, 1]):
            span, stick = extend_row(span, stick, rows, r, pieces, r - base)
            takes = takes and r != coarse
    p_min = span[3]
    n_flagged, last = n, n - 1
    if takes and p_min > 0.0:
        k = stick_span_constants(stick, pieces[0, law.M_MASS])
        n_flagged, last = span_pass(lanes, n, k, p_min)
    if n_flagged == n:  # no lane took the span: its rows for every lane, in place
        for k in range(n_runs):
            status, flying = run_rows(
                lanes, n, rows, runs[k, 0], runs[k, 1], pieces, base, coarse, laws, flying,
                switches, flagged, window, runs[k, 1], FINAL, dt, windowed,
            )  # fmt: skip
            if status != OK:
                return status, flying
        return OK, flying
    if n_flagged == 0:
        return OK, False  # every lane took the span (stuck: not in flight)
    sub, columns, counts = scratch
    m = gather_flagged(lanes, last, sub, columns)
    for j in range(m):
        counts[0, j], counts[1, j] = 0, 0
    for k in range(n_runs):
        # Not in flight (a bool, not the literal False: run_rows would compile for it too).
        status, _ = run_rows(
            sub, m, rows, runs[k, 0], runs[k, 1], pieces, base, coarse, laws, np.bool_(False),
            counts[0], counts[1], window, runs[k, 1], FINAL, dt, windowed,
        )  # fmt: skip
        if status != OK:
            return status, False
    for j in range(m):
        i = columns[j]
        lanes[X, i], lanes[V, i], lanes[FS, i] = sub[X, j], sub[V, j], sub[FS, j]
        lanes[MODE, i] = sub[MODE, j]
        switches[i] += counts[0, j]
        flagged[i] += counts[1, j]
    return OK, False


@njit(cache=True)
def stepped_spans(lanes, tape, n_rows, pieces, laws, flying, switches, flagged, window, dt,
                  windowed, scratch):  # fmt: skip
    """The lanes over rows [0, n_rows) of a block of ``tape`` (a multiple of SPAN_ROWS
    from t = 0), span by span (:func:`run_span`), each span's pieces written into
    ``pieces`` (SPAN_ROWS rows, the set-up's slots written) first. Returns (status,
    flying)."""
    runs = np.empty((1, 2), dtype=np.int64)
    for b0 in range(0, n_rows, SPAN_ROWS):
        b1 = min(b0 + SPAN_ROWS, n_rows)
        for r in range(b0, b1):
            a = nt.coefficients(tape, r)
            if not flight_piece(a) and law.set_piece(pieces[r - b0], a, tape, r, laws) != 0:
                return STEP_TOO_COARSE, flying
        runs[0, 0], runs[0, 1] = b0, b1
        status, flying = run_span(
            lanes, tape, runs, ONE_RUN, pieces, b0, NO_COARSE_ROW, laws, flying, switches, flagged,
            window, dt, windowed, scratch,
        )  # fmt: skip
        if status != OK:
            return status, flying
    return OK, flying


@njit(cache=True)
def periodic_spans(lanes, cycle, shape, table, coarse, laws, flying, switches, flagged, window,
                   dt, windowed, scratch, stop, item):  # fmt: skip
    """The lanes over a repeated tape (``cycle``, ``shape`` of
    :func:`~microslip.integrators.periodic_tape.cycle_rows`: its period's rows ``repeats``
    times, then its tail), span by span (:func:`run_span`) from its first row, each row's
    piece table[cycle row] (``coarse`` the first row too coarse). Returns (status,
    flying); STOPPED once ``stop[0]`` is set, reporting progress there as ``item``."""
    period_rows, tail_rows, repeats, _ = shape
    repeated = repeats * period_rows
    total = repeated + tail_rows
    runs = np.empty((SPAN_ROWS, 2), dtype=np.int64)
    for b0 in range(0, total, SPAN_ROWS):
        if stop[0] != 0:
            return STOPPED, flying
        b1 = min(b0 + SPAN_ROWS, total)
        n_runs = 0
        j = b0
        while j < b1:  # the span's rows as runs of the cycle's rows
            if j < repeated:
                source, left = j % period_rows, period_rows - j % period_rows
            else:
                source, left = period_rows + j - repeated, total - j
            m = min(left, b1 - j)
            runs[n_runs, 0], runs[n_runs, 1] = source, source + m
            n_runs += 1
            j += m
        status, flying = run_span(
            lanes, cycle, runs, n_runs, table, TABLE, coarse, laws, flying, switches, flagged,
            window, dt, windowed, scratch,
        )  # fmt: skip
        if status != OK:
            return status, flying
        threads.report(stop, item, b1 / total)
    return OK, flying
