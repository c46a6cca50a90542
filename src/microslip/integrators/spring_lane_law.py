"""One compliant tangential lane on a piece of the normal tape: a contact point on a
spring of constant stiffness (``TangentialSpring``) under a constant force.

The body at x and its massless contact point are joined by the spring k_t [N/m], with
the spring force f [N] (docs/theory/friction_reduction.md,
:mod:`microslip.model.tangential`); the normal force is the piece's quartic P(τ),
τ = (t - t0)/h (:mod:`microslip.integrators.normal_tape`):

    stick (mode 0)   u̇ = 0: m ẍ = F - f, ḟ = k_t ẋ; holds while |f| <= μ_s N,
    slip in s = ±1   f = s μ_k N: m ẍ = F - s μ_k N (the rigid law, eq. 2.5), while
                     s u̇ = s ẋ - μ_k Ṅ / k_t > 0,
    flight (mode 2)  f = 0 (a relaxed spring that follows the body): m ẍ = F.

Each has a closed form over a piece. Stick is the harmonic oscillator of e = f - F,
ω = sqrt(k_t/m), with d = ω (t - t_a):

    f = f_a + e_a (cos d - 1) + (k_t ẋ_a/ω) sin d,   ẋ = ẋ_a cos d - e_a/(m ω) sin d,
    x = x_a + (e_a/k_t)(cos d - 1) + (ẋ_a/ω) sin d;

slip is the rigid formula on the tape's integrals (:func:`rigid_lane_law.slip_speed`);
flight is uniform acceleration. The switches are those of :mod:`microslip.model.switches`:
a release at |f| = μ_s N (the spring force drops to μ_k N; the point slides unless
s u̇ <= 0 there), a stop at s u̇ = 0 (stick with f = s μ_k N), a loss of contact (the
tape's piece ends; f = 0) and a touchdown with a relaxed spring (stick, unless it
grazes, N = 0+, and the spring loads faster than the limit rises: then slip on the
limit, the rule of ``switches._touchdown_mode``).

Each switching instant is the first exit of a function g (the stick margin's two smooth
branches μ_s P ∓ f, or s u̇) from its inside, found by marching from the piece's start
in safe steps: with |g''| <= M on the piece (from bounds of the quartic's derivatives
and the oscillator's amplitude), g cannot reach 0 sooner than the root of
g + g' s - M s²/2, so no crossing is skipped; near a simple root the steps are Newton's
from the inside, and where g'' > 0 a bound of g''' clears 1.5 g''/M3 at once (the
double zero of the stick margin after every stop). The instant is located to within
~1e-12 of the piece, which keeps the 4th order of the normal RK4 integration
(tests/validation/test_compliant_lanes_order.py).
"""

from __future__ import annotations

import math

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip._refcount import NO_REFCOUNT
from microslip.integrators import normal_tape as nt
from microslip.integrators.kernel import MAX_SWITCHES_PER_STEP
from microslip.integrators.rigid_lane_law import slip_position
from microslip.integrators.rigid_lane_law import slip_speed as _slip_speed
from microslip.model.switches import GRAZING
from microslip.model.system import sign

FLIGHT = 2.0  # the mode of a lane out of contact (system.FLIGHT: a relaxed spring)
_TAU_TOLERANCE = 1e-12  # of a piece, as in rigid_lane_law
_STICK, _SLIP = 0, 1  # the switching function sought: the stick margin or s u̇
_MAX_STEPS = 2000  # of one search: a simple root takes ~5
_ROUNDING = 1e-15  # relative rounding of a switching function (a few ulps of its terms)


# Below this |d| [rad] the oscillator's sin d and cos d - 1 come from their Taylor series
# (:func:`oscillation`); a piece of the default step has θ = ω h ~ 0.03 on the paper's
# contact (k_t = K_n). The series' remainder at the bound is < 3e-21 of sin d and < 4e-22
# of cos d - 1, far below an ulp.
SERIES_BOUND = 0.125
# Taylor coefficients: sin d = d (1 + S3 d² + ... + S11 d¹⁰), cos d - 1 = C2 d² + ... + C12 d¹².
_S3, _S5, _S7, _S9, _S11 = -1 / 6, 1 / 120, -1 / 5040, 1 / 362880, -1 / 39916800
_C2, _C4, _C6, _C8, _C10, _C12 = -1 / 2, 1 / 24, -1 / 720, 1 / 40320, -1 / 3628800, 1 / 479001600


@njit(cache=True, inline="always")
def oscillation(d):
    """(sin d, cos d - 1) of an angle d [rad], the latter without cancellation. A stick
    search evaluates them at every step: libm's sin and cos took a sixth of a spring
    map's time, the series a few multiply-adds (within a few ulps of libm)."""
    if abs(d) <= SERIES_BOUND:
        # In d² = u, by Estrin's scheme: a search evaluates this at every step, one
        # step on the last one's result, and Estrin's chain of dependent operations is
        # half Horner's.
        u = d * d
        u2 = u * u
        u4 = u2 * u2
        sine = d * (((1.0 + _S3 * u) + u2 * (_S5 + _S7 * u)) + u4 * (_S9 + _S11 * u))
        cos_minus_one = u * (((_C2 + _C4 * u) + u2 * (_C6 + _C8 * u)) + u4 * (_C10 + _C12 * u))
        return sine, cos_minus_one
    half = math.sin(0.5 * d)
    return math.sin(d), -2.0 * half * half


@njit(cache=True, inline="always")
def rate2(a, tau):
    """d²P/dτ² [N]."""
    return 2.0 * a[2] + tau * (6.0 * a[3] + tau * 12.0 * a[4])


@njit(cache=True, inline="always")
def derivative_bounds(a):
    """Bounds of |P|, |P'|, |P''|, |P'''| on [0, 1] [N] (sums of the coefficients'
    moduli)."""
    a0, a1, a2, a3, a4 = abs(a[0]), abs(a[1]), abs(a[2]), abs(a[3]), abs(a[4])
    return (
        a0 + a1 + a2 + a3 + a4,
        a1 + 2.0 * a2 + 3.0 * a3 + 4.0 * a4,
        2.0 * a2 + 6.0 * a3 + 12.0 * a4,
        6.0 * a3 + 24.0 * a4,
    )


@njit(cache=True, inline="always")
def _value(kind, a, p, tau):
    """(g1, g1', g1'', g2, g2', g2'') at τ, derivatives in τ: the switching function
    sought is min(g1, g2), each smooth on the piece, from the state at p[0] = τ_a.

    Stick, p = (τ_a, θ = ω h, e_a, k_t ẋ_a/ω, f_a, μ_s): g1,2 = μ_s P ∓ f [N], whose
    minimum μ_s P - |f| is >= 0 while stick holds (its kink where f = 0 is why the two
    are marched apart). f = f_a + e_a (cos d - 1) + (k_t ẋ_a/ω) sin d is f_a exactly at
    τ_a, so a stick that starts on the limit starts inside. Slip, p = (τ_a, h, ẋ_a, s,
    F/m, μ_k/m, μ_k/(k_t h)): g1 = g2 = s u̇ [m/s], > 0 while sliding.
    """
    tau_a = p[0]
    if kind == _STICK:
        theta, e_a, b_a, f_a, mu_s = p[1], p[2], p[3], p[4], p[5]
        sd, cos_minus_one = oscillation(theta * (tau - tau_a))
        cd = 1.0 + cos_minus_one
        spring = f_a + e_a * cos_minus_one + b_a * sd
        spring_1 = theta * (b_a * cd - e_a * sd)
        spring_2 = -theta * theta * (e_a * cd + b_a * sd)
        limit = mu_s * nt.poly(a, tau)
        limit_1 = mu_s * nt.poly_rate(a, tau)
        limit_2 = mu_s * rate2(a, tau)
        return (
            limit - spring, limit_1 - spring_1, limit_2 - spring_2,
            limit + spring, limit_1 + spring_1, limit_2 + spring_2,
        )  # fmt: skip
    h, v_a, s, fm, km, q = p[1], p[2], p[3], p[4], p[5], p[6]
    value = _slip_speed(a, h, tau_a, v_a, s, fm, km, tau) - q * nt.poly_rate(a, tau)
    rate = h * (s * fm - km * nt.poly(a, tau)) - q * rate2(a, tau)
    curvature = -h * km * nt.poly_rate(a, tau) - q * (6.0 * a[3] + 24.0 * a[4] * tau)
    return value, rate, curvature, value, rate, curvature


@njit(cache=True, inline="always")
def _inside(kind, value):
    """Stick holds at a margin of 0 (eq. 2.2); sliding needs s u̇ > 0."""
    return value >= 0.0 if kind == _STICK else value > 0.0


@njit(cache=True, inline="always")
def safe_step(g, r, c, bound2, bound3):
    """A distance s > 0 within which a function of value g > 0 (or g = 0 rising), slope
    r and curvature c has no root, given |g''| <= bound2 and |g'''| <= bound3 on the
    piece: the larger of two proofs.

    First order: g + r s' - bound2 s'²/2 > 0 on [0, s) (near a simple root, a Newton
    step from the inside). Second order, where c > 0 and g is not falling faster than
    r² <= c g: g + r s' + c s'²/2 - bound3 s'³/6 > 0 on [0, 1.5 c/bound3] (its minimum
    there is >= g - 3r²/(4c) > 0). The second clears at once a stick that starts on its
    limit with the margin rising from a double zero (every stop: f = μ_k N, and the
    margin's rate -k_t s u̇ is 0 there), which the first would creep out of
    geometrically."""
    if bound2 <= 0.0:
        first = g / -r if r < 0.0 else math.inf
    elif r < 0.0 and bound2 * g < 0.05 * r * r:
        # Falling, near a root: 2g / (|r| + sqrt(r² + 2 bound2 g)) with the square root
        # replaced by its upper bound |r| + bound2 g/|r| (a step at most ~1e-3 shorter,
        # still safe), which saves its latency at every converging step.
        first = -2.0 * g * r / (2.0 * r * r + bound2 * g)
    else:
        root = math.sqrt(r * r + 2.0 * bound2 * g)
        # The same root, without cancellation when r < 0.
        first = 2.0 * g / (root - r) if r < 0.0 else (r + root) / bound2
    if c > 0.0 and bound3 > 0.0 and (r >= 0.0 or r * r <= c * g):
        return max(first, 1.5 * c / bound3)
    return first


@njit(cache=True)
def _first_exit(kind, a, p, bound2, bound3, noise, lo, hi):
    """First τ in [lo, hi] where the switching function is outside (the returned τ is,
    just past the crossing), 2 if none, -1 if the search stalled. ``bound2``,
    ``bound3`` >= |d²g/dτ²|, |d³g/dτ³| on the piece; ``noise`` [units of g] the
    rounding of g.

    It marches by safe steps (:func:`safe_step`), so no crossing is skipped: near a
    simple root the steps are Newton's from the inside (quadratic). Both the test and
    the steps take g as g + noise: a dip below zero no deeper than the rounding is not a
    crossing, and a tangency within the rounding (a stick whose force returns exactly to
    the limit, as at constant N) is passed, not taken for a release (some constant-N
    lanes of the bench map need 40-150 steps there). A crossing is found once g is
    below -noise. Each step goes half a tolerance past its safe distance, so the
    evaluation after a converged Newton step falls outside rather than on the root of
    g + noise: a crossing in that half tolerance is still located to within the
    tolerance, and only a dip narrower than it may pass. A search that starts on its
    boundary (a stick at f = μ_k N = μ_s N after a stop) then starts inside however its
    terms were rounded: with multiply-adds fused (a GPU) the margin μ_s P - μ_k P there
    is a rounding error of either sign, not 0."""
    tau = lo
    for _ in range(_MAX_STEPS):
        g1, r1, c1, g2, r2, c2 = _value(kind, a, p, tau)
        if not _inside(kind, min(g1, g2) + noise):
            return tau
        if tau >= hi:  # the end, inside
            return 2.0
        step = min(
            safe_step(g1 + noise, r1, c1, bound2, bound3),
            safe_step(g2 + noise, r2, c2, bound2, bound3),
        )
        if tau + step >= hi:
            return 2.0  # [τ, hi] was safe
        # Half a tolerance past the safe distance: a crossing there is still located
        # to within it, and the next evaluation falls outside rather than on the root
        # of g + noise, where its rounding leaves it inside about half the time.
        tau += step + 0.5 * _TAU_TOLERANCE
        if tau >= hi:
            # Past the end by less than half a tolerance: the end decides, at the one
            # evaluation of g above (inlined, as every site of it: docs/design.md).
            tau = hi
    return -1.0


@njit(cache=True, inline="always")
def _stick_at(tau_a, x, v, f, force, omega, k_t, mass, theta, tau):
    """(x [m], ẋ [m/s], f [N]) at τ of a lane stuck since τ_a (module doc)."""
    sd, cos_minus_one = oscillation(theta * (tau - tau_a))
    e_a = f - force
    return (
        x + (e_a / k_t) * cos_minus_one + (v / omega) * sd,
        v * (1.0 + cos_minus_one) - (e_a / (mass * omega)) * sd,
        f + e_a * cos_minus_one + (k_t * v / omega) * sd,
    )


@njit(cache=True, inline="always")
def touchdown(a, rate_ratio, mass, gravity, mu_s, mu_k, v):
    """(mode, f [N]) of a lane landing with a relaxed spring at the start of the piece:
    stick, unless the touchdown grazes (μ_s N <= GRAZING m g) with ẋ != 0 and the spring
    loads faster than the limit rises, μ_s dN/dt < k_t |ẋ|, i.e. μ_s R < |ẋ| with
    ``rate_ratio`` R = (dN/dt)/k_t [m/s] at the touchdown: slip with ẋ on f = μ_k N.
    The ratio, not the rates: on a Mindlin spring both vanish at δ = 0 for m2 > 1, and
    R = δ̇/λ (elastic law) decides (docs/theory/friction_reduction.md)."""
    limit = mu_s * a[0]
    if limit > GRAZING * mass * gravity or v == 0.0:
        return 0.0, 0.0
    if mu_s * rate_ratio >= abs(v):
        return 0.0, 0.0
    direction = sign(v)
    return direction, direction * mu_k * a[0]


# Columns of the per-piece constants (one row of the tape, the group's spring).
(P_H, P_THETA, P_OMEGA, P_KT, P_MASS, P_GRAVITY, P_D0, P_D1, P_D2, P_D3) = range(10)
PIECE = 10


@njit(cache=True, inline="always")
def set_spring(piece, omega, k_t, mass, gravity):
    """Write a set-up's columns of ``piece``: ω = sqrt(k_t/m) [rad/s], k_t [N/m], m [kg],
    g [m/s^2]."""
    piece[P_OMEGA], piece[P_KT], piece[P_MASS], piece[P_GRAVITY] = omega, k_t, mass, gravity


@njit(cache=True, inline="always")
def set_piece(piece, a, h):
    """Write a tape piece's columns of ``piece`` (its set-up's written already): h [s],
    θ = ω h, and the bounds of the quartic ``a``'s derivatives (:func:`derivative_bounds`)."""
    piece[P_H], piece[P_THETA] = h, piece[P_OMEGA] * h
    piece[P_D0], piece[P_D1], piece[P_D2], piece[P_D3] = derivative_bounds(a)


@njit(cache=True, **NO_REFCOUNT)
def lane_piece(a, piece, force, fm, km, mu_s, mu_k, x, v, f, mode):
    """(x, ẋ, f, mode, switches) of one lane at the end of a contact piece, through its
    switches; switches = -1 if the lane stalled."""
    h, theta, omega, k_t = piece[P_H], piece[P_THETA], piece[P_OMEGA], piece[P_KT]
    mass, d1, d2, d3 = piece[P_MASS], piece[P_D1], piece[P_D2], piece[P_D3]
    d0 = piece[P_D0]
    q = mu_k / (k_t * h)
    tau = 0.0
    switches = 0
    for _ in range(MAX_SWITCHES_PER_STEP):
        if abs(mode) == FLIGHT:
            if tau == 0.0:  # landing at the piece start
                mode, f = touchdown(a, a[1] / (h * k_t), mass, piece[P_GRAVITY], mu_s, mu_k, v)
                switches += 1
                continue
            # Lifted off inside the piece (N reached 0 at a switch): fly to its end.
            d = 1.0 - tau
            return x + h * v * d + 0.5 * h * h * fm * d * d, v + h * fm * d, 0.0, mode, switches
        if mode == 0.0:
            if v == 0.0 and f == 0.0 and force == 0.0:
                # At rest on a relaxed spring with F = 0: f stays 0 <= μ_s N, so no
                # release (the search would creep to the double zero of μ_s P at a
                # lift-off ending the piece).
                return x, 0.0, 0.0, mode, switches
            e_a = f - force
            b_a = k_t * v / omega
            p = (tau, theta, e_a, b_a, f, mu_s, 0.0)  # padded: one tuple type for both kinds
            amplitude = abs(e_a) + abs(b_a)  # of the oscillation of f
            bound2 = mu_s * d2 + theta * theta * amplitude
            bound3 = mu_s * d3 + theta * theta * theta * amplitude
            noise = _ROUNDING * (mu_s * d0 + abs(f) + amplitude)
            tau_r = _first_exit(_STICK, a, p, bound2, bound3, noise, tau, 1.0)
            if tau_r < 0.0:
                break
            x, v, f = _stick_at(tau, x, v, f, force, omega, k_t, mass, theta, min(tau_r, 1.0))
            if tau_r > 1.0:
                return x, v, f, mode, switches
            tau = tau_r
            switches += 1
            normal = nt.poly(a, tau)
            if normal <= 0.0:
                mode, f = FLIGHT, 0.0
                continue
            # Slip starts towards f, which drops to the kinetic limit; the point slides
            # unless s u̇ <= 0 there (the same function as the stop search's).
            s = sign(f)
            f = s * mu_k * normal
            p = (tau, h, v, s, fm, km, q)
            mode = s if _inside(_SLIP, _value(_SLIP, a, p, tau)[0]) else 0.0
            continue
        s = mode
        p = (tau, h, v, s, fm, km, q)
        bound2 = km * h * d1 + q * d3
        bound3 = km * h * d2 + q * 24.0 * abs(a[4])
        noise = _ROUNDING * (abs(v) + h * (abs(fm) + km * d0) + q * d1)
        tau_s = _first_exit(_SLIP, a, p, bound2, bound3, noise, tau, 1.0)
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
        mode = 0.0  # the point comes to rest on the limit f = s μ_k N: it sticks
        if normal <= 0.0:
            mode, f = FLIGHT, 0.0
    return x, v, f, mode, -1
