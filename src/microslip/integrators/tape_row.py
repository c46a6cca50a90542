"""One row of the normal tape: its columns, and the quartic P(τ) of the normal force on it.

A row of the tape (:mod:`microslip.integrators.normal_tape`, which fills it) is one piece
of the normal motion: its start t0 [s] and length h [s], the coefficients of

    P(τ) = a0 + a1 τ + a2 τ² + a3 τ³ + a4 τ⁴   [N],   τ = (t - t0)/h ∈ [0, 1],

the exact integrals I(1) = ∫₀¹ P and K(1) = ∫₀¹ (1 - τ) P [N], the extremes of P on
[0, 1] [N], its critical points (the roots of P', at most three, as τ) and the normal
state (y [m], ẏ [m/s], ÿ [m/s^2]) at both ends.

This module holds what is known of a piece without integrating anything: the column
indices of a row, the quartic's fit to the end and middle values (:func:`_quartic`), its
extremes and critical points (:func:`_extremes`), the readers of a row
(:func:`coefficients`, :func:`critical_points`), a span of rows as one piece
(:func:`span`) and the polynomial functions the lane laws evaluate inside a piece
(:func:`poly`, :func:`poly_rate`, :func:`integral`, :func:`double_integral`; also
called from the CUDA lane kernels). All are in τ: in time, dP/dt = P'(τ)/h [N/s],
∫ P dt = h I [N s] and the double integral h² K [N s²].
"""

from __future__ import annotations

import math

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)

# Columns of a tape row.
T0, H, A0, A1, A2, A3, A4, INT1, KINT1, PMIN, PMAX, NCRIT, CRIT1, CRIT2, CRIT3 = range(15)
# The normal state (y [m], ẏ [m/s], ÿ [m/s^2]) at both ends of the piece: a law that needs
# more of the normal motion than N (a Mindlin stiffness, k_t(δ)) interpolates it inside.
Y_START, YDOT_START, YDDOT_START, Y_END, YDOT_END, YDDOT_END = range(15, 21)
ROW = 21

_BISECTIONS = 60  # halvings of a bracket of P' (2^-60 < 1e-18 of a piece)


@njit(cache=True)
def _quartic(n0, d0, nm, n1, d1):
    """Coefficients (a0..a4) of the quartic with P(0) = n0, P'(0) = d0, P(1/2) = nm,
    P(1) = n1, P'(1) = d1 (derivatives per unit τ)."""
    r1 = n1 - n0 - d0
    r2 = d1 - d0
    r3 = nm - n0 - 0.5 * d0
    a4 = 16.0 * r3 - 8.0 * r1 + 2.0 * r2
    a3 = r2 - 2.0 * r1 - 2.0 * a4
    a2 = r1 - a3 - a4
    return n0, d0, a2, a3, a4


# The polynomial functions take the coefficients as a tuple a = (a0, ..., a4) [N]: a
# tuple goes by value through compiled calls, an array is reference-counted at each one
# (docs in integrators/kernel.py, "Speed").
@njit(cache=True)
def coefficients(tape, r):
    """The quartic's coefficients (a0, ..., a4) [N] of tape row r, as a tuple."""
    return tape[r, A0], tape[r, A1], tape[r, A2], tape[r, A3], tape[r, A4]


# A span of rows as one piece, for a lane law whose update over a piece needs only its
# length, integrals and extremes of N (the rigid one,
# :func:`~microslip.integrators.rigid_lane_law.free_piece`): (L [s], ∫ N dt [N s],
# ∫ (t1 - t) N dt [N s²], min N [N], max N [N]) over the span [t0, t1].
EMPTY_SPAN = (0.0, 0.0, 0.0, math.inf, -math.inf)


@njit(cache=True, inline="always")
def extend_span(span, h, int1, kint1, p_min, p_max):
    """``span`` followed by a row of length h [s], integrals I(1), K(1) [N] and extremes
    of P p_min, p_max [N]: ∫ (t1 - t) N dt gains the row's h² K(1) and h times the
    span's ∫ N dt before it. From EMPTY_SPAN, one row gives h, h I(1), h² K(1) and its
    extremes, bit for bit. Takes the row's values, not the tape: the CUDA lane kernels
    call it on their own reads of a tape."""
    length, first, second, low, high = span
    return (
        length + h,
        first + h * int1,
        second + (h * first + h * h * kint1),
        min(low, p_min),
        max(high, p_max),
    )


@njit(cache=True)
def span(tape, r0, r1):
    """Rows [r0, r1) of ``tape`` as one piece (:data:`EMPTY_SPAN`), in row order."""
    result = EMPTY_SPAN
    for r in range(r0, r1):
        result = extend_span(
            result, tape[r, H], tape[r, INT1], tape[r, KINT1], tape[r, PMIN], tape[r, PMAX]
        )
    return result


@njit(cache=True)
def flight_piece(a):
    """True for a tape piece in flight: its quartic P is 0 throughout."""
    return a[0] == 0.0 and a[1] == 0.0 and a[2] == 0.0 and a[3] == 0.0 and a[4] == 0.0


@njit(cache=True)
def has_flight(tape, n_rows):
    """True when one of the first ``n_rows`` rows of ``tape`` is in flight."""
    for r in range(n_rows):
        if flight_piece(coefficients(tape, r)):
            return True
    return False


@njit(cache=True)
def critical_points(tape, r):
    """(count, τ1, τ2, τ3) of tape row r: where P' = 0 inside the piece."""
    return int(tape[r, NCRIT]), tape[r, CRIT1], tape[r, CRIT2], tape[r, CRIT3]


# Estrin's scheme rather than Horner's: the lanes' switch searches evaluate these one
# after another, each on the last one's result, so their latency is what costs; Estrin
# halves the chain of dependent operations (a division by 3, 5, ... runs beside the
# powers of τ instead of inside the chain). Same accuracy, different rounding.
@njit(cache=True)
def poly(a, tau):
    """P(τ) [N]."""
    tau2 = tau * tau
    return (a[0] + tau * a[1]) + tau2 * ((a[2] + tau * a[3]) + tau2 * a[4])


@njit(cache=True)
def poly_rate(a, tau):
    """dP/dτ [N]."""
    return (a[1] + tau * (2.0 * a[2])) + (tau * tau) * (3.0 * a[3] + tau * (4.0 * a[4]))


@njit(cache=True)
def integral(a, tau):
    """I(τ) = ∫₀^τ P [N]."""
    tau2 = tau * tau
    low = a[0] + tau * (a[1] / 2.0)
    high = (a[2] / 3.0 + tau * (a[3] / 4.0)) + tau2 * (a[4] / 5.0)
    return tau * (low + tau2 * high)


@njit(cache=True)
def double_integral(a, tau):
    """K(τ) = ∫₀^τ I = ∫₀^τ (τ - σ) P(σ) dσ [N]."""
    tau2 = tau * tau
    low = a[0] / 2.0 + tau * (a[1] / 6.0)
    high = (a[2] / 12.0 + tau * (a[3] / 20.0)) + tau2 * (a[4] / 30.0)
    return tau2 * (low + tau2 * high)


@njit(cache=True)
def _root_of_rate(a, lo, hi):
    """The root of P' in [lo, hi], where P' changes sign and is monotone (bisection)."""
    f_lo = poly_rate(a, lo)
    for _ in range(_BISECTIONS):
        mid = 0.5 * (lo + hi)
        f_mid = poly_rate(a, mid)
        if (f_mid > 0.0) == (f_lo > 0.0):
            lo, f_lo = mid, f_mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@njit(cache=True)
def _extremes(a):
    """(min P, max P, count, τ1, τ2, τ3) on [0, 1]: the extremes and the critical
    points (roots of P') inside."""
    end = poly(a, 1.0)
    p_min, p_max = min(a[0], end), max(a[0], end)
    # Fast path: the Bernstein coefficients of P' (a cubic) all of one sign bound it
    # away from 0 on [0, 1]: P is monotone, its extremes are its end values.
    c0, c1, c2, c3 = a[1], 2.0 * a[2], 3.0 * a[3], 4.0 * a[4]
    b1 = c0 + c1 / 3.0
    b2 = c0 + 2.0 * c1 / 3.0 + c2 / 3.0
    b3 = c0 + c1 + c2 + c3
    if (c0 > 0.0 and b1 > 0.0 and b2 > 0.0 and b3 > 0.0) or (
        c0 < 0.0 and b1 < 0.0 and b2 < 0.0 and b3 < 0.0
    ):
        return p_min, p_max, 0, 0.0, 0.0, 0.0
    if flight_piece(a):  # P = 0 (a third of a forced tape's rows near resonance)
        return p_min, p_max, 0, 0.0, 0.0, 0.0
    # P' is monotone between the roots of P'' (a quadratic): at most one root of P' in
    # each of those intervals, found by bisection where P' changes sign.
    qa, qb, qc = 12.0 * a[4], 6.0 * a[3], 2.0 * a[2]
    turn_a, turn_b = 2.0, 2.0  # none
    if qa != 0.0:
        disc = qb * qb - 4.0 * qa * qc
        if disc > 0.0:
            root = disc**0.5
            turn_a = (-qb - root) / (2.0 * qa)
            turn_b = (-qb + root) / (2.0 * qa)
            if turn_a > turn_b:
                turn_a, turn_b = turn_b, turn_a
    elif qb != 0.0:
        turn_a = -qc / qb
    if not 0.0 < turn_a < 1.0:
        turn_a = turn_b
        turn_b = 2.0
    if not 0.0 < turn_b < 1.0:
        turn_b = 2.0
    if not 0.0 < turn_a < 1.0:
        turn_a = 2.0
    edges = (0.0, min(turn_a, 1.0), min(turn_b, 1.0), 1.0)
    # The critical points as scalars: a list would be allocated (and freed) per row.
    tau1, tau2, tau3 = 0.0, 0.0, 0.0
    n_crit = 0
    for k in range(3):
        lo, hi = edges[k], edges[k + 1]
        if hi <= lo:
            continue
        f_lo, f_hi = poly_rate(a, lo), poly_rate(a, hi)
        if (f_lo > 0.0 and f_hi < 0.0) or (f_lo < 0.0 and f_hi > 0.0):
            tau = _root_of_rate(a, lo, hi)
            if 0.0 < tau < 1.0:
                if n_crit == 0:
                    tau1 = tau
                elif n_crit == 1:
                    tau2 = tau
                else:
                    tau3 = tau
                n_crit += 1
                value = poly(a, tau)
                p_min = min(p_min, value)
                p_max = max(p_max, value)
    return p_min, p_max, n_crit, tau1, tau2, tau3
