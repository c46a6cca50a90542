"""A periodic normal motion's tape: one period integrated, then repeated.

A conservative free vibration (no damping, no excitation) is periodic: started at rest
at its top it returns there after its period T(A) (docs/theory/free_vibration.md). Its
tape (:mod:`microslip.integrators.normal_tape`) is then one period's pieces, repeated:
:func:`cycle_rows` (:func:`cycles` for many set-ups) integrates one period by the
tape's RK4 on the grid k T/n, n the whole number of steps of at most ``dt`` in T (so
that a step ends at T), every contact switch located, and the last, partial period
once on its own from the same start; :func:`repeat_rows` serves them, the k-th repeat
shifted by k T, in place of :func:`~microslip.integrators.normal_tape.fill_tape`.

The normal motion is then the same 4th-order approximation over every period: the
phase error of a tape filled step by step, which grows by the RK4 error every period,
is gone, and a set-up's lanes cost the integration of one period, not of the whole run
(1/74 of it over the paper's 0.05 s). The caller gives T; a set-up without one (0) is
filled step by step as before. The rigid lanes go further: a lane that repeats a period
skips the rest (:func:`microslip.integrators.shared_lanes._run_cycle`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import normal_tape as nt
from microslip.integrators import threads


def cycle_periods(periods, n_setups: int) -> np.ndarray:
    """(G,) float array of the set-ups' periods [s] (0: not periodic), from ``periods``
    (None: none periodic)."""
    if periods is None:
        return np.zeros(n_setups)
    out = np.array(periods, dtype=np.float64).reshape(-1)
    if out.shape != (n_setups,) or not np.all(np.isfinite(out) & (out >= 0.0)):
        raise ValueError(f"periods must be {n_setups} finite values >= 0 s")
    return out


def cycle_rows(c, y0, ydot0, period, t_end, dt):
    """(rows, (period rows, tail rows, repeats, T [s])) of the normal motion from
    (y0 [m], ẏ0 [m/s]) at t = 0 in coefficients ``c``, periodic with period T:
    ``rows`` holds one period's pieces and then those of the last, partial one (up to
    ``t_end`` [s]), with steps of at most ``dt`` [s]. No cycle (period rows 0) where
    T <= 0, the run is shorter than two periods, or a period needs more than
    :data:`~microslip.integrators.normal_tape.TAPE_ROWS` pieces (one tape's worth).
    Python around the compiled fill_tape: a compiled function that calls fill_tape
    costs seconds of cold compile, and a period is ~200 pieces."""
    none = (np.empty((0, nt.ROW)), (0, 0, 0, 0.0))
    if not period > 0.0 or t_end < 2.0 * period:
        return none
    c = np.ascontiguousarray(c, dtype=np.float64)
    step = period / math.ceil(period / dt)
    carry, tape, work = nt.tape_buffers(y0, ydot0)
    period_rows, status = nt.fill_tape(carry, c, period, step, tape, work)
    if status != 0:
        return none
    period_rows = int(period_rows)
    repeats = math.floor(t_end / period)
    rest = t_end - repeats * period
    tail_rows = 0
    tail = np.empty((0, nt.ROW))
    if rest > 0.0:
        carry, tail, work = nt.tape_buffers(y0, ydot0)
        tail_rows, status = nt.fill_tape(carry, c, rest, step, tail, work)
        if status != 0:
            return none
        tail_rows = int(tail_rows)
    rows = np.empty((period_rows + tail_rows, nt.ROW))
    rows[:period_rows] = tape[:period_rows]
    rows[period_rows:] = tail[:tail_rows]
    return rows, (period_rows, tail_rows, repeats, period)


def cycles(normal_coeffs, normal_states0, periods, t_end, dt):
    """(cycles, offsets, shapes) of every set-up g: its :func:`cycle_rows` are
    cycles[offsets[g]:offsets[g + 1]], its shape the row shapes[g] (period rows, tail
    rows, repeats, T [s]); ``periods`` as for :func:`cycle_periods`, [s]."""
    n_groups = normal_coeffs.shape[0]
    periods = cycle_periods(periods, n_groups)
    blocks, shapes = [np.empty((0, nt.ROW))], np.zeros((n_groups, 4))
    for g in range(n_groups):
        rows, shape = cycle_rows(
            normal_coeffs[g], normal_states0[g, 0], normal_states0[g, 1], periods[g], t_end, dt
        )
        blocks.append(rows)
        shapes[g] = shape
    offsets = np.cumsum([0] + [len(b) for b in blocks[1:]]).astype(np.int64)
    return np.concatenate(blocks), offsets, shapes


@njit(cache=True)
def group_cycle(cycles, offsets, shapes, g):
    """(cycle, shape) of set-up g from :func:`cycles`, for :func:`repeat_rows`."""
    shape = (int(shapes[g, 0]), int(shapes[g, 1]), int(shapes[g, 2]), shapes[g, 3])
    return cycles[offsets[g] : offsets[g + 1]], shape


@njit(cache=True)
def repeat_rows(carry, tape, cycle, shape):
    """(rows written, status) as :func:`~microslip.integrators.normal_tape.fill_tape`:
    the next pieces of the repeated ``cycle`` (``shape`` from :func:`cycle_rows`, with
    period rows > 0) into ``tape``; ``carry`` from
    :func:`~microslip.integrators.normal_tape.tape_buffers`, its grid index counting the
    pieces served. (The kernels call fill_tape themselves where there is no cycle: one
    more compiled caller of fill_tape costs seconds of cold compile.)"""
    period_rows, tail_rows, repeats, period = shape
    repeated = repeats * period_rows
    total = repeated + tail_rows
    j = int(carry[nt.C_K])
    rows = 0
    while j < total and rows < tape.shape[0]:
        if j < repeated:
            source, shift = j % period_rows, (j // period_rows) * period
        else:
            source, shift = period_rows + j - repeated, repeats * period
        for col in range(nt.ROW):
            tape[rows, col] = cycle[source, col]
        tape[rows, nt.T0] += shift
        rows += 1
        j += 1
    carry[nt.C_K] = j
    return rows, (0 if j >= total else 1)


def fill_blocks(normal_c, carries, works, tapes, rows, status, t_end, dt, cycles, offsets,
                shapes):  # fmt: skip
    """The next block of every set-up's tape (``tapes[g]``, its row count in
    ``rows[g]``), in parallel over the set-ups: the GPU lanes' blocks. ``status`` 1 = more
    to come (fill), 0 = done (no rows), > 1 = failed (no rows). ``cycles``, ``offsets``,
    ``shapes``: the set-ups' periodic cycles (:func:`cycles`), whose rows
    :func:`repeat_rows` serves; without one (period rows 0) a tape is filled step by step
    (:func:`~microslip.integrators.normal_tape.fill_tape`)."""
    threads.run_ranges(
        _fill_block_range, normal_c.shape[0], normal_c, carries, works, tapes, rows, status, t_end,
        dt, cycles, offsets, shapes, per_task=1,
    )  # fmt: skip


@njit(cache=True, nogil=True)
def _fill_block_range(g_lo, g_hi, normal_c, carries, works, tapes, rows, status, t_end, dt, cycles,
                offsets, shapes):  # fmt: skip
    """Set-ups [g_lo, g_hi) of :func:`fill_blocks`."""
    for g in range(g_lo, g_hi):
        if status[g] != 1:
            rows[g] = 0
            continue
        cycle, shape = group_cycle(cycles, offsets, shapes, g)
        if shape[0] > 0:
            rows[g], status[g] = repeat_rows(carries[g], tapes[g], cycle, shape)
        else:
            rows[g], status[g] = nt.fill_tape(carries[g], normal_c[g], t_end, dt, tapes[g],
                                              works[g])  # fmt: skip
