"""The Mindlin lanes over spans of tape rows: SPAN_ROWS rows at a time from the tape's
first row (:func:`run_spans`), for the set-ups whose
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
    STEP_TOO_COARSE,
    TABLE,
    run_rows,
)
from microslip.integrators.rigid_pass import SPAN_ROWS, gather_flagged
from microslip.integrators.shared_lanes import OK, STOPPED
from microslip.integrators.spring_pass import put_flagged, span_pass
from microslip.integrators.tape_row import flight_piece


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
def run_spans(lanes, rows, n_rows, shape, pieces, coarse, laws, flying, switches, flagged,
              window, dt, windowed, scratch, stop, item):  # fmt: skip
    """The lanes over a tape span by span from its first row, in place (module doc): a
    lane stuck throughout a span takes it as one map, the others take its rows one by
    one (:func:`~microslip.integrators.mindlin_rows.run_rows`; ``laws``, ``window``,
    ``dt``, ``windowed`` as there), on a compact copy unless no lane took the span
    (``scratch`` = (sub, columns, counts) for it). Returns (status, flying).

    A stepped tape (``shape``'s period rows 0): rows [0, n_rows) of a block of ``rows``
    (a multiple of SPAN_ROWS from t = 0), each span's pieces written into ``pieces``
    (SPAN_ROWS rows, the set-up's slots written) first. A repeated tape (``rows`` its
    cycle, ``shape`` of :func:`~microslip.integrators.periodic_tape.cycle_rows`: the
    period's rows ``repeats`` times, then the tail): each row's piece is
    pieces[cycle row] (``coarse`` the first row too coarse), a span's rows one or two
    runs of the cycle; STOPPED once ``stop[0]`` is set, progress reported as ``item``.
    (One function for both, and the span inline: each compiled function costs seconds
    of cold compile.)"""
    n = lanes.shape[1]
    period_rows, tail_rows, repeats, _ = shape
    repeated = repeats * period_rows
    cached = period_rows > 0
    total = repeated + tail_rows if cached else n_rows
    runs = np.empty((SPAN_ROWS, 2), dtype=np.int64)
    for b0 in range(0, total, SPAN_ROWS):
        b1 = min(b0 + SPAN_ROWS, total)
        # The span's rows as runs of ``rows``, and where their pieces are.
        n_runs, base = 0, TABLE
        if cached:
            if stop[0] != 0:
                return STOPPED, flying
            j = b0
            while j < b1:
                if j < repeated:
                    source, left = j % period_rows, period_rows - j % period_rows
                else:
                    source, left = period_rows + j - repeated, total - j
                m = min(left, b1 - j)
                runs[n_runs, 0], runs[n_runs, 1] = source, source + m
                n_runs += 1
                j += m
        else:
            for r in range(b0, b1):
                a = nt.coefficients(rows, r)
                if not flight_piece(a) and law.set_piece(pieces[r - b0], a, rows, r, laws) != 0:
                    return STEP_TOO_COARSE, flying
            runs[0, 0], runs[0, 1] = b0, b1
            n_runs, base = 1, b0
        # The span's stick, and which lanes take it.
        span, stick = nt.EMPTY_SPAN, EMPTY_STICK
        takes = True  # no row too coarse (run_rows reports it)
        for k in range(n_runs):
            for r in range(runs[k, 0], runs[k, 1]):
                span, stick = extend_row(span, stick, rows, r, pieces, r - base)
                takes = takes and r != coarse
        p_min = span[3]
        n_flagged, last = n, n - 1
        if takes and p_min > 0.0:
            constants = stick_span_constants(stick, pieces[0, law.M_MASS])
            n_flagged, last = span_pass(lanes, n, constants, p_min)
        if n_flagged == n:  # no lane took the span: its rows for every lane, in place
            for k in range(n_runs):
                status, flying = run_rows(
                    lanes, n, rows, runs[k, 0], runs[k, 1], pieces, base, coarse, laws,
                    flying, switches, flagged, window, runs[k, 1], FINAL, dt, windowed,
                )  # fmt: skip
                if status != OK:
                    return status, flying
        elif n_flagged > 0:
            sub, columns, counts = scratch
            m = gather_flagged(lanes, last, sub, columns)
            for j in range(m):
                counts[0, j], counts[1, j] = 0, 0
            for k in range(n_runs):
                # Not in flight (a bool, not the literal False: run_rows would compile
                # for it too).
                status, _ = run_rows(
                    sub, m, rows, runs[k, 0], runs[k, 1], pieces, base, coarse, laws,
                    np.bool_(False), counts[0], counts[1], window, runs[k, 1], FINAL, dt,
                    windowed,
                )  # fmt: skip
                if status != OK:
                    return status, False
            put_flagged(lanes, switches, flagged, sub, columns, counts, m)
            flying = False  # a lane took the span: no row of it is in flight
        else:
            flying = False  # every lane took the span (stuck: not in flight)
        if cached:
            threads.report(stop, item, b1 / total)
    return OK, flying
