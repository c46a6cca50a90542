"""Many tangential lanes on one shared normal motion: the time-domain map kernel.

The normal motion does not depend on the tangential one (docs/design.md), so a map over
forces and friction coefficients at a given normal set-up needs it once: it is
integrated by the core RK4 kernel into a tape of pieces, each carrying the normal force
as a quartic P(τ) in τ = (t - t0)/h (:mod:`microslip.integrators.normal_tape`). Each
lane then is a body on a rigid contact under a constant force, advanced over each piece
by the law of :mod:`microslip.integrators.rigid_lane_law`: a common piece (or a span
of SPAN_ROWS pieces at once) is a few multiply-adds per lane
(:func:`~microslip.integrators.rigid_lane_law.free_piece`), in a branch-free loop over
the lanes that LLVM vectorises and that flags the lanes where a switch may lie inside;
a flagged lane is redone alone, piece by piece
(:func:`~microslip.integrators.rigid_lane_law.lane_piece`): the passes are
:mod:`microslip.integrators.rigid_pass`'s.

Every lane's arithmetic depends only on its own parameters and its group's tape, and the
vector loop is compiled without fastmath (no FMA contraction): a lane's result is
bit-identical whatever the other lanes, their number, their order or the threads.
Groups (normal set-ups) run in parallel over the cores
(:mod:`~microslip.integrators.threads`). On a periodic normal motion's repeated tape a
lane that starts a period as it started the last one takes its remaining periods at
once (:func:`_run_cycle`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import lane_parking as parking
from microslip.integrators import normal_tape as nt
from microslip.integrators import periodic_tape, threads
from microslip.integrators.kernel import as_tuple
from microslip.integrators.rigid_pass import (
    DIRECTION,
    FM,
    KM,
    LANE_ROWS,
    LANE_STALLED,
    MODE,
    N_BALANCE,
    N_RELEASE,
    OK,
    V,
    X,
    active_end,
    lanes_over_rows,
)
from microslip.integrators.setup_copies import SetupCopies
from microslip.model.coefficients import MASS
from microslip.model.normal import normal_force

# Status per group: rigid_pass.OK, rigid_pass.LANE_STALLED, or
STOPPED = 9  # an interrupt raised the run's stop flag (threads.stop_flag): results unread


class LaneStalledError(RuntimeError):
    """Set-ups the lanes hand back, to be run on the batched RK4 kernel: a lane stalled
    (more than MAX_SWITCHES_PER_STEP switches in one piece) or, on the Mindlin lanes, a
    set-up left contact on a rough law (``mindlin_lanes.LEFT_ROUGH_CONTACT``);
    ``setups`` holds every such set-up; ``partial``, where the kernel sets it, its
    results, complete for every other set-up (each depends on nothing else in the run).
    ``lanes`` holds the lanes handed back alone, in the caller's order (the Mindlin lanes
    hand back a lane that stalls and finish the others of its set-up; its results in
    ``partial`` are NaN)."""

    def __init__(self, message: str, setups: np.ndarray, lanes: np.ndarray | None = None):
        super().__init__(message)
        self.setups = setups
        self.lanes = np.zeros(0, dtype=np.int64) if lanes is None else lanes
        self.partial: tuple | None = None


# The statuses of a set-up that :func:`raise_on_failure` hands back, with their reason.
HANDED_BACK = {LANE_STALLED: "a lane stalled"}


def raise_on_failure(status: np.ndarray, kernel: str, handed_back=None, lanes=None,
                     partial=None) -> None:  # fmt: skip
    """RuntimeError naming the first normal set-up whose status is not OK: a failed
    normal integration first, else :class:`LaneStalledError` for the statuses of
    ``handed_back`` ({status: reason}, default :data:`HANDED_BACK`) and for ``lanes``
    (the lanes a kernel hands back alone, in the caller's order), which it carries with
    ``partial`` (the kernel's results, complete for everything not handed back)."""
    handed_back = HANDED_BACK if handed_back is None else handed_back
    back = np.isin(status, list(handed_back))
    failed = np.flatnonzero((status != OK) & ~back)
    if failed.size:
        g = int(failed[0])
        raise RuntimeError(
            f"{kernel}: the normal integration failed in set-up {g} (status {status[g]})"
        )
    setups = np.flatnonzero(back)
    lanes = np.zeros(0, dtype=np.int64) if lanes is None else lanes
    if setups.size:
        g = int(setups[0])
        message = f"{kernel}: {handed_back[int(status[g])]} in set-up {g} (status {status[g]})"
    elif lanes.size:
        message = f"{kernel}: {lanes.size} lane(s) stalled, lane {lanes[0]} first"
    else:
        return
    error = LaneStalledError(message, setups, lanes)
    error.partial = partial
    raise error


@njit(cache=True)
def start_modes(lanes, lo, hi, n0):
    """Lanes [lo, hi) at rest start to slide towards F unless |F| <= μ_s N(0) (2.2);
    ``n0`` [N] is N at t = 0 of their normal set-up."""
    for i in range(lo, hi):
        if lanes[MODE, i] == 0.0 and lanes[V, i] == 0.0 and n0 < lanes[N_RELEASE, i]:
            lanes[MODE, i] = lanes[DIRECTION, i]


@njit(cache=True)
def take_group(lanes, lo, hi):
    """(group lanes, switches, flagged) of the set-up whose lanes are columns [lo, hi)
    of ``lanes``: a C-contiguous copy of those columns (every row) and zeroed counts."""
    group = np.empty((lanes.shape[0], hi - lo))
    for row in range(lanes.shape[0]):
        for i in range(lo, hi):
            group[row, i - lo] = lanes[row, i]
    return group, np.zeros(hi - lo, dtype=np.int64), np.zeros(hi - lo, dtype=np.int64)


@njit(cache=True)
def put_group(lanes, switches, flagged, lo, group, group_switches, group_flagged):
    """Write a set-up's lanes and counts (:func:`take_group`) back from column ``lo``.
    Loops, not slice assignments: those compile numba's shape-mismatch error message
    (string formatting, ~1.5 s of cold compile; docs/design.md)."""
    for row in range(group.shape[0]):
        for i in range(group.shape[1]):
            lanes[row, lo + i] = group[row, i]
    for i in range(group.shape[1]):
        switches[lo + i] = group_switches[i]
        flagged[lo + i] = group_flagged[i]


# Row 0 as a NumPy integer: a literal 0 would compile lanes_over_rows a second time, for
# Literal[int](0) beside int64 (~2 s of cold compile; docs/design.md).
FIRST_ROW = np.int64(0)


@njit(cache=True)
def _run_group(c, y0, ydot0, cycle, shape, t_end, dt, lanes, switches, flagged, park, stop,
               item):  # fmt: skip
    """One normal set-up and its lanes (rows FM ... FLAG of ``lanes``), sorted by
    decreasing |F|/μ_s, in place; returns the status. Only lanes [0, n_active) can be
    moving: past it every lane sticks, and one that a piece cannot release
    (|F|/μ_s <= min P) is left alone. A periodic normal motion (``shape`` from
    :func:`periodic_tape.cycle_rows` with period rows > 0) goes through
    :func:`_run_cycle`. Returns STOPPED after a block of tape once ``stop[0]`` is set
    (:func:`threads.stop_flag`), and reports its progress there as ``item``
    (:func:`threads.report`)."""
    n = lanes.shape[1]
    start_modes(lanes, 0, n, normal_force(0.0, y0, ydot0, as_tuple(c)))
    n_active = active_end(lanes, n)
    if shape[0] > 0:
        return _run_cycle(cycle, shape, lanes, switches, flagged, n_active, park, stop, item)
    carry, tape, work = nt.tape_buffers(y0, ydot0)
    while True:
        if stop[0] != 0:
            return STOPPED
        rows, tape_status = nt.fill_tape(carry, c, t_end, dt, tape, work)
        if tape_status > 1:
            return tape_status
        status, n_active = lanes_over_rows(
            tape, FIRST_ROW, rows, lanes, n, n_active, switches, flagged
        )
        if status != OK:
            return status
        threads.report(stop, item, carry[nt.C_T] / t_end)
        if tape_status == 0:
            return OK


@njit(cache=True)
def _run_cycle(cycle, shape, lanes, switches, flagged, n_active, park, stop, item):
    """The lanes through ``repeats`` periods of ``cycle`` and its tail (``shape`` =
    (period rows, tail rows, repeats, T)), in place; returns the status (STOPPED after a
    period once ``stop[0]`` is set; the periods done reported as ``item``).

    Every period's pieces are the same rows, and a lane's law reads its state (ẋ, mode)
    and never x. So a lane that starts a period in the state it started the previous one
    with repeats that period, bit for bit, and so every period up to the tail. With
    ``park`` such a lane is parked (moved past the live lanes, out of every pass) and
    at the tail takes its remaining periods at once: x += (periods left) Δx, the counts
    likewise, Δx its last period's increment of x. That differs from adding Δx period by
    period only in rounding (docs/theory/numerics.md, "Repeating lanes"). Whether a lane
    parks depends on that lane alone, so its bits still do not depend on the others.
    """
    period_rows, tail_rows, repeats, _period = shape
    n = lanes.shape[1]
    book = parking.new_book(n)
    n_live = n
    for k in range(repeats):
        if stop[0] != 0:
            return STOPPED
        if park:
            parking.mark_period_start(lanes, switches, flagged, book, n_live, X, V, MODE)
        status, n_active = lanes_over_rows(
            cycle, FIRST_ROW, period_rows, lanes, n_live, n_active, switches, flagged
        )
        if status != OK:
            return status
        threads.report(stop, item, (k + 1) / (repeats + 1))
        if park and k + 1 < repeats:
            n_live = parking.park(lanes, switches, flagged, book, n_live, k + 1, X, V, MODE)
            # The live lanes kept their order: the moving ones are still below n_active.
            n_active = active_end(lanes, min(n_active, n_live))
            if n_live == 0:
                break  # every lane parked: the periods left cost nothing (a long run's)
    if n_live < n:
        parking.unpark(lanes, switches, flagged, book, n_live, repeats, X)
    return lanes_over_rows(
        cycle, period_rows, period_rows + tail_rows, lanes, n, active_end(lanes, n),
        switches, flagged,
    )[0]  # fmt: skip


@njit(cache=True, nogil=True)
def _run_groups(g_lo, g_hi, normal_c, y0, ydot0, cycles, offsets, shapes, starts, lanes,
                switches, flagged, status, t_end, dt, park, stop):  # fmt: skip
    """Set-ups [g_lo, g_hi) and their lanes, in place (a range of :func:`threads.run_ranges`,
    ``stop`` its flag)."""
    for g in range(g_lo, g_hi):
        lo, hi = starts[g], starts[g + 1]
        group_lanes, group_switches, group_flagged = take_group(lanes, lo, hi)
        cycle, shape = periodic_tape.group_cycle(cycles, offsets, shapes, g)
        status[g] = _run_group(
            normal_c[g].copy(), y0[g], ydot0[g], cycle, shape, t_end, dt, group_lanes,
            group_switches, group_flagged, park, stop, g,
        )  # fmt: skip
        put_group(lanes, switches, flagged, lo, group_lanes, group_switches, group_flagged)


def run_shared(normal_coeffs, normal_states0, group_of_lane, forces, mu_static, mu_kinetic,
               t_end, dt, x0=None, v0=None, periods=None, park=True,
               on_done=None):  # fmt: skip
    """Final tangential states of many lanes on shared normal motions (arrays, SI).

    Parameters
    ----------
    normal_coeffs : (G, SIZE) coefficient vectors of the G normal set-ups (their
        tangential slots are ignored; see :func:`normal_tape.normal_coefficients`).
    normal_states0 : (G, 2) initial (y [m], ẏ [m/s]) of each set-up at t = 0.
    group_of_lane : (L,) int, the set-up of each lane.
    forces : (L,) constant tangential force F [N]; mu_static, mu_kinetic : (L,) [-].
    t_end : end time [s]; dt : RK4 step of the normal motion [s] (grid k·dt).
    x0, v0 : (L,) initial x [m] and ẋ [m/s] (default 0: at rest).
    periods : (G,) period [s] of each set-up's normal motion where it is periodic from
        t = 0 (a conservative free vibration), else 0 (default: all 0): one period's
        tape is then repeated (:mod:`~microslip.integrators.periodic_tape`).
    park : on a repeated tape, a lane that starts a period as it started the last one
        takes its remaining periods at once (:func:`_run_cycle`); False steps every
        lane through every period (the same result to rounding, slower).
    on_done : told of the set-ups done since its last call, in parts as they advance (a
        caller's progress: :func:`threads.run_ranges`).

    Returns (x, ẋ, mode, switches, flagged) per lane at ``t_end``; raises RuntimeError
    if a normal integration or a lane fails.
    """
    normal_coeffs = np.ascontiguousarray(normal_coeffs, dtype=np.float64)
    normal_states0 = np.asarray(normal_states0, dtype=np.float64)
    # Few set-ups run as copies that share out their lanes (the same bits).
    copies = SetupCopies.plan(group_of_lane, normal_coeffs.shape[0])
    normal_coeffs, normal_states0 = copies.spread(normal_coeffs), copies.spread(normal_states0)
    if periods is not None:
        periods = copies.spread(periods)
    lanes, order, starts = pack_lanes(
        normal_coeffs, copies.lane_copy, forces, mu_static, mu_kinetic, x0, v0
    )
    n_lanes = order.size
    switches = np.zeros(n_lanes, dtype=np.int64)
    flagged = np.zeros(n_lanes, dtype=np.int64)
    status = np.zeros(copies.n_copies, dtype=np.int64)
    cycles = periodic_tape.cycles(normal_coeffs, normal_states0, periods, t_end, dt)
    stop = threads.stop_flag(copies.n_copies)
    threads.run_ranges(
        _run_groups, copies.n_copies, normal_coeffs, normal_states0[:, 0].copy(),
        normal_states0[:, 1].copy(), *cycles, starts, lanes, switches, flagged, status,
        float(t_end), float(dt), bool(park), stop, per_task=1, stop=stop,
        on_done=copies.done(on_done),
    )  # fmt: skip
    raise_on_failure(copies.status(status), "shared-normal kernel")
    return unpack_lanes(lanes, order, switches, flagged)


def pack_lanes(normal_coeffs, group_of_lane, forces, mu_static, mu_kinetic, x0=None,
               v0=None):  # fmt: skip
    """(lanes, order, starts): the lane array (rows FM ... FLAG) of :func:`run_shared`'s
    lanes in kernel order (by set-up, then by decreasing |F|/μ_s, ties in lane order:
    see :func:`_run_group`), ``order`` the lane of each column and ``starts`` (G + 1,)
    the first column of each set-up."""
    group_of_lane = np.asarray(group_of_lane, dtype=np.int64)
    n_lanes = group_of_lane.size
    forces = np.asarray(forces, dtype=np.float64)
    mu_s = np.asarray(mu_static, dtype=np.float64)
    mu_k = np.asarray(mu_kinetic, dtype=np.float64)
    n_release = np.where(forces == 0.0, -math.inf, np.abs(forces) / mu_s)
    # By set-up, then by decreasing |F|/μ_s (ties in lane order): see _run_group.
    order = np.lexsort((np.arange(n_lanes), -n_release, group_of_lane))
    counts = np.bincount(group_of_lane, minlength=normal_coeffs.shape[0])
    starts = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    mass = normal_coeffs[group_of_lane, MASS]
    fm = forces / mass
    km = mu_k / mass
    n_balance = forces / mu_k
    direction = np.sign(forces)
    x = np.zeros(n_lanes) if x0 is None else np.array(x0, dtype=np.float64)
    v = np.zeros(n_lanes) if v0 is None else np.array(v0, dtype=np.float64)
    mode = np.sign(v)
    lanes = np.zeros((LANE_ROWS, n_lanes))
    rows = (FM, KM, N_RELEASE, N_BALANCE, DIRECTION, X, V, MODE)
    values = (fm, km, n_release, n_balance, direction, x, v, mode)
    for row, value in zip(rows, values, strict=True):
        lanes[row] = value[order]
    return lanes, order, starts


def unpack_lanes(lanes, order, switches, flagged):
    """(x, ẋ, mode, switches, flagged) per lane in the caller's order, from the kernel's
    columns (:func:`pack_lanes`)."""
    inverse = np.empty_like(order)
    inverse[order] = np.arange(order.size)
    x, v, mode = lanes[X][inverse], lanes[V][inverse], lanes[MODE][inverse]
    return x, v, mode, switches[inverse], flagged[inverse]
