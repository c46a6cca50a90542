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
(:func:`~microslip.integrators.mindlin_piece.hermite_state`; O(h⁵), and no node at an
end, where δ = 0 makes k_t = 0 and Ṅ/k_t 0/0 at a contact switch).

Stick is then linear with polynomial coefficients. With e = f - F, the state (ẋ, e)
obeys dẋ/dτ = -(h/m) e, de/dτ = h k(τ) ẋ, whose fundamental matrix Φ(τ) (Φ(0) = I) is a
power series in τ, computed once per piece for all the lanes of a set-up
(:mod:`microslip.integrators.mindlin_piece`, the per-piece vector) by the recurrence of
its coefficients (exact for the quartic k; truncated where its terms fall below 1e-17 of
the state's scale: ~θ^n/n!, θ = h sqrt(max k/m)); x follows from ∫ẋ. A lane stuck from
τ_a with (ẋ_a, e_a) has (ẋ, e)(τ) = Φ(τ) Φ(τ_a)⁻¹ (ẋ_a, e_a) (det Φ = 1: the system
has no trace). So every switching function of a lane is a polynomial in τ on the piece,
and its first exit is found by the safe marching steps of the constant-stiffness law
(bounds of its second and third derivatives from the sums of its coefficients' moduli).
"""

from __future__ import annotations

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip._refcount import NO_REFCOUNT
from microslip.integrators import normal_tape as nt
from microslip.integrators.kernel import MAX_SWITCHES_PER_STEP

# The per-piece vector (its slots, set_setup, set_piece) is mindlin_piece's; all its names
# are re-exported here (callers read law.PIECE, law.M_H, law.set_piece, ...).
from microslip.integrators.mindlin_piece import (  # noqa: F401  (re-exported)
    _FIT,
    _N,
    _NODES,
    _SERIES,
    _SERIES_TOLERANCE,
    DEGREE,
    M_D0,
    M_D1,
    M_D2,
    M_D3,
    M_DEG,
    M_E1,
    M_E1_0,
    M_E1_2,
    M_E1_3,
    M_E2,
    M_E2_0,
    M_E2_2,
    M_E2_3,
    M_GRAVITY,
    M_H,
    M_K,
    M_MASS,
    M_NODES,
    M_PHI11,
    M_PHI12,
    M_PHI21,
    M_PHI22,
    M_PSI1,
    M_PSI2,
    M_R,
    M_R_0,
    M_R_2,
    M_R_3,
    M_RATIO,
    M_V1,
    M_V2,
    M_X1,
    M_X2,
    MAX_THETA,
    PIECE,
    TOO_COARSE,
    _fundamental_series,
    hermite_state,
    set_piece,
    set_setup,
)
from microslip.integrators.rigid_lane_law import slip_position
from microslip.integrators.rigid_lane_law import slip_speed as _slip_speed
from microslip.integrators.spring_lane_law import (
    FLIGHT,
    rate2,
    safe_step,
    touchdown,
)
from microslip.model.system import sign

_TAU_TOLERANCE = 1e-12  # of a piece, as in spring_lane_law
_MAX_STEPS = 2000
_ROUNDING = 1e-15
_STICK, _SLIP = 0, 1


@njit(cache=True, inline="always")
def _series(piece, start, degree, tau):
    """(value, d/dτ, d²/dτ²) of the series Σ c_n τⁿ (n <= degree) at ``start`` in
    ``piece``: its even and odd parts, E(u) + τ O(u) in u = τ², each by Horner's rule
    in u. The two chains are independent and half as long as Horner's in τ, whose
    latency every step of a stick search waited on."""
    u = tau * tau
    m = degree // 2
    # Both parts have m + 1 coefficients: O's top one is 0 when the degree is even.
    ev, er, ec = piece[start + 2 * m], 0.0, 0.0
    ov = piece[start + 2 * m + 1] if degree % 2 == 1 else 0.0
    orate, oc = 0.0, 0.0
    for j in range(m - 1, -1, -1):
        ec = ec * u + 2.0 * er
        er = er * u + ev
        ev = ev * u + piece[start + 2 * j]
        oc = oc * u + 2.0 * orate
        orate = orate * u + ov
        ov = ov * u + piece[start + 2 * j + 1]
    # P = E + τ O, P' = 2τ E' + O + 2u O', P'' = 2E' + 4u E'' + 6τ O' + 4τu O''.
    value = ev + tau * ov
    rate = 2.0 * tau * er + ov + 2.0 * u * orate
    curvature = (2.0 * er + 4.0 * u * ec) + tau * (6.0 * orate + 4.0 * u * oc)
    return value, rate, curvature


@njit(cache=True, inline="always")
def _quartic(piece, start, tau):
    """(value, d/dτ, d²/dτ²) of the quartic at ``start`` in ``piece``."""
    return _series(piece, start, 4, tau)


@njit(cache=True, inline="always")
def _stick_series(piece, degree, tau):
    """(v_1, v_2, e_1, e_2, x_1, x_2) at τ: the values of the six series of the stick
    solution stored in ``piece`` (Φ's entries and ∫ẋ's), by :func:`_series`'s arithmetic
    for a value (the same bits), in one loop. :func:`stick_state` and
    :func:`virtual_start` need all six; each site of an inlined function is compiled
    again (docs/design.md, "Compile time"), and six sites of :func:`_series` each were
    most of their compile."""
    u = tau * tau
    m = degree // 2
    top = 2 * m
    odd = degree % 2 == 1
    ev1, ev2, ee1 = piece[M_V1 + top], piece[M_V2 + top], piece[M_E1 + top]
    ee2, ex1, ex2 = piece[M_E2 + top], piece[M_X1 + top], piece[M_X2 + top]
    ov1 = piece[M_V1 + top + 1] if odd else 0.0
    ov2 = piece[M_V2 + top + 1] if odd else 0.0
    oe1 = piece[M_E1 + top + 1] if odd else 0.0
    oe2 = piece[M_E2 + top + 1] if odd else 0.0
    ox1 = piece[M_X1 + top + 1] if odd else 0.0
    ox2 = piece[M_X2 + top + 1] if odd else 0.0
    for j in range(m - 1, -1, -1):
        k = 2 * j
        ev1, ov1 = ev1 * u + piece[M_V1 + k], ov1 * u + piece[M_V1 + k + 1]
        ev2, ov2 = ev2 * u + piece[M_V2 + k], ov2 * u + piece[M_V2 + k + 1]
        ee1, oe1 = ee1 * u + piece[M_E1 + k], oe1 * u + piece[M_E1 + k + 1]
        ee2, oe2 = ee2 * u + piece[M_E2 + k], oe2 * u + piece[M_E2 + k + 1]
        ex1, ox1 = ex1 * u + piece[M_X1 + k], ox1 * u + piece[M_X1 + k + 1]
        ex2, ox2 = ex2 * u + piece[M_X2 + k], ox2 * u + piece[M_X2 + k + 1]
    return (
        ev1 + tau * ov1, ev2 + tau * ov2, ee1 + tau * oe1, ee2 + tau * oe2,
        ex1 + tau * ox1, ex2 + tau * ox2,
    )  # fmt: skip


@njit(cache=True, inline="always")
def stick_state(piece, x0, v0, e0, tau):
    """(x [m], ẋ [m/s], e [N]) at τ of a lane stuck with virtual initial state
    (x0, ẋ0, e0) at τ = 0 (:func:`virtual_start`)."""
    v_1, v_2, e_1, e_2, x_1, x_2 = _stick_series(piece, int(piece[M_DEG]), tau)
    return x0 + x_1 * v0 + x_2 * e0, v_1 * v0 + v_2 * e0, e_1 * v0 + e_2 * e0


@njit(cache=True, inline="always")
def virtual_start(piece, tau_a, x_a, v_a, e_a):
    """(x0, ẋ0, e0) at τ = 0 of the stick through (x_a, ẋ_a, e_a) at τ_a: Φ(τ_a)⁻¹."""
    if tau_a == 0.0:
        return x_a, v_a, e_a
    v_1, v_2, e_1, e_2, x_1, x_2 = _stick_series(piece, int(piece[M_DEG]), tau_a)
    det = v_1 * e_2 - v_2 * e_1
    v0 = (e_2 * v_a - v_2 * e_a) / det
    e0 = (v_1 * e_a - e_1 * v_a) / det
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


@njit(cache=True, **NO_REFCOUNT)
def _first_exit(kind, a, piece, p, bound2, bound3, noise, lo, hi):
    """First τ in [lo, hi] where the switching function is outside, 2 if none, -1 if the
    search stalled: the marching of ``spring_lane_law._first_exit`` (safe steps from
    bounds of g'' and g''', g taken as g + noise) on this law's functions."""
    tau = lo
    for _ in range(_MAX_STEPS):
        g1, r1, c1, g2, r2, c2 = _value(kind, a, piece, p, tau)
        if not _inside(kind, min(g1, g2) + noise):
            return tau
        if tau >= hi:  # the end, inside
            return 2.0
        step = min(
            safe_step(g1 + noise, r1, c1, bound2, bound3),
            safe_step(g2 + noise, r2, c2, bound2, bound3),
        )
        if tau + step >= hi:
            return 2.0
        # Half a tolerance past the safe distance: a crossing there is still located
        # to within it, and the next evaluation falls outside rather than on the root
        # of g + noise, where its rounding leaves it inside about half the time.
        tau += step + 0.5 * _TAU_TOLERANCE
        if tau >= hi:
            # Past the end by less than half a tolerance: the end decides, at the one
            # evaluation of g above (inlined, as every site of it: docs/design.md).
            tau = hi
    return -1.0


@njit(cache=True, **NO_REFCOUNT)
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
            if tau == 0.0:  # landing at the piece start: R(0) = Ṅ/k_t there
                mode, f = touchdown(a, piece[M_R], mass, piece[M_GRAVITY], mu_s, mu_k, v)
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
