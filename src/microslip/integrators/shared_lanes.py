"""Many tangential lanes on one shared normal motion: the time-domain map kernel.

The normal motion does not depend on the tangential one (docs/design.md), so a map over
forces and friction coefficients at a given normal set-up needs it once: it is
integrated by the core RK4 kernel into a tape of pieces, each carrying the normal force
as a quartic P(τ) in τ = (t - t0)/h (:mod:`microslip.integrators.normal_tape`). Each
lane then is the tangential motion of a body on a rigid contact under a constant force
F (eqs. 2.2, 2.5, with the friction law's static and kinetic coefficients):

    stick (mode 0):          holds while |F| <= μ_s N                     (2.2)
    slip in s = ±1:          m ẍ = F - s μ_k N,                           (2.5)

and over a piece in slip it integrates in closed form on the tape's polynomial,

    ẋ(τ) = ẋ_a + h (F/m)(τ - τ_a) - s (μ_k/m) h (I(τ) - I(τ_a)),
    x(τ) = x_a + h ẋ_a (τ - τ_a) + h² (F/m)(τ - τ_a)²/2
           - s (μ_k/m) h² (K(τ) - K(τ_a) - I(τ_a)(τ - τ_a)),

with I, K the first and second integrals of P. A common piece is therefore a few
multiply-adds per lane, in a branch-free loop over the lanes that LLVM vectorises; the
loop also flags the lanes where a switch may lie inside the piece:

* stick: the piece's exact minimum of P is below |F|/μ_s (release);
* slip: s ẋ ends <= 0 (stop or reversal), or the acceleration changes sign inside the
  piece (P crosses s F/μ_k) while the speed is within the piece's largest change of 0.

A flagged lane is redone alone: every switching instant is the root of a function that
is monotone on the piece's segments (P between its critical points; the speed between
the zeros of its acceleration), bracketed there and found to 1e-12 of the piece, so
no double crossing can hide and the located switching keeps the order of the normal
RK4 integration (4: tests/validation/test_shared_normal_order.py). At a stop the lane
sticks if |F| <= μ_s N there, else slides towards F (eq. 2.2).

Every lane's arithmetic depends only on its own parameters and its group's tape, and the
vector loop is compiled without fastmath (no FMA contraction): a lane's result is
bit-identical whatever the other lanes, their number, their order or the threads.
Groups (normal set-ups) run in parallel over the cores (``prange``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, parallel_chunksize, prange

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import normal_tape as nt
from microslip.integrators.kernel import MAX_SWITCHES_PER_STEP
from microslip.model.coefficients import MASS
from microslip.model.normal import normal_force

_BISECTIONS = 64
# Of a piece: ~3e-18 s at the default step (T0/200), far below the RK4 error; finer
# buys nothing where P is flat to rounding near a crossing, and costs evaluations.
_TAU_TOLERANCE = 1e-12

# Status per group.
OK = 0
LANE_STALLED = 5  # a lane switched more than MAX_SWITCHES_PER_STEP times in one piece


def raise_on_failure(status: np.ndarray, kernel: str) -> None:
    """RuntimeError naming the first normal set-up whose status is not OK."""
    bad = np.flatnonzero(status != OK)
    if bad.size:
        g = int(bad[0])
        what = "a lane stalled" if status[g] == LANE_STALLED else "the normal integration failed"
        raise RuntimeError(f"{kernel}: {what} in set-up {g} (status {status[g]})")


@njit(cache=True, inline="always")
def slip_speed(a, h, tau_a, v_a, s, fm, km, tau):
    """s·ẋ(τ) [m/s] of a lane sliding in direction s since (τ_a, ẋ_a) on a piece of
    length h [s] whose normal force is the quartic ``a``."""
    return (
        s * v_a
        + s * h * fm * (tau - tau_a)
        - km * h * (nt.integral(a, tau) - nt.integral(a, tau_a))
    )


@njit(cache=True, inline="always")
def slip_position(a, h, tau_a, x_a, v_a, s, fm, km, tau):
    """x(τ) [m] of a lane sliding in direction s since (τ_a, x_a, ẋ_a)."""
    d = tau - tau_a
    k = nt.double_integral(a, tau) - nt.double_integral(a, tau_a) - nt.integral(a, tau_a) * d
    return x_a + h * v_a * d + h * h * fm * d * d / 2.0 - s * km * h * h * k


@njit(cache=True, inline="always")
def _root_value(kind, a, h, tau_a, v_a, s, fm, km, level, tau):
    """(value, rate per unit τ) of the function whose root is sought: P - level
    (kind 0) or the speed s·ẋ (kind 1)."""
    if kind == 0:
        return nt.poly(a, tau) - level, nt.poly_rate(a, tau)
    rate = h * (s * fm - km * nt.poly(a, tau))
    return slip_speed(a, h, tau_a, v_a, s, fm, km, tau), rate


@njit(cache=True)
def _root(kind, a, h, tau_a, v_a, s, fm, km, level, lo, hi, f_lo, f_hi, zero_above):
    """The crossing in [lo, hi] of a function monotone there (:func:`_root_value`),
    with values ``f_lo``, ``f_hi`` at the ends: the returned τ is on the far side,
    within _TAU_TOLERANCE of the crossing. A value counts as above zero when > 0, or == 0 if
    ``zero_above``: the far side of a descent is then strictly below zero.
    Secant start, Newton steps inside the bracket, bisection when one leaves it or
    when a probe past a converged Newton root fails to close the bracket (a function
    flat to rounding there)."""
    lo_above = f_lo > 0.0 or (zero_above and f_lo == 0.0)
    tau = lo + (hi - lo) * f_lo / (f_lo - f_hi) if f_lo != f_hi else 0.5 * (lo + hi)
    probe = 0.0  # > 0 once Newton converged: the distance of the next probe
    for _ in range(_BISECTIONS):
        if hi - lo <= _TAU_TOLERANCE:
            break
        if not (lo < tau < hi):
            tau = 0.5 * (lo + hi)
        value, rate = _root_value(kind, a, h, tau_a, v_a, s, fm, km, level, tau)
        above = value > 0.0 or (zero_above and value == 0.0)
        if above == lo_above:
            lo = tau
        else:
            hi = tau
        step = value / rate if rate != 0.0 else 0.0
        newton = tau - step
        if probe > 0.0:
            # The probe did not close the bracket (the function is flat to rounding
            # there): probe twice as far, bisect once the bracket is that small.
            probe *= 2.0
            tau = tau + (probe if above == lo_above else -probe)
        elif rate != 0.0 and abs(step) <= 0.25 * _TAU_TOLERANCE:
            # Converged: probe just past the root to close the bracket from the far side.
            probe = 0.5 * _TAU_TOLERANCE
            tau = newton + (probe if above == lo_above else -probe)
        elif rate != 0.0 and lo < newton < hi:
            tau = newton
        else:
            tau = 0.5 * (lo + hi)
    return hi


@njit(cache=True, inline="always")
def _edges(crit):
    """(count, ends): the ends 0, critical points, 1 of the segments where P is
    monotone (``crit`` from :func:`~microslip.integrators.normal_tape.critical_points`)."""
    n_crit, tau1, tau2, tau3 = crit
    if n_crit == 0:
        return 2, (0.0, 1.0, 1.0, 1.0, 1.0)
    if n_crit == 1:
        return 3, (0.0, tau1, 1.0, 1.0, 1.0)
    if n_crit == 2:
        return 4, (0.0, tau1, tau2, 1.0, 1.0)
    return 5, (0.0, tau1, tau2, tau3, 1.0)


@njit(cache=True)
def _first_below(a, crit, tau_a, level):
    """First τ in [τ_a, 1] with P(τ) < level (the returned τ satisfies it), or 2."""
    n_edges, edges = _edges(crit)
    for k in range(n_edges - 1):
        hi = edges[k + 1]
        if hi <= tau_a:
            continue
        lo = max(edges[k], tau_a)
        f_lo = nt.poly(a, lo) - level
        if f_lo < 0.0:
            return lo
        f_hi = nt.poly(a, hi) - level
        if f_hi < 0.0:
            return _root(0, a, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, level, lo, hi, f_lo, f_hi, True)
    return 2.0


@njit(cache=True)
def _first_stop(a, crit, h, tau_a, v_a, s, fm, km, level):
    """First τ in (τ_a, 1] where the speed s·ẋ falls to 0 (the returned τ has s·ẋ <= 0),
    or 2. ``level`` = s F/μ_k: the acceleration changes sign where P crosses it."""
    n_edges, edges = _edges(crit)
    for k in range(n_edges - 1):
        seg_hi = edges[k + 1]
        if seg_hi <= tau_a:
            continue
        seg_lo = max(edges[k], tau_a)
        # The speed is monotone between the zeros of its acceleration: split the
        # segment where P (monotone on it) crosses the level.
        split = seg_hi
        p_lo = nt.poly(a, seg_lo) - level
        p_hi = nt.poly(a, seg_hi) - level
        if (p_lo > 0.0) != (p_hi > 0.0):
            split = _root(
                0, a, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, level, seg_lo, seg_hi, p_lo, p_hi, False
            )
        for part in range(2):
            lo = seg_lo if part == 0 else split
            hi = split if part == 0 else seg_hi
            if hi <= lo:
                continue
            w_hi = slip_speed(a, h, tau_a, v_a, s, fm, km, hi)
            if w_hi > 0.0:
                continue
            w_lo = slip_speed(a, h, tau_a, v_a, s, fm, km, lo)
            if w_lo <= 0.0:
                if lo > tau_a:
                    return lo
                w_lo = 1e-300  # starts at rest (a release): the speed must first rise
            return _root(1, a, h, tau_a, v_a, s, fm, km, 0.0, lo, hi, w_lo, w_hi, False)
    return 2.0


@njit(cache=True)
def lane_piece(a, crit, h, fm, km, n_release, n_balance, direction, x, v, mode):
    """(x, ẋ, mode, switches) of one lane at the end of a piece of length h [s] whose
    normal force is the quartic ``a`` with critical points ``crit``, through its
    switches; switches = -1 if the lane stalled."""
    tau = 0.0
    switches = 0
    for _ in range(MAX_SWITCHES_PER_STEP):
        if mode == 0.0:
            tau_r = _first_below(a, crit, tau, n_release)
            if tau_r > 1.0:
                return x, 0.0, 0.0, switches
            tau = tau_r
            mode = direction
            v = 0.0
            switches += 1
            continue
        s = mode
        tau_s = _first_stop(a, crit, h, tau, v, s, fm, km, s * n_balance)
        if tau_s > 1.0:
            x1 = slip_position(a, h, tau, x, v, s, fm, km, 1.0)
            v1 = s * slip_speed(a, h, tau, v, s, fm, km, 1.0)
            return x1, v1, mode, switches
        x = slip_position(a, h, tau, x, v, s, fm, km, tau_s)
        v = 0.0
        tau = tau_s
        switches += 1
        # At rest: stick iff |F| <= μ_s N (2.2), else slide towards F.
        mode = direction if nt.poly(a, tau) < n_release else 0.0
    return x, v, mode, -1


# Rows of the lane array of a group (one array: a compiled call counts each array
# argument once, so the per-piece pass takes one).
FM, KM, N_RELEASE, N_BALANCE, DIRECTION, X, V, MODE, FLAG = range(9)
LANE_ROWS = 9


@njit(cache=True, inline="always", error_model="numpy")
def free_piece(mode, v, x, fm, km, n_release, n_balance, h, h_int, h2_kint, p_min, p_max):
    """(flag, x1, ẋ1) of a lane over a piece as if it held no switch: the closed form of
    the module doc in slip, the state held in stick; ``flag`` is True where a switch may
    lie inside the piece (module doc), and the lane must be redone by
    :func:`lane_piece`. ``h_int`` = h I(1), ``h2_kint`` = h² K(1); p_min, p_max [N] the
    piece's extremes of P. Branch-free: every lane of a vector loop (or a GPU warp) runs
    the same instructions."""
    s = mode
    active = s * s
    skm = s * km
    v1 = v + active * (h * fm - skm * h_int)
    x1 = x + active * (h * v + 0.5 * h * h * fm - skm * h2_kint)
    release = p_min < n_release
    level = s * n_balance
    turning = (p_min < level) & (level < p_max)
    near = s * v <= 2.0 * h * (abs(fm) + km * p_max)
    stop = (s * v1 <= 0.0) | (turning & near)
    flag = ((active == 0.0) & release) | ((active != 0.0) & stop)
    return flag, x1, v1


@njit(cache=True, error_model="numpy")
def _vector_pass(lanes, n_range, h, h_int, h2_kint, p_min, p_max):
    """A piece for lanes [0, n_range) as if it held no switch (:func:`free_piece`),
    vectorised. A flagged lane keeps its state. Returns the number of flagged lanes."""
    n_flagged = 0
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
    return n_flagged


@njit(cache=True)
def start_modes(lanes, lo, hi, n0):
    """Lanes [lo, hi) at rest start to slide towards F unless |F| <= μ_s N(0) (2.2);
    ``n0`` [N] is N at t = 0 of their normal set-up."""
    for i in range(lo, hi):
        if lanes[MODE, i] == 0.0 and lanes[V, i] == 0.0 and n0 < lanes[N_RELEASE, i]:
            lanes[MODE, i] = lanes[DIRECTION, i]


@njit(cache=True)
def _run_group(c, y0, ydot0, t_end, dt, lanes, switches, flagged):
    """One normal set-up and its lanes (rows FM ... FLAG of ``lanes``), sorted by
    decreasing |F|/μ_s, in place; returns the status. Only lanes [0, n_active) can be
    moving: past it every lane sticks, and one that a piece cannot release
    (|F|/μ_s <= min P) is left alone."""
    n = lanes.shape[1]
    start_modes(lanes, 0, n, normal_force(0.0, y0, ydot0, c))
    n_active = n
    while n_active > 0 and lanes[MODE, n_active - 1] == 0.0:
        n_active -= 1
    carry, tape, work = nt.tape_buffers(y0, ydot0)
    while True:
        rows, tape_status = nt.fill_tape(carry, c, t_end, dt, tape, work)
        if tape_status > 1:
            return tape_status
        for r in range(rows):
            h = tape[r, nt.H]
            p_min = tape[r, nt.PMIN]
            # Lanes a piece can release: |F|/μ_s > min P, a prefix (bisection).
            lo, hi = 0, n
            while lo < hi:
                mid = (lo + hi) // 2
                if lanes[N_RELEASE, mid] > p_min:
                    lo = mid + 1
                else:
                    hi = mid
            n_range = max(n_active, lo)
            n_flagged = _vector_pass(
                lanes, n_range, h, h * tape[r, nt.INT1], h * h * tape[r, nt.KINT1], p_min,
                tape[r, nt.PMAX],
            )  # fmt: skip
            a = nt.coefficients(tape, r)
            crit = nt.critical_points(tape, r)
            for i in range(n_range):
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
                        return LANE_STALLED
                    switches[i] += k
                    lanes[X, i], lanes[V, i], lanes[MODE, i] = xi, vi, mi
            n_active = n_range
            while n_active > 0 and lanes[MODE, n_active - 1] == 0.0:
                n_active -= 1
        if tape_status == 0:
            return OK


@njit(cache=True, parallel=True)
def _run_groups(normal_c, y0, ydot0, starts, lanes, switches, flagged, status, t_end, dt):
    for g in prange(normal_c.shape[0]):
        lo, hi = starts[g], starts[g + 1]
        group_lanes = np.ascontiguousarray(lanes[:, lo:hi])
        group_switches = np.zeros(hi - lo, dtype=np.int64)
        group_flagged = np.zeros(hi - lo, dtype=np.int64)
        status[g] = _run_group(
            normal_c[g].copy(), y0[g], ydot0[g], t_end, dt, group_lanes, group_switches,
            group_flagged,
        )  # fmt: skip
        lanes[:, lo:hi] = group_lanes
        switches[lo:hi] = group_switches
        flagged[lo:hi] = group_flagged


def run_shared(normal_coeffs, normal_states0, group_of_lane, forces, mu_static, mu_kinetic,
               t_end, dt, x0=None, v0=None):  # fmt: skip
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

    Returns (x, ẋ, mode, switches, flagged) per lane at ``t_end``; raises RuntimeError
    if a normal integration or a lane fails.
    """
    normal_coeffs = np.ascontiguousarray(normal_coeffs, dtype=np.float64)
    normal_states0 = np.asarray(normal_states0, dtype=np.float64)
    lanes, order, starts = pack_lanes(
        normal_coeffs, group_of_lane, forces, mu_static, mu_kinetic, x0, v0
    )
    n_lanes = order.size
    switches = np.zeros(n_lanes, dtype=np.int64)
    flagged = np.zeros(n_lanes, dtype=np.int64)
    status = np.zeros(normal_coeffs.shape[0], dtype=np.int64)
    with parallel_chunksize(1):
        _run_groups(
            normal_coeffs, normal_states0[:, 0].copy(), normal_states0[:, 1].copy(), starts,
            lanes, switches, flagged, status, float(t_end), float(dt),
        )  # fmt: skip
    raise_on_failure(status, "shared-normal kernel")
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
