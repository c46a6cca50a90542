"""The law of one rigid lane over a piece of the normal tape (the shared-normal kernel's
lanes, :mod:`microslip.integrators.shared_lanes`, and their GPU twin).

A lane is the tangential motion of a body on a rigid contact under a constant force F
(eqs. 2.2, 2.5, with the friction law's static and kinetic coefficients):

    stick (mode 0):          holds while |F| <= μ_s N                     (2.2)
    slip in s = ±1:          m ẍ = F - s μ_k N,                           (2.5)

and over a piece in slip it integrates in closed form on the tape's polynomial P(τ),

    ẋ(τ) = ẋ_a + h (F/m)(τ - τ_a) - s (μ_k/m) h (I(τ) - I(τ_a)),
    x(τ) = x_a + h ẋ_a (τ - τ_a) + h² (F/m)(τ - τ_a)²/2
           - s (μ_k/m) h² (K(τ) - K(τ_a) - I(τ_a)(τ - τ_a)),

with I, K the first and second integrals of P. :func:`free_piece` is that closed form
for a piece without a switch, branch-free, with the flag of a lane where a switch may lie
inside the piece:

* stick: the piece's exact minimum of P is below |F|/μ_s (release);
* slip: s ẋ ends <= 0 (stop or reversal), or the acceleration changes sign inside the
  piece (P crosses s F/μ_k) while the speed is within the piece's largest change of 0.

:func:`lane_piece` redoes a flagged lane alone: every switching instant is the root of
a function that is monotone on the piece's segments (P between its critical points; the
speed between the zeros of its acceleration), bracketed there and found to 1e-12 of the
piece, so no double crossing can hide and the located switching keeps the order of the
normal RK4 integration (4: tests/validation/test_shared_normal_order.py). At a stop the
lane sticks if |F| <= μ_s N there, else slides towards F (eq. 2.2).
"""

from __future__ import annotations

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import normal_tape as nt
from microslip.integrators.kernel import MAX_SWITCHES_PER_STEP

_BISECTIONS = 64
# Of a piece: ~3e-18 s at the default step (T0/200), far below the RK4 error; finer
# buys nothing where P is flat to rounding near a crossing, and costs evaluations.
_TAU_TOLERANCE = 1e-12


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


# ``kind`` and ``zero_above`` are literals at _root's three call sites on purpose: numba
# compiles it once for each pair (~0.3 s each of a cold start), and the branches folded
# away make the forced time map ~6% faster than one compile with them as run-time
# values (NumPy scalars: 0.188-0.21 s against 0.178-0.189 s, alternating, 2026-11-29).
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


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always", error_model="numpy")
def free_piece(mode, v, x, fm, km, n_release, n_balance, h, h_int, h2_kint, p_min, p_max):
    """(flag, x1, ẋ1) of a lane over a piece as if it held no switch: the closed form of
    the module doc in slip, the state held in stick; ``flag`` is True where a switch may
    lie inside the piece (module doc), and the lane must be redone by
    :func:`lane_piece`. ``h_int`` = h I(1) = ∫ N dt [N s], ``h2_kint`` = h² K(1) =
    ∫ (t1 - t) N dt [N s²]; p_min, p_max [N] the piece's extremes of P. The same over a
    span of pieces of total length h (:func:`~microslip.integrators.normal_tape.span`).
    Branch-free: every lane of a vector loop (or a GPU warp) runs the same instructions."""
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
