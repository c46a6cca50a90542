"""The per-piece vector of the Mindlin-lane law: what all the lanes of a set-up share on
one piece (a tape row, :mod:`microslip.integrators.normal_tape`).

:func:`set_setup` writes the set-up's slots (m [kg], g [m/s^2], λ [-]); :func:`set_piece`
then writes, once per piece, the rest of the PIECE floats, at the M_* slots defined here:

- h [s] and the bounds of the normal force quartic's derivatives [N]
  (:func:`~microslip.integrators.spring_lane_law.derivative_bounds`);
- the quartics k_t(τ) = λ dN_el/dδ [N/m] and R(τ) = Ṅ/k_t [m/s], fitted to their
  values at the five Chebyshev points of [0, 1], at the normal states of the tape's
  quintic Hermite interpolant (:func:`hermite_state`);
- the power series in τ of the two columns of the stick's fundamental matrix Φ(τ), the
  state (ẋ, e) from (1, 0) and (0, 1), and of their ∫ẋ (times h), up to DEGREE terms
  (:func:`_fundamental_series`), with Φ(1), ∫ẋ(1) and the coefficient sums that bound
  the lanes' switching functions.

:mod:`microslip.integrators.mindlin_lane_law` evaluates a lane on the piece from this
vector; the CUDA kernel (:mod:`microslip.integrators.mindlin_lanes_cuda`) fills a table
of them, one per piece.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import normal_tape as nt
from microslip.integrators.spring_lane_law import derivative_bounds
from microslip.model.coefficients import GRAVITY, MASS
from microslip.model.contact import elastic_stiffness
from microslip.model.normal import gap, normal_force_rate

DEGREE = 24  # of the series: its terms θ^n/n! fall below 1e-17 for θ <= MAX_THETA
MAX_THETA = 2.0  # largest h sqrt(max k_t / m) of a piece (a finer dt beyond)
_SERIES_TOLERANCE = 1e-17

# Chebyshev points of the first kind on [0, 1] and the inverse of their Vandermonde
# matrix: the monomial coefficients of the quartic through five values there.
_NODES = 0.5 * (1.0 - np.cos((2.0 * np.arange(5) + 1.0) * np.pi / 10.0))
_FIT = np.linalg.inv(np.vander(_NODES, 5, increasing=True))

# Slots of the per-piece vector (one per set-up, rewritten each piece).
(M_H, M_MASS, M_GRAVITY, M_RATIO, M_D0, M_D1, M_D2, M_D3, M_DEG) = range(9)
M_K = 9  # the quartic k_t(τ) [N/m], 5 coefficients
M_R = 14  # the quartic R(τ) = Ṅ/k_t [m/s], 5 coefficients
(M_PHI11, M_PHI12, M_PHI21, M_PHI22, M_PSI1, M_PSI2) = range(19, 25)  # Φ(1), ∫ẋ at τ = 1
# Σ n(n-1)|c_n|, Σ n(n-1)(n-2)|c_n| and Σ|c_n| of the e-series of both columns, then
# Σ|r_n| and the bounds of |R''|, |R'''| on [0, 1].
(M_E1_2, M_E2_2, M_E1_3, M_E2_3, M_E1_0, M_E2_0, M_R_0, M_R_2, M_R_3) = range(25, 34)
M_NODES = 34  # scratch: k_t and R at the five nodes
_SERIES = 44
_N = DEGREE + 1
M_V1, M_E1, M_V2, M_E2, M_X1, M_X2 = (_SERIES + j * _N for j in range(6))
PIECE = _SERIES + 6 * _N

TOO_COARSE = -2  # set_piece's status: θ > MAX_THETA


@njit(cache=True, inline="always")
def hermite_state(tape, r, sigma):
    """(t [s], y [m], ẏ [m/s]) at τ = ``sigma`` of tape row r, from the quintic Hermite
    interpolant of y through y, ẏ, ÿ at both ends (O(h⁶) in y; at τ = 1/2 the middle
    state of :func:`~microslip.integrators.normal_tape.piece_coefficients`)."""
    h = tape[r, nt.H]
    y0, v0, acc0 = tape[r, nt.Y_START], tape[r, nt.YDOT_START], tape[r, nt.YDDOT_START]
    y1, v1, acc1 = tape[r, nt.Y_END], tape[r, nt.YDOT_END], tape[r, nt.YDDOT_END]
    s = sigma
    s2 = s * s
    s3 = s2 * s
    # The quintic Hermite basis and its derivatives (value, slope, curvature at each end).
    rise = s3 * (10.0 - 15.0 * s + 6.0 * s2)
    slope0 = s - s3 * (6.0 - 8.0 * s + 3.0 * s2)
    curv0 = 0.5 * (s2 - s3 * (3.0 - 3.0 * s + s2))
    slope1 = -s3 * (4.0 - 7.0 * s + 3.0 * s2)
    curv1 = 0.5 * s3 * (1.0 - 2.0 * s + s2)
    d_rise = 30.0 * s2 * (1.0 - 2.0 * s + s2)
    d_slope0 = 1.0 - s2 * (18.0 - 32.0 * s + 15.0 * s2)
    d_curv0 = 0.5 * (2.0 * s - s2 * (9.0 - 12.0 * s + 5.0 * s2))
    d_slope1 = -s2 * (12.0 - 28.0 * s + 15.0 * s2)
    d_curv1 = 0.5 * s2 * (3.0 - 8.0 * s + 5.0 * s2)
    y = (
        y0
        + (y1 - y0) * rise
        + h * (v0 * slope0 + v1 * slope1)
        + h * h * (acc0 * curv0 + acc1 * curv1)
    )
    ydot = (
        (y1 - y0) * d_rise / h
        + v0 * d_slope0
        + v1 * d_slope1
        + h * (acc0 * d_curv0 + acc1 * d_curv1)
    )
    return tape[r, nt.T0] + s * h, y, ydot


@njit(cache=True, inline="always")
def set_setup(piece, mass, gravity, ratio):
    """Write a set-up's slots of ``piece``: m [kg], g [m/s^2], λ [-]."""
    piece[M_MASS], piece[M_GRAVITY], piece[M_RATIO] = mass, gravity, ratio


@njit(cache=True)
def set_piece(piece, a, tape, r, c):
    """Write tape row r's slots of ``piece`` (its set-up's written already): h, the
    bounds of the quartic ``a``'s derivatives, the quartics k_t(τ) and R(τ), and the
    stick's fundamental series. Returns 0, or TOO_COARSE when θ > MAX_THETA."""
    h = tape[r, nt.H]
    mass, ratio = piece[M_MASS], piece[M_RATIO]
    piece[M_H] = h
    piece[M_D0], piece[M_D1], piece[M_D2], piece[M_D3] = derivative_bounds(a)
    k_nodes = piece[M_NODES : M_NODES + 5]
    r_nodes = piece[M_NODES + 5 : M_NODES + 10]
    for j in range(5):
        t, y, ydot = hermite_state(tape, r, _NODES[j])
        delta = gap(t, y, ydot, c)[0]
        k = ratio * elastic_stiffness(delta, c) if delta > 0.0 else 0.0
        k_nodes[j] = k
        r_nodes[j] = normal_force_rate(t, y, ydot, c) / k if k > 0.0 else 0.0
    k_bound = 0.0
    for i in range(5):
        kc = 0.0
        rc = 0.0
        for j in range(5):
            kc += _FIT[i, j] * k_nodes[j]
            rc += _FIT[i, j] * r_nodes[j]
        piece[M_K + i] = kc
        piece[M_R + i] = rc
        k_bound += abs(kc)
    q = piece[M_R : M_R + 5]
    piece[M_R_0] = abs(q[0]) + abs(q[1]) + abs(q[2]) + abs(q[3]) + abs(q[4])
    piece[M_R_2] = 2.0 * abs(q[2]) + 6.0 * abs(q[3]) + 12.0 * abs(q[4])
    piece[M_R_3] = 6.0 * abs(q[3]) + 24.0 * abs(q[4])
    if h * math.sqrt(k_bound / mass) > MAX_THETA:
        return TOO_COARSE
    _fundamental_series(piece, h, mass, math.sqrt(k_bound * mass) if k_bound > 0.0 else mass / h)
    return 0


@njit(cache=True)
def _fundamental_series(piece, h, mass, scale):
    """The power series of the two columns of Φ (from (ẋ, e) = (1, 0) and (0, 1)) and of
    their ∫ẋ (times h), with its degree, Φ(1), ∫ẋ(1) and the coefficient sums of the
    e-series; ``scale`` = m ω [N s/m] weighs e against ẋ in the truncation."""
    k = piece[M_K : M_K + 5]
    v1, e1, v2, e2 = (
        piece[M_V1 : M_V1 + _N],
        piece[M_E1 : M_E1 + _N],
        piece[M_V2 : M_V2 + _N],
        piece[M_E2 : M_E2 + _N],
    )
    x1, x2 = piece[M_X1 : M_X1 + _N], piece[M_X2 : M_X2 + _N]
    # Φ(0) = I; the loop writes every coefficient up to the degree it stops at, and
    # nothing reads past that degree.
    v1[0], e1[0], v2[0], e2[0], x1[0], x2[0] = 1.0, 0.0, 0.0, 1.0, 0.0, 0.0
    h_m = h / mass
    degree = DEGREE
    small = 0
    for n in range(DEGREE):
        inv = 1.0 / (n + 1.0)
        v1[n + 1] = -h_m * e1[n] * inv
        v2[n + 1] = -h_m * e2[n] * inv
        s1 = 0.0
        s2 = 0.0
        for j in range(min(4, n) + 1):
            s1 += k[j] * v1[n - j]
            s2 += k[j] * v2[n - j]
        e1[n + 1] = h * s1 * inv
        e2[n + 1] = h * s2 * inv
        x1[n + 1] = h * v1[n] * inv
        x2[n + 1] = h * v2[n] * inv
        size = abs(v1[n + 1]) + abs(e1[n + 1]) / scale + abs(v2[n + 1]) * scale + abs(e2[n + 1])
        small = small + 1 if size < _SERIES_TOLERANCE else 0
        if small == 5:  # k is a quartic: five negligible terms in a row end the series
            degree = n - 4  # the last term that is not negligible
            break
    piece[M_DEG] = degree
    phi11 = phi12 = phi21 = phi22 = psi1 = psi2 = 0.0
    e1_2 = e2_2 = e1_3 = e2_3 = e1_0 = e2_0 = 0.0
    for n in range(degree + 1):
        phi11 += v1[n]
        phi12 += v2[n]
        phi21 += e1[n]
        phi22 += e2[n]
        psi1 += x1[n]
        psi2 += x2[n]
        w2 = n * (n - 1.0)
        w3 = w2 * (n - 2.0)
        e1_2 += w2 * abs(e1[n])
        e2_2 += w2 * abs(e2[n])
        e1_3 += w3 * abs(e1[n])
        e2_3 += w3 * abs(e2[n])
        e1_0 += abs(e1[n])
        e2_0 += abs(e2[n])
    piece[M_PHI11], piece[M_PHI12], piece[M_PHI21], piece[M_PHI22] = phi11, phi12, phi21, phi22
    piece[M_PSI1], piece[M_PSI2] = psi1, psi2
    piece[M_E1_2], piece[M_E2_2], piece[M_E1_3], piece[M_E2_3] = e1_2, e2_2, e1_3, e2_3
    piece[M_E1_0], piece[M_E2_0] = e1_0, e2_0


@njit(cache=True)
def piece_table(table, rows, n_rows, laws, ratio):
    """Write the piece of each contact row r < ``n_rows`` of ``rows`` into table[r]
    (its set-up's slots, :func:`set_setup`, and :func:`set_piece`'s; ``laws`` the
    coefficient tuple, ``ratio`` λ [-]); returns the first row too coarse for the
    tangential oscillation (θ > MAX_THETA), or ``n_rows``. The Mindlin lanes on a
    repeated tape write each cycle row's piece once and read it every period."""
    coarse = n_rows
    for r in range(n_rows):
        set_setup(table[r], laws[MASS], laws[GRAVITY], ratio)
        a = nt.coefficients(rows, r)
        if nt.flight_piece(a):
            continue
        if set_piece(table[r], a, rows, r, laws) != 0 and coarse == n_rows:
            coarse = r
    return coarse
