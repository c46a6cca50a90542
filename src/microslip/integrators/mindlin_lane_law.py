"""One compliant tangential lane of Mindlin stiffness on a piece of the normal tape: a
contact point on a spring k_t = λ dN_el/dδ (``MindlinSpring``) under a constant force.

The laws are those of :mod:`microslip.integrators.spring_lane_law` (stick, slip on the
kinetic limit, flight with a relaxed spring, the same switches) with a stiffness that
follows the normal motion (docs/theory/friction_reduction.md):

    stick   m ẍ = F - f,  ḟ = k_t(t) ẋ   (the incremental law, u̇ = 0),
    slip    f = s μ_k N (the rigid law, eq. 2.5), while s u̇ = s ẋ - μ_k R > 0, R = Ṅ/k_t.

Both k_t(t) and R(t) [m/s] depend on the normal motion only: on each piece they are
quartics in τ = (t - t0)/h, interpolating λ dN_el/dδ and Ṅ/k_t at the five Chebyshev
points of [0, 1], at the normal states of the tape's quintic Hermite interpolant
(:func:`hermite_state`; O(h⁵), and no node at an end,
where δ = 0 makes k_t = 0 and Ṅ/k_t 0/0 at a contact switch).

Stick is then linear with polynomial coefficients. With e = f - F, the state (ẋ, e)
obeys dẋ/dτ = -(h/m) e, de/dτ = h k(τ) ẋ, whose fundamental matrix Φ(τ) (Φ(0) = I) is a
power series in τ, computed once per piece for all the lanes of a set-up by the
recurrence of its coefficients (exact for the quartic k; truncated where its terms fall
below 1e-17 of the state's scale: ~θ^n/n!, θ = h sqrt(max k/m)); x follows from
∫ẋ. A lane stuck from τ_a with (ẋ_a, e_a) has (ẋ, e)(τ) = Φ(τ) Φ(τ_a)⁻¹ (ẋ_a, e_a)
(det Φ = 1: the system has no trace). So every switching function of a lane is a
polynomial in τ on the piece, and its first exit is found by the safe marching steps of
the constant-stiffness law (bounds of its second and third derivatives from the sums of
its coefficients' moduli).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import normal_tape as nt
from microslip.integrators.kernel import MAX_SWITCHES_PER_STEP
from microslip.integrators.rigid_lane_law import slip_position
from microslip.integrators.rigid_lane_law import slip_speed as _slip_speed
from microslip.integrators.spring_lane_law import (
    FLIGHT,
    derivative_bounds,
    rate2,
    safe_step,
    touchdown,
)
from microslip.model.contact import elastic_stiffness
from microslip.model.normal import gap, normal_force_rate
from microslip.model.system import sign

DEGREE = 24  # of the series: its terms θ^n/n! fall below 1e-17 for θ <= MAX_THETA
MAX_THETA = 2.0  # largest h sqrt(max k_t / m) of a piece (a finer dt beyond)
_SERIES_TOLERANCE = 1e-17
_TAU_TOLERANCE = 1e-12  # of a piece, as in spring_lane_law
_MAX_STEPS = 2000
_ROUNDING = 1e-15
_STICK, _SLIP = 0, 1

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
            degree = n + 1
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


@njit(cache=True, inline="always")
def _series(piece, start, degree, tau):
    """(value, d/dτ, d²/dτ²) of the series at ``start`` in ``piece`` (Horner)."""
    value = piece[start + degree]
    rate = 0.0
    curvature = 0.0
    for n in range(degree - 1, -1, -1):
        curvature = curvature * tau + 2.0 * rate
        rate = rate * tau + value
        value = value * tau + piece[start + n]
    return value, rate, curvature


@njit(cache=True, inline="always")
def _quartic(piece, start, tau):
    """(value, d/dτ, d²/dτ²) of the quartic at ``start`` in ``piece``."""
    return _series(piece, start, 4, tau)


@njit(cache=True, inline="always")
def stick_state(piece, x0, v0, e0, tau):
    """(x [m], ẋ [m/s], e [N]) at τ of a lane stuck with virtual initial state
    (x0, ẋ0, e0) at τ = 0 (:func:`virtual_start`)."""
    degree = int(piece[M_DEG])
    v_1 = _series(piece, M_V1, degree, tau)[0]
    v_2 = _series(piece, M_V2, degree, tau)[0]
    e_1 = _series(piece, M_E1, degree, tau)[0]
    e_2 = _series(piece, M_E2, degree, tau)[0]
    x_1 = _series(piece, M_X1, degree, tau)[0]
    x_2 = _series(piece, M_X2, degree, tau)[0]
    return x0 + x_1 * v0 + x_2 * e0, v_1 * v0 + v_2 * e0, e_1 * v0 + e_2 * e0


@njit(cache=True, inline="always")
def virtual_start(piece, tau_a, x_a, v_a, e_a):
    """(x0, ẋ0, e0) at τ = 0 of the stick through (x_a, ẋ_a, e_a) at τ_a: Φ(τ_a)⁻¹."""
    if tau_a == 0.0:
        return x_a, v_a, e_a
    degree = int(piece[M_DEG])
    v_1 = _series(piece, M_V1, degree, tau_a)[0]
    v_2 = _series(piece, M_V2, degree, tau_a)[0]
    e_1 = _series(piece, M_E1, degree, tau_a)[0]
    e_2 = _series(piece, M_E2, degree, tau_a)[0]
    det = v_1 * e_2 - v_2 * e_1
    v0 = (e_2 * v_a - v_2 * e_a) / det
    e0 = (v_1 * e_a - e_1 * v_a) / det
    x_1 = _series(piece, M_X1, degree, tau_a)[0]
    x_2 = _series(piece, M_X2, degree, tau_a)[0]
    return x_a - (x_1 * v0 + x_2 * e0), v0, e0


@njit(cache=True, inline="always")
def _value(kind, a, piece, p, tau):
    """(g1, g1', g1'', g2, g2', g2'') at τ (derivatives in τ), as in spring_lane_law.

    Stick, p = (ẋ0, e0, F, μ_s, ...): g1,2 = μ_s P ∓ f, f = F + e(τ), e from the virtual
    start (ẋ0, e0). Slip, p = (τ_a, ẋ_a, s, F/m, μ_k/m, μ_k): g = s u̇ = s ẋ - μ_k R.
    """
    if kind == _STICK:
        v0, e0, force, mu_s = p[0], p[1], p[2], p[3]
        degree = int(piece[M_DEG])
        a1, b1, c1 = _series(piece, M_E1, degree, tau)
        a2, b2, c2 = _series(piece, M_E2, degree, tau)
        spring = force + a1 * v0 + a2 * e0
        spring_1 = b1 * v0 + b2 * e0
        spring_2 = c1 * v0 + c2 * e0
        limit = mu_s * nt.poly(a, tau)
        limit_1 = mu_s * nt.poly_rate(a, tau)
        limit_2 = mu_s * rate2(a, tau)
        return (
            limit - spring, limit_1 - spring_1, limit_2 - spring_2,
            limit + spring, limit_1 + spring_1, limit_2 + spring_2,
        )  # fmt: skip
    tau_a, v_a, s, fm, km, mu_k = p[0], p[1], p[2], p[3], p[4], p[5]
    h = piece[M_H]
    r, r_1, r_2 = _quartic(piece, M_R, tau)
    value = _slip_speed(a, h, tau_a, v_a, s, fm, km, tau) - mu_k * r
    rate = h * (s * fm - km * nt.poly(a, tau)) - mu_k * r_1
    curvature = -h * km * nt.poly_rate(a, tau) - mu_k * r_2
    return value, rate, curvature, value, rate, curvature


@njit(cache=True, inline="always")
def _inside(kind, value):
    """Stick holds at a margin of 0 (eq. 2.2); sliding needs s u̇ > 0."""
    return value >= 0.0 if kind == _STICK else value > 0.0


@njit(cache=True)
def _first_exit(kind, a, piece, p, bound2, bound3, noise, lo, hi):
    """First τ in [lo, hi] where the switching function is outside, 2 if none, -1 if the
    search stalled: the marching of ``spring_lane_law._first_exit`` (safe steps from
    bounds of g'' and g''', g taken as g + noise) on this law's functions."""
    tau = lo
    for _ in range(_MAX_STEPS):
        g1, r1, c1, g2, r2, c2 = _value(kind, a, piece, p, tau)
        if not _inside(kind, min(g1, g2) + noise):
            return tau
        step = min(
            safe_step(g1 + noise, r1, c1, bound2, bound3),
            safe_step(g2 + noise, r2, c2, bound2, bound3),
        )
        step = max(step, 0.5 * _TAU_TOLERANCE)
        tau += step
        if tau >= hi:
            if step > 0.5 * _TAU_TOLERANCE:
                return 2.0
            g1, _, _, g2, _, _ = _value(kind, a, piece, p, hi)
            return hi if not _inside(kind, min(g1, g2) + noise) else 2.0
    return -1.0


@njit(cache=True)
def lane_piece(a, piece, force, fm, km, mu_s, mu_k, x, v, f, mode):
    """(x, ẋ, f, mode, switches) of one lane at the end of a contact piece, through its
    switches; switches = -1 if the lane stalled (spring_lane_law.lane_piece's rules)."""
    h, mass, d0, d1, d2, d3 = (
        piece[M_H], piece[M_MASS], piece[M_D0], piece[M_D1], piece[M_D2], piece[M_D3],
    )  # fmt: skip
    tau = 0.0
    switches = 0
    for _ in range(MAX_SWITCHES_PER_STEP):
        if abs(mode) == FLIGHT:
            if tau == 0.0:  # landing at the piece start, k_t(0) ~ 0 at δ = 0
                k_0 = max(piece[M_K], 0.0)
                mode, f = touchdown(a, h, k_0, mass, piece[M_GRAVITY], mu_s, mu_k, v)
                switches += 1
                continue
            d = 1.0 - tau
            return x + h * v * d + 0.5 * h * h * fm * d * d, v + h * fm * d, 0.0, mode, switches
        if mode == 0.0:
            if v == 0.0 and f == 0.0 and force == 0.0:  # no release: spring_lane_law's rule
                return x, 0.0, 0.0, mode, switches
            x0, v0, e0 = virtual_start(piece, tau, x, v, f - force)
            p = (v0, e0, force, mu_s, 0.0, 0.0)
            lane_2 = abs(v0) * piece[M_E1_2] + abs(e0) * piece[M_E2_2]
            lane_3 = abs(v0) * piece[M_E1_3] + abs(e0) * piece[M_E2_3]
            amplitude = abs(v0) * piece[M_E1_0] + abs(e0) * piece[M_E2_0]
            noise = _ROUNDING * (mu_s * d0 + abs(force) + amplitude)
            tau_r = _first_exit(_STICK, a, piece, p, mu_s * d2 + lane_2, mu_s * d3 + lane_3,
                                noise, tau, 1.0)  # fmt: skip
            if tau_r < 0.0:
                break
            x, v, e = stick_state(piece, x0, v0, e0, min(tau_r, 1.0))
            f = force + e
            if tau_r > 1.0:
                return x, v, f, mode, switches
            tau = tau_r
            switches += 1
            normal = nt.poly(a, tau)
            if normal <= 0.0:
                mode, f = FLIGHT, 0.0
                continue
            s = sign(f)
            f = s * mu_k * normal
            p = (tau, v, s, fm, km, mu_k)
            mode = s if _inside(_SLIP, _value(_SLIP, a, piece, p, tau)[0]) else 0.0
            continue
        s = mode
        p = (tau, v, s, fm, km, mu_k)
        bound2 = km * h * d1 + mu_k * piece[M_R_2]
        bound3 = km * h * d2 + mu_k * piece[M_R_3]
        noise = _ROUNDING * (abs(v) + h * (abs(fm) + km * d0) + mu_k * piece[M_R_0])
        tau_s = _first_exit(_SLIP, a, piece, p, bound2, bound3, noise, tau, 1.0)
        if tau_s < 0.0:
            break
        end = min(tau_s, 1.0)
        x = slip_position(a, h, tau, x, v, s, fm, km, end)
        v = s * _slip_speed(a, h, tau, v, s, fm, km, end)
        normal = nt.poly(a, end)
        f = s * mu_k * normal
        if tau_s > 1.0:
            return x, v, f, mode, switches
        tau = tau_s
        switches += 1
        mode = 0.0
        if normal <= 0.0:
            mode, f = FLIGHT, 0.0
    return x, v, f, mode, -1
