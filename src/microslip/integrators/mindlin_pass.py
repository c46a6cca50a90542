"""The Mindlin lanes' branch-free pass over a contact piece
(:mod:`microslip.integrators.mindlin_lanes`; its GPU twin
:mod:`microslip.integrators.mindlin_lanes_cuda` calls the same :func:`free_piece`).

Every lane advances as if the piece held no switch: Φ (the stick's fundamental matrix)
in stick, the rigid law in slip, with the constants of the piece that every lane shares
(:func:`piece_constants`), and is flagged where its switching function may reach its
boundary inside the piece or it lands there; the flagged lanes are redone by the lane
law (:func:`~microslip.integrators.mindlin_lane_law.lane_piece`).

A span of pieces: :func:`extend_stick` composes the stick's map over its rows (the
product of their Φ) and the bounds of their stiffness, and :func:`stick_span_constants`
turns them into the proof of
:func:`~microslip.integrators.spring_pass.stuck_span`
(:mod:`~microslip.integrators.mindlin_spans`; docs/theory/numerics.md, "Lanes on a
Mindlin spring").
"""

from __future__ import annotations

import math

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import mindlin_lane_law as law
from microslip.integrators import normal_tape as nt
from microslip.integrators.spring_pass import FLAG, FM, FORCE, FS, KM, MODE, MU_K, MU_S, V, X


@njit(cache=True, inline="always", error_model="numpy")
def piece_constants(a, piece, h_int, h2_kint):
    """The numbers of a contact piece that every lane shares (a tuple of floats for
    :func:`free_piece`: a tuple, not the array, keeps the lane loop free of reference
    counting, which LLVM cannot vectorise); ``h_int`` = h I(1), ``h2_kint`` = h² K(1)."""
    h = piece[law.M_H]
    r = piece[law.M_R : law.M_R + 5]
    return (
        h, piece[law.M_PHI11], piece[law.M_PHI12], piece[law.M_PHI21], piece[law.M_PHI22],
        piece[law.M_PSI1], piece[law.M_PSI2], a[0], nt.poly(a, 1.0),
        0.125 * piece[law.M_D2], 0.125 * piece[law.M_E1_2], 0.125 * piece[law.M_E2_2],
        r[0], r[0] + r[1] + r[2] + r[3] + r[4],
        0.125 * (h * piece[law.M_D1]), 0.125 * piece[law.M_R_2], 0.5 * h * h, h_int, h2_kint,
    )  # fmt: skip


@njit(cache=True, inline="always", error_model="numpy")
def free_piece(k, s, xi, vi, fi, force, fm, km, mu_s, mu_k):
    """(flag, x1, ẋ1, f1) of a lane over a contact piece as if it held no switch (Φ in
    stick, the rigid law in slip), ``k`` from :func:`piece_constants`; ``flag`` where its
    switching function may reach its boundary inside (g >= min(g(0), g(1)) - max|g''|/8)
    or it lands here. Branch-free."""
    h, phi11, phi12, phi21, phi22, psi1, psi2, p0, p1 = k[:9]
    d2_8, e1_8, e2_8, r0, r1, h_d1_8, r2_8, h2_half, h_int, h2_kint = k[9:]
    # Stick: (ẋ, e) through Φ(1), x through ∫ẋ.
    e0 = fi - force
    x_st = xi + psi1 * vi + psi2 * e0
    v_st = phi11 * vi + phi12 * e0
    f_st = force + phi21 * vi + phi22 * e0
    margin = min(mu_s * p0 - abs(fi), mu_s * p1 - abs(f_st))
    stick_low = margin - (mu_s * d2_8 + abs(vi) * e1_8 + abs(e0) * e2_8)
    # Slip: the rigid law; its stop function s u̇ = s ẋ - μ_k R at the ends.
    skm = s * km
    v_sl = vi + (h * fm - skm * h_int)
    x_sl = xi + (h * vi + h2_half * fm - skm * h2_kint)
    g_ends = min(s * vi - mu_k * r0, s * v_sl - mu_k * r1)
    slip_low = g_ends - (km * h_d1_8 + mu_k * r2_8)
    stick = s == 0.0
    landing = s * s > 1.5
    flag = (stick & (stick_low <= 0.0)) | ((s != 0.0) & (slip_low <= 0.0)) | landing
    x1 = x_st if stick else x_sl
    v1 = v_st if stick else v_sl
    f1 = f_st if stick else s * mu_k * p1
    return flag, x1, v1, f1


@njit(cache=True, error_model="numpy")
def vector_pass(lanes, n, a, piece, h_int, h2_kint):
    """A contact piece for every lane as if it held no switch (:func:`free_piece`); a
    flagged lane keeps its state. Returns the number flagged and the first of them (n
    if none): the lanes a piece switches are few and close together in force order, and
    the search for them starts there."""
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


# A span's stick before its first row (:func:`extend_stick`): length [s], the map A = I,
# B = 0, the greatest and least stiffness k_hi, k_lo [N/m], the largest rate |dk/dt|
# [N/(m s)], the variation of k [N/m] and the jumps of k between rows [N/m]; the
# stiffness at the end of the last row [N/m] (NaN: no row yet).
EMPTY_STICK = (0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, math.inf, 0.0, 0.0, 0.0, math.nan)


@njit(cache=True, inline="always", error_model="numpy")
def extend_stick(stick, h, phi11, phi12, phi21, phi22, psi1, psi2, k0, k1, k2, k3, k4):
    """``stick`` (:data:`EMPTY_STICK`, then this) followed by a contact piece of length h
    [s], the stick's Φ(1) and ∫ẋ(1) on it and its stiffness quartic k(τ) = Σ k_j τ^j
    [N/m] (the slots of :func:`~microslip.integrators.mindlin_piece.set_piece`): the
    stick's map over both, (ẋ, e) -> Φ A (ẋ, e), x gaining Ψ·A (ẋ, e), and the bounds
    of k on it (k's coefficients' moduli bound it on [0, 1]). Takes the row's values,
    not the table: the CUDA lanes call it on their own reads."""
    length, a11, a12, a21, a22, b1, b2, k_hi, k_lo, rate, variation, jumps, k_end = stick
    slope = abs(k1) + 2.0 * abs(k2) + 3.0 * abs(k3) + 4.0 * abs(k4)  # >= |dk/dτ| on [0, 1]
    rest = abs(k1) + abs(k2) + abs(k3) + abs(k4)
    jump = abs(k0 - k_end) if k_end == k_end else 0.0
    return (
        length + h,
        phi11 * a11 + phi12 * a21, phi11 * a12 + phi12 * a22,
        phi21 * a11 + phi22 * a21, phi21 * a12 + phi22 * a22,
        b1 + (psi1 * a11 + psi2 * a21), b2 + (psi1 * a12 + psi2 * a22),
        max(k_hi, abs(k0) + rest), min(k_lo, k0 - rest), max(rate, slope / h),
        variation + slope, jumps + jump, k0 + k1 + k2 + k3 + k4,
    )  # fmt: skip


@njit(cache=True, inline="always", error_model="numpy")
def stick_span_constants(stick, mass):
    """The numbers of a span that every stuck lane shares, as
    :func:`~microslip.integrators.spring_pass.stuck_span` takes them, from its
    :func:`extend_stick` (m [kg]). With k_lo > 0 the energy E = ½ m ẋ² + e²/(2k) of a
    stuck lane changes at a rate |dE/dt| = |k̇| e²/(2k²) <= |k̇|/k_lo E, and a jump of k
    between rows scales it by at most 1 + |Δk|/k_lo: E <= G E0, G = exp((∫|k̇| dt + Σ|Δk|)
    / k_lo), so |ẋ| <= sqrt(G/m) sqrt(2 E0) and |e| <= sqrt(k_hi G) sqrt(2 E0). On the
    span (τ ∈ [0, 1], t = t0 + Lτ) f'' = L² (k̇ ẋ - k e/m), and f' jumps by L Δk ẋ
    between rows: f strays from its chord by at most L² max|f''|/8 + L Σ|Δk| |ẋ|/4. A
    span with k_lo <= 0 gets an infinite bound (no lane takes it)."""
    length, a11, a12, a21, a22, b1, b2, k_hi, k_lo, rate, variation, jumps, _ = stick
    if not k_lo > 0.0:
        return a11, a12, a21, a22, b1, b2, mass, 0.0, math.inf
    growth = math.exp((variation + jumps) / k_lo)
    v_scale = math.sqrt(growth / mass)
    e_scale = math.sqrt(k_hi * growth)
    c = length * length * (rate * v_scale + k_hi * e_scale / mass) / 8.0
    c += length * jumps * v_scale / 4.0
    return a11, a12, a21, a22, b1, b2, mass, 1.0 / k_lo, c
