"""Many compliant tangential lanes of Mindlin stiffness on one shared normal motion: the
time-domain map kernel of a contact point on a spring k_t = λ dN_el/dδ
(``MindlinSpring``).

The structure of :mod:`microslip.integrators.spring_lanes`: the normal motion once per
set-up (the tape of :mod:`microslip.integrators.normal_tape`), then per contact piece a
branch-free pass over the lanes that advances each as if the piece held no switch and
bounds its switching function (:mod:`~microslip.integrators.mindlin_pass`), and the law of
:mod:`microslip.integrators.mindlin_lane_law` for the lanes it flags. What a piece's
lanes share (the quartics k_t(τ), R(τ) = Ṅ/k_t and the stick's fundamental matrix Φ)
is computed once per piece (:func:`~microslip.integrators.mindlin_lane_law.set_piece`;
on a repeated tape once per row of the cycle, for every period), so a stuck lane costs
a 2x2 matrix product and a sliding one the rigid law. At the exponents below whose
flights the closed form crosses, the rows go by spans
(:mod:`~microslip.integrators.mindlin_spans`): a lane stuck throughout a span takes the
product of its rows' Φ at once; the rows themselves go by
:func:`~microslip.integrators.mindlin_rows.run_rows`.

A lane's arithmetic depends only on its own parameters and its set-up's tape (no
fastmath): the same bits whatever the other lanes, their order or the threads.

Contact exponents: any m2. For m2 = 1, 2 and >= 3 (:func:`supports_exponent`) the
closed form runs every set-up through its flights. Otherwise k_t ∝ δ^(m2-1) is not
smooth where δ = 0 (a Hertz contact, m2 = 1.5): on the piece after a touchdown (and
before a lift-off) its quartic misses the infinite slope (1 < m2 < 2) or curvature
(2 < m2 < 3) there, the stick's loading and the slip's stop function disagree at a
grazing touchdown, and a lane that lands chatters between them until it stalls
(measured: every lane with a flight at m2 = 1.2, 1.5, 1.9, 1.99, 2.2, 2.5). So the
lanes of such a set-up cross each lift-off and touchdown on the scalar RK4 step, by
windows of the tape (:mod:`~microslip.integrators.mindlin_windows`); in contact k_t is
smooth (within 2e-7 of the event method's largest velocity at m2 = 1.5 up to
A = 0.999 y0). A set-up whose window does not fit the rows in sight, and with
``windowed=False`` (the GPU lanes' way) every such set-up at its first row in flight,
is handed back (``LEFT_ROUGH_CONTACT``,
:class:`~microslip.integrators.shared_lanes.LaneStalledError`): the time sweep runs it on
the batched RK4 kernel (:mod:`microslip.sweeps.compute`). A lane whose closed form
stalls on a piece (an exact tie of stick and slip) takes that piece on the scalar step
too (:func:`~microslip.integrators.mindlin_windows.step_lane`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import mindlin_lane_law as law
from microslip.integrators import mindlin_windows as windows
from microslip.integrators import normal_tape as nt
from microslip.integrators import periodic_tape, threads
from microslip.integrators.kernel import as_tuple
from microslip.integrators.mindlin_piece import piece_table
from microslip.integrators.mindlin_rows import (
    FINAL,
    LEFT_ROUGH_CONTACT,
    NO_COARSE_ROW,
    NOT_CACHED,
    NOT_FINAL,
    STEP_TOO_COARSE,
    TABLE,
    run_rows,
    supports_exponent,
)
from microslip.integrators.mindlin_spans import run_spans
from microslip.integrators.rigid_pass import SPAN_ROWS
from microslip.integrators.shared_lanes import (
    FIRST_ROW,
    OK,
    STOPPED,
    put_group,
    raise_on_failure,
    take_group,
)
from microslip.integrators.spring_lanes import (
    FS,
    LANE_ROWS,
    MODE,
    V,
    X,
    copied_setups,
    pack_lanes,
    start_lanes,
)
from microslip.integrators.tape_row import has_flight
from microslip.model.coefficients import EXPONENT, GRAVITY, MASS

# The set-ups the Mindlin lanes hand back whole; a lane that stalls goes back alone, with
# ``LaneStalledError.lanes`` (CPU and GPU lanes).
HANDED_BACK = {
    LEFT_ROUGH_CONTACT: "the normal motion left contact on a law whose Mindlin stiffness is "
    "rough at touchdown",
}


@njit(cache=True)
def _run_group(c, y0, ydot0, ratio, cycle, shape, t_end, dt, lanes, switches, flagged, stop,
               item, windowed):  # fmt: skip
    """One normal set-up and its lanes, in place; returns the status. On a repeated tape
    (``shape``: period rows, tail rows, repeats, T) each row's piece is written once
    (:func:`~microslip.integrators.mindlin_piece.piece_table`) and read every period: a
    free vibration's pieces are the same every period, and set_piece is most of a
    set-up's own cost. At an m2 that :func:`supports_exponent` the rows go by spans
    (:mod:`~microslip.integrators.mindlin_spans`), else one by one
    (:func:`~microslip.integrators.mindlin_rows.run_rows`), and where ``windowed`` the
    set-up crosses its flights by windows (:mod:`~microslip.integrators.mindlin_windows`;
    a stepped tape is then filled PEEK_ROWS rows ahead of each block, where a window may
    end). Returns STOPPED after a period, a span or a block of tape once ``stop[0]`` is
    set (:func:`threads.stop_flag`), and reports its progress there as ``item``
    (:func:`threads.report`)."""
    n = lanes.shape[1]
    flying = start_lanes(c, y0, ydot0, lanes, n)
    laws = as_tuple(c)  # the coefficients as the pieces' laws take them, once per set-up
    window = windows.window_buffers(c, ratio)
    rough = not supports_exponent(laws[EXPONENT])
    # A compact copy of the lanes a span flags, their indices, switches and flagged.
    scratch = (np.empty((LANE_ROWS, n)), np.empty(n, np.int64), np.empty((2, n), np.int64))
    if shape[0] > 0:
        period_rows, tail_rows, repeats, period = shape
        total = period_rows + tail_rows
        step = period / math.ceil(period / dt)  # the cycle's grid (periodic_tape.cycle_rows)
        table = np.zeros((total, law.PIECE))
        coarse = piece_table(table, cycle, total, laws, ratio)
        # A period in contact throughout needs no window (nor a look-ahead past its end).
        windowed = windowed and has_flight(cycle, total)
        if not rough:
            return run_spans(
                lanes, cycle, total, shape, table, coarse, laws, flying, switches, flagged,
                window, step, windowed, scratch, stop, item,
            )[0]  # fmt: skip
        for k in range(repeats):
            if stop[0] != 0:
                return STOPPED
            windows.reset_windows(window)  # each period's times are the first one's
            status, flying = run_rows(
                lanes, n, cycle, FIRST_ROW, period_rows, table, TABLE, coarse, laws, flying,
                switches, flagged, window, period_rows, NOT_FINAL, step, windowed,
            )  # fmt: skip
            if status != OK:
                return status
            threads.report(stop, item, (k + 1) / (repeats + 1))
        windows.reset_windows(window)  # the tail's times start at 0 too
        return run_rows(
            lanes, n, cycle, period_rows, total, table, TABLE, coarse, laws, flying, switches,
            flagged, window, total, FINAL, step, windowed,
        )[0]  # fmt: skip
    # Rough: each row's piece written into pieces[0] as it comes; else a span's pieces.
    pieces = np.zeros((SPAN_ROWS, law.PIECE))
    for j in range(SPAN_ROWS):
        law.set_setup(pieces[j], c[MASS], c[GRAVITY], ratio)
    carry, _, work = nt.tape_buffers(y0, ydot0)
    # The rows of a block and up to PEEK_ROWS after it, where a window may end.
    sight = np.empty((nt.TAPE_ROWS + windows.PEEK_ROWS, nt.ROW))
    tape = sight[: nt.TAPE_ROWS]
    while True:
        if stop[0] != 0:
            return STOPPED
        rows, tape_status = nt.fill_tape(carry, c, t_end, dt, tape, work)
        if tape_status > 1:
            return tape_status
        in_sight, final = rows, tape_status == 0
        if windowed and not final and rough:
            ahead = carry.copy()
            peeked, peek_status = nt.fill_tape(
                ahead, c, t_end, dt, sight[rows : rows + windows.PEEK_ROWS], work
            )
            in_sight, final = rows + peeked, peek_status == 0
        if rough:
            status, flying = run_rows(
                lanes, n, sight, FIRST_ROW, rows, pieces, NOT_CACHED, NO_COARSE_ROW, laws,
                flying, switches, flagged, window, in_sight, final, dt, windowed,
            )  # fmt: skip
        else:
            status, flying = run_spans(
                lanes, tape, rows, shape, pieces, NO_COARSE_ROW, laws, flying, switches,
                flagged, window, dt, windowed, scratch, stop, item,
            )  # fmt: skip
        if status != OK:
            return status
        threads.report(stop, item, carry[nt.C_T] / t_end)
        if tape_status == 0:
            return OK


@njit(cache=True, nogil=True)
def _run_groups(g_lo, g_hi, normal_c, y0, ydot0, ratio, cycles, offsets, shapes, starts, lanes,
                switches, flagged, status, t_end, dt, windowed, stop):  # fmt: skip
    """Set-ups [g_lo, g_hi) and their lanes, in place (a range of :func:`threads.run_ranges`,
    ``stop`` its flag, where a set-up handed back is marked: :func:`threads.hand_back`)."""
    for g in range(g_lo, g_hi):
        lo, hi = starts[g], starts[g + 1]
        group_lanes, group_switches, group_flagged = take_group(lanes, lo, hi)
        cycle, shape = periodic_tape.group_cycle(cycles, offsets, shapes, g)
        status[g] = _run_group(
            normal_c[g].copy(), y0[g], ydot0[g], ratio[g], cycle, shape, t_end, dt,
            group_lanes, group_switches, group_flagged, stop, g, windowed,
        )  # fmt: skip
        if status[g] == LEFT_ROUGH_CONTACT:  # handed back whole (a stalled lane goes alone)
            threads.hand_back(stop, g)  # its progress is the batched run's (caller)
        put_group(lanes, switches, flagged, lo, group_lanes, group_switches, group_flagged)


def run_mindlin_lanes(normal_coeffs, normal_states0, ratio, group_of_lane, forces, mu_static,
                      mu_kinetic, t_end, dt, periods=None, on_done=None,
                      windowed=True):  # fmt: skip
    """Final states of many compliant lanes of Mindlin stiffness on shared normal
    motions, each from rest with a relaxed spring (SI).

    Parameters
    ----------
    normal_coeffs : (G, SIZE) coefficient vectors of the G normal set-ups
        (:func:`normal_tape.normal_coefficients`).
    normal_states0 : (G, 2) initial (y [m], ẏ [m/s]) of each set-up at t = 0.
    ratio : (G,) Mindlin ratio λ [-] of k_t = λ dN_el/dδ of each set-up (> 0).
    group_of_lane : (L,) int, the set-up of each lane, non-decreasing.
    forces : (L,) constant tangential force F [N]; mu_static, mu_kinetic : (L,) [-].
    t_end : end time [s]; dt : RK4 step of the normal motion [s] (grid k·dt).
    periods : (G,) period [s] of each set-up's periodic normal motion, else 0 (default:
        all 0): :func:`~microslip.integrators.shared_lanes.run_shared`.
    on_done : as for :func:`~microslip.integrators.shared_lanes.run_shared`.

    Returns (x [m], ẋ [m/s], f [N], mode, switches, flagged) per lane at ``t_end``
    (mode 0 stick, ±1 slip, 2 flight). ValueError when dt is too coarse for the
    tangential oscillation (h sqrt(k_t/m) > 2 on a piece); RuntimeError if a normal
    integration fails; :class:`~microslip.integrators.shared_lanes.LaneStalledError`
    naming the set-ups it hands back (a set-up of a contact exponent outside
    :func:`supports_exponent` left contact: module doc) and the lanes it hands back
    alone (a lane stalled: more than MAX_SWITCHES_PER_STEP switches in a piece, at an
    exact stick/slip tie; its x, ẋ and f are NaN, the other lanes of its set-up run to
    the end), with these results, complete for the rest, as its ``partial``.
    ``windowed`` (default): a set-up of such an exponent crosses its flights, and a lane
    that stalls its piece, on the scalar RK4 step
    (:mod:`~microslip.integrators.mindlin_windows`); False hands them back as described
    (what the GPU lanes do).
    """
    copies, normal_coeffs, states0, ratio, periods, lane_args = copied_setups(
        normal_coeffs, normal_states0, ratio, periods, group_of_lane, forces, mu_static,
        mu_kinetic,
    )  # fmt: skip
    lanes, starts, ratio = pack_lanes(normal_coeffs, ratio, *lane_args, what="ratio")
    n_lanes = lanes.shape[1]
    switches = np.zeros(n_lanes, dtype=np.int64)
    flagged = np.zeros(n_lanes, dtype=np.int64)
    status = np.zeros(copies.n_copies, dtype=np.int64)
    cycles = periodic_tape.cycles(normal_coeffs, states0, periods, t_end, dt)
    stop = threads.stop_flag(copies.n_copies)
    threads.run_ranges(
        _run_groups, copies.n_copies, normal_coeffs, states0[:, 0].copy(), states0[:, 1].copy(),
        ratio, *cycles, starts, lanes, switches, flagged, status, float(t_end), float(dt),
        np.bool_(windowed), stop, per_task=1, stop=stop, on_done=copies.done(on_done),
    )  # fmt: skip
    status = copies.status(status)
    raise_if_too_coarse(status == STEP_TOO_COARSE, dt)
    results = tuple(
        copies.unorder(r) for r in (lanes[X], lanes[V], lanes[FS], lanes[MODE], switches, flagged)
    )
    # The lanes handed back alone are NaN; the rest ran to the end: no need to rerun it.
    stalled = np.flatnonzero(np.isnan(results[0]))
    raise_on_failure(status, "Mindlin-lane kernel", HANDED_BACK, stalled, results)
    return results


def raise_if_too_coarse(coarse: np.ndarray, dt: float) -> None:
    """ValueError in one line naming the first set-up marked in ``coarse`` (G,), where a
    piece's θ = h sqrt(k_t/m) exceeded MAX_THETA."""
    marked = np.flatnonzero(coarse)
    if marked.size:
        raise ValueError(
            f"dt = {dt!r} s is too coarse for the Mindlin tangential oscillation of set-up "
            f"{int(marked[0])} (h sqrt(k_t/m) > {law.MAX_THETA} on a piece): use a smaller dt"
        )
