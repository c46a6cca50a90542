"""Lanes that repeat a period of a repeated normal tape: parked, then all their periods
at once (docs/theory/numerics.md, "Repeating lanes").

On a periodic normal motion's tape (:mod:`microslip.integrators.periodic_tape`) every
period is the same rows. A lane whose law reads its speed and mode but never its
position x (x only accumulates) and that starts a period in the state it started the
previous one with, bit for bit, repeats that period bit for bit, and every later one.
The kernel marks each live lane's state at every period start
(:func:`mark_period_start`); at the next one :func:`park` moves the lanes that repeat
past the live ones, which keep their order, with their increments per period; at the
tail :func:`unpark` gives them their remaining periods at once and puts every lane back
in its column.

The lane array is the kernel's: a column per lane, the rows named by the caller (x, ẋ,
mode); ``switches`` and ``flagged`` are its per-lane counts, taken along.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)

# Rows of the book, one column per lane: its column in the caller's order; x, ẋ, mode
# and the two counts at the last period start; once parked, the period it parked at
# and its increments of x and of the counts per period.
B_COLUMN, B_X, B_V, B_MODE, B_SWITCHES, B_FLAGGED, B_AT, B_DX, B_DSWITCHES, B_DFLAGGED = range(10)
BOOK_ROWS = 10


@njit(cache=True, inline="always")
def starts_as_before(v, mode, v_mark, mode_mark):
    """A lane in (ẋ [m/s], mode) starts this period as it started the last one, in
    (v_mark, mode_mark): the same bits (a zero speed with the same sign), so it repeats
    that period."""
    return mode == mode_mark and v == v_mark and math.copysign(1.0, v) == math.copysign(1.0, v_mark)


@njit(cache=True, inline="always")
def after_periods(left, x, switches, flagged, dx, dswitches, dflagged):
    """(x [m], switches, flagged) of a parked lane after ``left`` more periods of its
    increments (dx [m], dswitches, dflagged) per period. The CPU kernel and the GPU's
    threads both take their periods through it: the same bits."""
    return x + left * dx, switches + int(left * dswitches), flagged + int(left * dflagged)


@njit(cache=True)
def new_book(n):
    """The book of n lanes in their columns, none parked."""
    book = np.zeros((BOOK_ROWS, n))
    for i in range(n):
        book[B_COLUMN, i] = i
    return book


@njit(cache=True)
def mark_period_start(lanes, switches, flagged, book, n_live, x_row, v_row, mode_row):
    """Note the state and counts of the live lanes [0, n_live) at a period start."""
    for i in range(n_live):
        book[B_X, i], book[B_V, i] = lanes[x_row, i], lanes[v_row, i]
        book[B_MODE, i] = lanes[mode_row, i]
        book[B_SWITCHES, i], book[B_FLAGGED, i] = switches[i], flagged[i]


@njit(cache=True)
def _copy_lane(lanes, switches, flagged, book, i, to_lanes, to_switches, to_flagged, to_book, j):
    """Column i of (lanes, switches, flagged, book) into column j of the ``to_`` arrays."""
    for q in range(lanes.shape[0]):
        to_lanes[q, j] = lanes[q, i]
    for q in range(BOOK_ROWS):
        to_book[q, j] = book[q, i]
    to_switches[j], to_flagged[j] = switches[i], flagged[i]


@njit(cache=True)
def park(lanes, switches, flagged, book, n_live, period, x_row, v_row, mode_row):
    """Park the live lanes [0, n_live) that start ``period`` (counted from 0) as they
    started the last one: a stable partition, the live lanes first and in their order,
    the newly parked ones next, before those parked earlier. Returns the live count."""
    repeating = np.zeros(n_live, dtype=np.bool_)
    n_parked = 0
    for i in range(n_live):
        if starts_as_before(lanes[v_row, i], lanes[mode_row, i], book[B_V, i], book[B_MODE, i]):
            repeating[i] = True
            n_parked += 1
            book[B_AT, i] = period
            book[B_DX, i] = lanes[x_row, i] - book[B_X, i]
            book[B_DSWITCHES, i] = switches[i] - book[B_SWITCHES, i]
            book[B_DFLAGGED, i] = flagged[i] - book[B_FLAGGED, i]
    if n_parked == 0:
        return n_live
    held = (
        np.empty((lanes.shape[0], n_parked)), np.empty(n_parked, dtype=np.int64),
        np.empty(n_parked, dtype=np.int64), np.empty((BOOK_ROWS, n_parked)),
    )  # fmt: skip
    live = parked = np.int64(0)  # not a literal 0: one compile of _copy_lane (docs/design.md)
    for i in range(n_live):
        if repeating[i]:
            _copy_lane(lanes, switches, flagged, book, i, *held, parked)
            parked += 1
        else:  # live <= i: a move towards the front never overwrites a lane not yet read
            _copy_lane(lanes, switches, flagged, book, i, lanes, switches, flagged, book, live)
            live += 1
    for k in range(n_parked):
        _copy_lane(*held, k, lanes, switches, flagged, book, live + k)
    return live


@njit(cache=True)
def unpark(lanes, switches, flagged, book, n_live, repeats, x_row):
    """The parked lanes [n_live, n) take their periods left up to ``repeats``:
    x += (periods left) Δx [m], the counts likewise; then every lane goes back to its
    column."""
    n = lanes.shape[1]
    for i in range(n_live, n):
        lanes[x_row, i], switches[i], flagged[i] = after_periods(
            repeats - book[B_AT, i], lanes[x_row, i], switches[i], flagged[i], book[B_DX, i],
            book[B_DSWITCHES, i], book[B_DFLAGGED, i],
        )  # fmt: skip
    held = (lanes.copy(), switches.copy(), flagged.copy(), book.copy())
    for i in range(n):
        _copy_lane(*held, i, lanes, switches, flagged, book, int(held[3][B_COLUMN, i]))
