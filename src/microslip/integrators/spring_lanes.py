"""Many compliant tangential lanes on one shared normal motion: the time-domain map
kernel of a contact point on a spring of constant stiffness (``TangentialSpring``).

The normal motion is the tape of :mod:`microslip.integrators.normal_tape` (one per
normal set-up: N as a quartic P(τ) per piece); each lane is a body on its spring under a
constant force F, advanced over each piece in closed form by the law of
:mod:`microslip.integrators.spring_lane_law`. A piece in flight (P = 0) moves every lane
ballistically, its spring relaxed (the lift-off is applied to all lanes at once).

A contact piece is a branch-free pass over the lanes that advances each as if the piece
held no switch and flags those whose bound does not prove it
(:func:`~microslip.integrators.spring_pass.vector_pass`); the flagged ones are redone
alone by :func:`~microslip.integrators.spring_lane_law.lane_piece`. The rows go
SPAN_ROWS at a time from the tape's start, whatever the lanes (:func:`_spans`): a lane
that provably sticks throughout a span turns its oscillator once over it
(:func:`~microslip.integrators.spring_pass.span_pass`), and the others go through the
span's rows one by one on a compact copy, as the rigid lanes do
(:mod:`~microslip.integrators.rigid_pass`).

A lane's arithmetic depends only on its own parameters and its group's tape (no
fastmath): its result is the same bits whatever the other lanes, their number, their
order or the threads. Groups (normal set-ups) run in parallel over the cores
(:mod:`~microslip.integrators.threads`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import normal_tape as nt
from microslip.integrators import periodic_tape, threads
from microslip.integrators.kernel import as_tuple
from microslip.integrators.rigid_pass import SPAN_ROWS, gather_flagged
from microslip.integrators.setup_copies import SetupCopies
from microslip.integrators.shared_lanes import (
    LANE_STALLED,
    OK,
    STOPPED,
    put_group,
    raise_on_failure,
    take_group,
)
from microslip.integrators.spring_lane_law import (
    FLIGHT,
    P_KT,
    P_MASS,
    P_OMEGA,
    PIECE,
    lane_piece,
    set_piece,
    set_spring,
)
from microslip.integrators.spring_pass import (
    FLAG,
    FM,
    FORCE,
    FS,
    KM,
    LANE_ROWS,
    MODE,
    MU_K,
    MU_S,
    V,
    X,
    put_flagged,
    span_constants,
    span_pass,
    vector_pass,
)
from microslip.integrators.tape_row import flight_piece
from microslip.model.coefficients import GRAVITY, MASS
from microslip.model.normal import normal_force


@njit(cache=True)
def starts_in_flight(c, y0, ydot0):
    """True when a set-up starts out of contact (N = 0 at t = 0): its lanes, at rest on a
    relaxed spring, start in flight; otherwise they stick."""
    return normal_force(0.0, y0, ydot0, as_tuple(c)) <= 0.0


@njit(cache=True)
def flight_step(x, v, fm, h):
    """(x, ẋ) after a piece of length h [s] in flight: f = 0, m ẍ = F."""
    return x + (h * v + 0.5 * h * h * fm), v + h * fm


@njit(cache=True, error_model="numpy")
def _flight_pass(lanes, n, h):
    """A piece in flight for every lane (:func:`flight_step`)."""
    for i in range(n):
        lanes[X, i], lanes[V, i] = flight_step(lanes[X, i], lanes[V, i], lanes[FM, i], h)


@njit(cache=True)
def start_lanes(c, y0, ydot0, lanes, n):
    """Put lanes [0, n) at rest on a relaxed spring in flight or stuck, as their set-up
    starts out of contact or in it; returns whether it starts in flight."""
    flying = starts_in_flight(c, y0, ydot0)
    for i in range(n):
        lanes[MODE, i] = FLIGHT if flying else 0.0
    return flying


@njit(cache=True)
def lift_off(lanes, n):
    """Lanes [0, n) leave contact: every spring relaxes (f = 0, u = x) and flies."""
    for i in range(n):
        lanes[MODE, i], lanes[FS, i] = FLIGHT, 0.0


@njit(cache=True)
def fly(lanes, n, h, flying):
    """A tape piece in flight for lanes [0, n): on lift-off (``flying`` False) every
    spring relaxes (:func:`lift_off`), then every lane flies (:func:`_flight_pass`)."""
    if not flying:
        lift_off(lanes, n)
    _flight_pass(lanes, n, h)


@njit(cache=True)
def _rows(tape, r0, r1, lanes, n, piece, flying, switches, flagged):
    """Lanes [0, n) through rows [r0, r1) of ``tape`` one row at a time, in place
    (``piece`` holds the set-up's spring; ``flying`` where the row before was in flight).
    Returns (status, flying)."""
    for r in range(r0, r1):
        h = tape[r, nt.H]
        a = nt.coefficients(tape, r)
        if flight_piece(a):
            fly(lanes, n, h, flying)
            flying = True
            continue
        flying = False  # a lane that lands is flagged: the piece applies the touchdown
        set_piece(piece, a, h)
        n_flagged, first = vector_pass(
            lanes, n, a, piece, h * tape[r, nt.INT1], h * h * tape[r, nt.KINT1]
        )
        for i in range(first, n):
            if n_flagged == 0:
                break
            if lanes[FLAG, i] != 0.0:
                n_flagged -= 1
                flagged[i] += 1
                xi, vi, fi, mi, k = lane_piece(
                    a, piece, lanes[FORCE, i], lanes[FM, i], lanes[KM, i], lanes[MU_S, i],
                    lanes[MU_K, i], lanes[X, i], lanes[V, i], lanes[FS, i], lanes[MODE, i],
                )  # fmt: skip
                if k < 0:
                    return LANE_STALLED, flying
                switches[i] += k
                lanes[X, i], lanes[V, i], lanes[FS, i], lanes[MODE, i] = xi, vi, fi, mi
    return OK, flying


@njit(cache=True)
def _spans(tape, n_rows, lanes, n, piece, flying, switches, flagged, sub, columns, counts):
    """Lanes [0, n) through rows [0, n_rows) of ``tape``, SPAN_ROWS rows at a time from
    its start (module doc), in place: a lane that sticks throughout a span takes it as
    one turn of its oscillator (:func:`~microslip.integrators.spring_pass.span_pass`),
    the others go through its rows one by one (:func:`_rows`) on a compact copy
    (``sub``, ``columns``, ``counts``: scratch for n lanes). Returns (status, flying)."""
    omega, k_t, mass = piece[P_OMEGA], piece[P_KT], piece[P_MASS]
    for b0 in range(0, n_rows, SPAN_ROWS):
        b1 = min(b0 + SPAN_ROWS, n_rows)
        length, _, _, p_min, _ = nt.span(tape, b0, b1)
        n_flagged, last = n, n - 1
        if p_min > 0.0:  # no flight in the span
            n_flagged, last = span_pass(lanes, n, span_constants(omega, k_t, mass, length), p_min)
        if n_flagged == n:  # no lane took the span: its rows for every lane, in place
            status, flying = _rows(tape, b0, b1, lanes, n, piece, flying, switches, flagged)
            if status != OK:
                return status, flying
            continue
        flying = False  # a lane stuck throughout the span: no row of it is in flight
        if n_flagged == 0:
            continue  # every lane took the span: its rows need not be read
        m = gather_flagged(lanes, last, sub, columns)
        for j in range(m):
            counts[0, j], counts[1, j] = 0, 0
        # Not in flight (a bool, not the literal False: _rows would compile for it too).
        status, _ = _rows(tape, b0, b1, sub, m, piece, np.bool_(False), counts[0], counts[1])
        if status != OK:
            return status, flying
        put_flagged(lanes, switches, flagged, sub, columns, counts, m)
    return OK, flying


@njit(cache=True)
def _run_group(c, y0, ydot0, k_t, cycle, shape, t_end, dt, lanes, switches, flagged, stop,
               item):  # fmt: skip
    """One normal set-up and its lanes, in place; returns the status (STOPPED after a
    block of tape once ``stop[0]`` is set: :func:`threads.stop_flag`; each block's
    progress reported there as ``item``, :func:`threads.report`)."""
    n = lanes.shape[1]
    mass = c[MASS]
    omega = math.sqrt(k_t / mass)
    piece = np.empty(PIECE)
    set_spring(piece, omega, k_t, mass, c[GRAVITY])
    flying = start_lanes(c, y0, ydot0, lanes, n)
    carry, tape, work = nt.tape_buffers(y0, ydot0)
    sub, columns = np.empty((LANE_ROWS, n)), np.empty(n, dtype=np.int64)
    counts = np.empty((2, n), dtype=np.int64)  # a compact copy's switches and flagged
    while True:
        if stop[0] != 0:
            return STOPPED
        if shape[0] > 0:
            rows, tape_status = periodic_tape.repeat_rows(carry, tape, cycle, shape)
        else:
            rows, tape_status = nt.fill_tape(carry, c, t_end, dt, tape, work)
        if tape_status > 1:
            return tape_status
        status, flying = _spans(
            tape, rows, lanes, n, piece, flying, switches, flagged, sub, columns, counts
        )
        if status != OK:
            return status
        if rows > 0:
            threads.report(stop, item, (tape[rows - 1, nt.T0] + tape[rows - 1, nt.H]) / t_end)
        if tape_status == 0:
            return OK


@njit(cache=True, nogil=True)
def _run_groups(g_lo, g_hi, normal_c, y0, ydot0, stiffness, cycles, offsets, shapes, starts, lanes,
                switches, flagged, status, t_end, dt, stop):  # fmt: skip
    """Set-ups [g_lo, g_hi) and their lanes, in place (a range of :func:`threads.run_ranges`,
    ``stop`` its flag)."""
    for g in range(g_lo, g_hi):
        lo, hi = starts[g], starts[g + 1]
        group_lanes, group_switches, group_flagged = take_group(lanes, lo, hi)
        cycle, shape = periodic_tape.group_cycle(cycles, offsets, shapes, g)
        status[g] = _run_group(
            normal_c[g].copy(), y0[g], ydot0[g], stiffness[g], cycle, shape, t_end, dt,
            group_lanes, group_switches, group_flagged, stop, g,
        )  # fmt: skip
        put_group(lanes, switches, flagged, lo, group_lanes, group_switches, group_flagged)


def run_spring_lanes(normal_coeffs, normal_states0, stiffness, group_of_lane, forces,
                     mu_static, mu_kinetic, t_end, dt, periods=None, on_done=None):  # fmt: skip
    """Final states of many compliant lanes (a contact point on a spring of constant
    stiffness) on shared normal motions, each from rest with a relaxed spring (SI).

    Parameters
    ----------
    normal_coeffs : (G, SIZE) coefficient vectors of the G normal set-ups (their
        tangential slots are ignored; see :func:`normal_tape.normal_coefficients`).
    normal_states0 : (G, 2) initial (y [m], ẏ [m/s]) of each set-up at t = 0.
    stiffness : (G,) tangential stiffness k_t [N/m] of each set-up (> 0).
    group_of_lane : (L,) int, the set-up of each lane, non-decreasing.
    forces : (L,) constant tangential force F [N]; mu_static, mu_kinetic : (L,) [-].
    t_end : end time [s]; dt : RK4 step of the normal motion [s] (grid k·dt).
    periods : (G,) period [s] of each set-up's periodic normal motion, else 0 (default:
        all 0): :func:`~microslip.integrators.shared_lanes.run_shared`.
    on_done : as for :func:`~microslip.integrators.shared_lanes.run_shared`.

    Returns (x [m], ẋ [m/s], f [N], mode, switches, flagged) per lane at ``t_end``
    (mode 0 stick, ±1 slip, 2 flight); raises RuntimeError if a normal integration or a
    lane fails.
    """
    copies, normal_coeffs, states0, stiffness, periods, lane_args = copied_setups(
        normal_coeffs, normal_states0, stiffness, periods, group_of_lane, forces, mu_static,
        mu_kinetic,
    )  # fmt: skip
    lanes, starts, stiffness = pack_lanes(normal_coeffs, stiffness, *lane_args)
    n_lanes = lanes.shape[1]
    switches = np.zeros(n_lanes, dtype=np.int64)
    flagged = np.zeros(n_lanes, dtype=np.int64)
    status = np.zeros(copies.n_copies, dtype=np.int64)
    cycles = periodic_tape.cycles(normal_coeffs, states0, periods, t_end, dt)
    stop = threads.stop_flag(copies.n_copies)
    threads.run_ranges(
        _run_groups, copies.n_copies, normal_coeffs, states0[:, 0].copy(), states0[:, 1].copy(),
        stiffness, *cycles, starts, lanes, switches, flagged, status, float(t_end), float(dt),
        stop, per_task=1, stop=stop, on_done=copies.done(on_done),
    )  # fmt: skip
    raise_on_failure(copies.status(status), "spring-lane kernel")
    results = lanes[X], lanes[V], lanes[FS], lanes[MODE], switches, flagged
    return tuple(copies.unorder(r) for r in results)


def copied_setups(normal_coeffs, normal_states0, parameter, periods, group_of_lane, forces,
                  mu_static, mu_kinetic):  # fmt: skip
    """(copies, coefficients, initial states, spring parameter, periods, lane arrays) of a
    spring or Mindlin lane run as :class:`~microslip.integrators.setup_copies.SetupCopies`:
    the per-set-up arrays one row per copy, the lane arrays (copy, F, μ_s, μ_k) in copy
    order (:func:`pack_lanes` takes them by set-up); ``copies.unorder`` puts the
    results back in the caller's lane order."""
    normal_coeffs = np.ascontiguousarray(normal_coeffs, dtype=np.float64)
    group_of_lane = np.asarray(group_of_lane, dtype=np.int64)
    if np.any(np.diff(group_of_lane) < 0):
        raise ValueError("group_of_lane must be non-decreasing (lanes by set-up)")
    copies = SetupCopies.plan(group_of_lane, normal_coeffs.shape[0])
    per_lane = [
        np.broadcast_to(np.asarray(a, dtype=np.float64), group_of_lane.shape)[copies.order]
        for a in (forces, mu_static, mu_kinetic)
    ]
    return (
        copies,
        copies.spread(normal_coeffs),
        copies.spread(np.asarray(normal_states0, dtype=np.float64)),
        copies.spread(np.asarray(parameter, dtype=np.float64)),
        copies.spread(periods),
        (copies.lane_copy[copies.order], *per_lane),
    )


def pack_lanes(normal_coeffs, stiffness, group_of_lane, forces, mu_static, mu_kinetic,
               what="stiffness"):  # fmt: skip
    """(lanes, starts, stiffness): the lane array (rows FORCE ... FLAG) of
    :func:`run_spring_lanes`'s lanes at rest, ``starts`` (G + 1,) the first lane of each
    set-up, and the set-ups' spring parameter (k_t [N/m], or the Mindlin ratio λ [-] with
    ``what="ratio"``) as an array; ValueError for lanes out of set-up order or a
    parameter <= 0."""
    stiffness = np.asarray(stiffness, dtype=np.float64)
    group_of_lane = np.asarray(group_of_lane, dtype=np.int64)
    if np.any(np.diff(group_of_lane) < 0):
        raise ValueError("group_of_lane must be non-decreasing (lanes by set-up)")
    if not np.all(stiffness > 0.0):
        unit = " N/m" if what == "stiffness" else ""
        raise ValueError(f"{what} must be > 0{unit}; got {float(stiffness.min())!r}")
    n_lanes = group_of_lane.size
    counts = np.bincount(group_of_lane, minlength=normal_coeffs.shape[0])
    starts = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    forces = np.asarray(forces, dtype=np.float64)
    mass = normal_coeffs[group_of_lane, MASS]
    mu_k = np.asarray(mu_kinetic, dtype=np.float64) * np.ones(n_lanes)
    lanes = np.zeros((LANE_ROWS, n_lanes))
    lanes[FORCE] = forces
    lanes[FM] = forces / mass
    lanes[KM] = mu_k / mass
    lanes[MU_S] = mu_static
    lanes[MU_K] = mu_k
    return lanes, starts, stiffness
