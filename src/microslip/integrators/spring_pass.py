"""The spring lanes' branch-free passes over the normal tape
(:mod:`microslip.integrators.spring_lanes`; its GPU twin
:mod:`microslip.integrators.spring_lanes_cuda` calls the same :func:`free_piece` and
:func:`stuck_span`).

A contact piece: every lane advances as if the piece held no switch (the oscillator in
stick, the rigid law in slip), with the constants of the piece that every lane shares
(:func:`piece_constants`), and is flagged where its switching function may reach its
boundary inside: with |g''| <= M on [0, 1] (in τ), g >= min(g(0), g(1)) - M/8 (for the
stick margin min(μ_s P ∓ f) this is min(μ_s P - |f|) at the two ends, less M/8). A lane
whose bound does not prove the piece free of switches, or that lands on it, is redone
alone by :func:`~microslip.integrators.spring_lane_law.lane_piece`.

A span of contact pieces (SPAN_ROWS rows of the tape,
:func:`~microslip.integrators.normal_tape.span`): a stuck lane's oscillator does not
depend on N, so a lane that provably sticks throughout the span (its spring force
bounded by the oscillation's ends and amplitude, against the least N of the span) turns
once over the whole span (:func:`stuck_span`, :func:`span_pass`) instead of once a row.
On the bench's spring map ~64% of the lanes take each span so (2026-11-29). The law of a
stuck span takes any stick linear in (ẋ, e): the Mindlin lanes
(:mod:`~microslip.integrators.mindlin_spans`) give it their span's product of Φ's.

The loops are compiled without fastmath (no FMA contraction): a lane's bits depend only
on its own parameters and its set-up's tape.
"""

from __future__ import annotations

import math

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import normal_tape as nt
from microslip.integrators.spring_lane_law import (
    P_D1,
    P_D2,
    P_D3,
    P_H,
    P_KT,
    P_MASS,
    P_OMEGA,
    P_THETA,
    oscillation,
)

# Rows of the lane array of a group.
FORCE, FM, KM, MU_S, MU_K, X, V, FS, MODE, FLAG = range(10)  # FLAG last (gather_flagged)
LANE_ROWS = 10


@njit(cache=True, inline="always", error_model="numpy")
def piece_constants(a, piece, h_int, h2_kint):
    """The numbers of a contact piece that every lane shares (a tuple for
    :func:`free_piece`): the oscillator's sin and cos over the piece, the ends of P and
    P', the bounds' factors; ``h_int`` = h I(1), ``h2_kint`` = h² K(1)."""
    h, theta, omega, k_t = piece[P_H], piece[P_THETA], piece[P_OMEGA], piece[P_KT]
    mass, d1, d2, d3 = piece[P_MASS], piece[P_D1], piece[P_D2], piece[P_D3]
    sin_t, cos_minus_one = oscillation(theta)
    return (
        h, sin_t, cos_minus_one, sin_t / omega, sin_t / (mass * omega), cos_minus_one / k_t,
        k_t / omega, 1.0 / (k_t * h), a[0], nt.poly(a, 1.0), a[1], nt.poly_rate(a, 1.0),
        theta * theta / 8.0, d2 / 8.0, h * d1 / 8.0, d3 / 8.0, 0.5 * h * h, h_int, h2_kint,
    )  # fmt: skip


@njit(cache=True, inline="always", error_model="numpy")
def oscillator(xi, vi, fi, force, sin_t, cos_minus_one, sin_over_omega, sin_over_m_omega,
               cm1_over_kt, kt_over_omega):  # fmt: skip
    """(x1, ẋ1, f1, e0, b) of a stuck lane turned by θ on its spring (the module doc of
    :mod:`~microslip.integrators.spring_lane_law`): from x [m], ẋ [m/s], f [N] under the
    force F [N], given sin θ, cos θ - 1, sin θ/ω [s], sin θ/(m ω) [s/kg], (cos θ - 1)/k_t
    [m/N] and k_t/ω [N s/m]; e0 = f - F [N] and b = k_t ẋ/ω [N] are the oscillation's
    cosine and sine amplitudes."""
    e0 = fi - force
    b = kt_over_omega * vi
    x1 = xi + e0 * cm1_over_kt + vi * sin_over_omega
    v1 = vi * (1.0 + cos_minus_one) - e0 * sin_over_m_omega
    f1 = fi + e0 * cos_minus_one + b * sin_t
    return x1, v1, f1, e0, b


@njit(cache=True, inline="always", error_model="numpy")
def free_piece(k, s, xi, vi, fi, force, fm, km, mu_s, mu_k):
    """(flag, x1, ẋ1, f1) of a lane over a contact piece as if it held no switch (the
    oscillator in stick, the rigid law in slip), ``k`` from :func:`piece_constants`;
    ``flag`` where its switching function may reach its boundary inside (module doc) or
    it lands here: then :func:`~microslip.integrators.spring_lane_law.lane_piece` must
    redo it. Branch-free."""
    h, sin_t, cos_minus_one, sin_over_omega, sin_over_m_omega, cm1_over_kt = k[:6]
    kt_over_omega, inv_kt_h, p0, p1, rate0, rate1 = k[6:12]
    theta2_8, d2_8, h_d1_8, d3_8, h2_half, h_int, h2_kint = k[12:]
    # Stick: the oscillator.
    x_st, v_st, f_st, e0, b = oscillator(
        xi, vi, fi, force, sin_t, cos_minus_one, sin_over_omega, sin_over_m_omega,
        cm1_over_kt, kt_over_omega,
    )  # fmt: skip
    margin = min(mu_s * p0 - abs(fi), mu_s * p1 - abs(f_st))
    stick_low = margin - mu_s * d2_8 - theta2_8 * (abs(e0) + abs(b))
    # Slip: the rigid law; its stop function s u̇ at the ends.
    skm = s * km
    v_sl = vi + (h * fm - skm * h_int)
    x_sl = xi + (h * vi + h2_half * fm - skm * h2_kint)
    q = mu_k * inv_kt_h
    g_ends = min(s * vi - q * rate0, s * v_sl - q * rate1)
    slip_low = g_ends - km * h_d1_8 - q * d3_8
    stick = s == 0.0
    landing = s * s > 1.5  # flight (mode 2): the touchdown is applied alone
    flag = (stick & (stick_low <= 0.0)) | ((s != 0.0) & (slip_low <= 0.0)) | landing
    x1 = x_st if stick else x_sl
    v1 = v_st if stick else v_sl
    f1 = f_st if stick else s * mu_k * p1
    return flag, x1, v1, f1


@njit(cache=True, inline="always", error_model="numpy")
def span_constants(omega, k_t, mass, length):
    """The numbers of a span of contact pieces (:func:`~microslip.integrators.normal_tape.span`,
    ``length`` [s]) that every stuck lane shares, as :func:`stuck_span` takes them: the
    oscillator's turn by θ = ω·length (ω [rad/s], k_t [N/m], m [kg]) as a linear map of
    (ẋ, e), and its bound's factors. The spring's k_t is constant: the energy
    ½ m ẋ² + e²/(2 k_t) is too, and |f''| <= θ² sqrt(k_t) sqrt(m ẋ0² + e0²/k_t)."""
    theta = omega * length
    sin_t, cos_minus_one = oscillation(theta)
    cos_t = 1.0 + cos_minus_one
    return (
        cos_t, -sin_t / (mass * omega), k_t * sin_t / omega, cos_t, sin_t / omega,
        cos_minus_one / k_t, mass, 1.0 / k_t, theta * theta * math.sqrt(k_t) / 8.0,
    )  # fmt: skip


@njit(cache=True, inline="always", error_model="numpy")
def stuck_span(k, p_min, s, xi, vi, fi, force, mu_s):
    """(safe, x1 [m], ẋ1 [m/s], f1 [N]) of a lane over a span of contact pieces on which
    its stick is linear in (ẋ, e), e = f - F: (ẋ1, e1) = A (ẋ0, e0), x1 = x0 + B·(ẋ0, e0),
    with ``k`` = (A11, A12, A21, A22, B1, B2, m [kg], 1/k_lo [m/N], c [(N/m)^½]) from
    :func:`span_constants` (a spring) or
    :func:`~microslip.integrators.mindlin_pass.stick_span_constants` (Mindlin);
    ``p_min`` [N] the least N on the span. ``safe`` where the lane sticks (mode ``s`` =
    0) and provably stays stuck throughout: f deviates from its chord by at most
    c sqrt(w) on the span, w = m ẋ0² + e0²/k_lo [J] twice the energy's bound at its
    start (k_lo the least stiffness on it), so |f| <= max(|f0|, |f1|) + c sqrt(w), which
    must stay below μ_s p_min (docs/theory/numerics.md, "Lanes on a spring" and "Lanes
    on a Mindlin spring"). Branch-free."""
    a11, a12, a21, a22, b1, b2, mass, inv_k, c8 = k
    e0 = fi - force
    x1 = xi + (b1 * vi + b2 * e0)
    v1 = a11 * vi + a12 * e0
    f1 = force + (a21 * vi + a22 * e0)
    energy = mass * vi * vi + inv_k * e0 * e0
    low = mu_s * p_min - max(abs(fi), abs(f1)) - c8 * math.sqrt(energy)
    return (s == 0.0) & (p_min > 0.0) & (low > 0.0), x1, v1, f1


@njit(cache=True, inline="always")
def put_flagged(lanes, switches, flagged, sub, columns, counts, m):
    """Write the first ``m`` lanes of a compact copy (``sub``, their indices ``columns``,
    their switches and flagged pieces in ``counts``, from
    :func:`~microslip.integrators.rigid_pass.gather_flagged`) back into ``lanes``: their
    state, and their counts added to ``switches`` and ``flagged``."""
    for j in range(m):
        i = columns[j]
        lanes[X, i], lanes[V, i], lanes[FS, i] = sub[X, j], sub[V, j], sub[FS, j]
        lanes[MODE, i] = sub[MODE, j]
        switches[i] += counts[0, j]
        flagged[i] += counts[1, j]


@njit(cache=True, error_model="numpy")
def vector_pass(lanes, n, a, piece, h_int, h2_kint):
    """A contact piece for every lane as if it held no switch (:func:`free_piece`),
    vectorised; a flagged lane keeps its state. Returns the number flagged and the first
    of them (n if none): the lanes a piece switches are few and close together in force
    order, and the search for them starts there."""
    k = piece_constants(a, piece, h_int, h2_kint)
    n_flagged = 0
    first = n
    for i in range(n):
        xi, vi, fi = lanes[X, i], lanes[V, i], lanes[FS, i]
        flag, x1, v1, f1 = free_piece(
            k, lanes[MODE, i], xi, vi, fi, lanes[FORCE, i], lanes[FM, i], lanes[KM, i],
            lanes[MU_S, i], lanes[MU_K, i],
        )  # fmt: skip
        lanes[FLAG, i] = 1.0 if flag else 0.0
        lanes[X, i] = xi if flag else x1
        lanes[V, i] = vi if flag else v1
        lanes[FS, i] = fi if flag else f1
        n_flagged += 1 if flag else 0
        first = min(first, i if flag else n)
    return n_flagged, first


@njit(cache=True, error_model="numpy")
def span_pass(lanes, n, k, p_min):
    """A span of contact pieces for every lane that sticks throughout it
    (:func:`stuck_span`), vectorised; the others keep their state and are flagged.
    Returns the number flagged and the last of them (-1 if none)."""
    n_flagged = 0
    last = -1
    for i in range(n):
        xi, vi, fi = lanes[X, i], lanes[V, i], lanes[FS, i]
        safe, x1, v1, f1 = stuck_span(
            k, p_min, lanes[MODE, i], xi, vi, fi, lanes[FORCE, i], lanes[MU_S, i]
        )
        lanes[FLAG, i] = 0.0 if safe else 1.0
        lanes[X, i] = x1 if safe else xi
        lanes[V, i] = v1 if safe else vi
        lanes[FS, i] = f1 if safe else fi
        n_flagged += 0 if safe else 1
        last = max(last, -1 if safe else i)
    return n_flagged, last
