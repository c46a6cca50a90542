"""The pieces of one period of a known normal force N(t), on which it is smooth: the
shared normal side of the exact steady state of a compliant contact point
(:mod:`microslip.analysis.contact_point`, docs/theory/friction_reduction.md).

:func:`build_pieces` cuts the period at the nodes of the normal orbit's table (or a
uniform grid for a closed-form N), splits them at every contact switch and grades them
geometrically towards it; it stores per piece the Gauss–Legendre integrals of N and of
the contact stiffness, and the end values (one-sided at a switch).

``src`` = (kind, t, y, ẏ, ÿ+, ÿ-, c): ``CLOSED_FORM`` (a prescribed penetration, N(t)
from the coefficients c; the tables are unused) or ``TABLE`` (quintic Hermite nodes of
a periodic orbit, :func:`microslip.analysis.orbit_table.orbit_state`); c is the tuple the
laws take (``model.coefficients.as_tuple``), built once with ``src``. The stiffness
evaluated is the elastic contact stiffness K(δ) = m2 S c_n δ^(m2-1).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip._refcount import NO_REFCOUNT
from microslip.analysis.orbit_table import orbit_state
from microslip.model.contact import elastic_stiffness
from microslip.model.normal import gap, normal_force, raw_normal_force_rate

__all__ = [
    "CLOSED_FORM", "CLOSED_FORM_PIECES", "GAUSS_NODES", "GAUSS_WEIGHTS", "TABLE",
    "build_pieces", "normal_at", "piece_integrals",
]  # fmt: skip

CLOSED_FORM = 0.0
TABLE = 1.0

# Columns of a piece: its ends [s], contact flag, ∫N [N s], ∫K [N s/m], ∫(b - s) K(s) ds
# [N s²/m], and (N [N], Ṅ [N/s], K [N/m]) at both ends (one-sided at a contact switch)
# and at its middle (a + b)/2, where the walk looks for a slip that ends inside.
A, B, CONTACT, INT_N, INT_K, INT_K2, N_A, RATE_A, K_A, N_B, RATE_B, K_B = range(12)
N_M, RATE_M, K_M = range(12, 15)
N_COLUMNS = 15

GAUSS_NODES, GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(8)
_GRADING = 12  # a piece next to a contact switch is split at h/2, h/4, ..., h/2^12
_NUDGE = 1e-9  # one-sided values at a switch: this fraction of the piece inside it
CLOSED_FORM_PIECES = 32  # uniform pieces per period of a closed-form N(t)


# Inlined (with orbit_state) into its callers: as a call, each evaluation took and
# released a reference to each of the five table arrays (atomic NRT operations, ~100 ns,
# several times the interpolation), and the walk of each drive speed evaluates it often.
@njit(cache=True, inline="always")
def normal_at(t, src):
    """(N [N], Ṅ [N/s], K [N/m]) at time t [s]; all 0 out of contact."""
    kind, tn, yn, vn, a0, a1, c = src
    y, yd = 0.0, 0.0
    if kind == TABLE:
        y, yd = orbit_state(t, tn, yn, vn, a0, a1)
    n = normal_force(t, y, yd, c)
    if n <= 0.0:
        return 0.0, 0.0, 0.0
    # In contact (n > 0) the clipped rate is the raw one: given n, it is not recomputed.
    return n, raw_normal_force_rate(t, y, yd, n, c), elastic_stiffness(gap(t, y, yd, c)[0], c)


@njit(cache=True, **NO_REFCOUNT)
def piece_integrals(lo, hi, src):
    """(∫N [N s], ∫K [N s/m], ∫(hi - s) K(s) ds [N s²/m]) over [lo, hi] inside one piece
    (Gauss–Legendre)."""
    half = 0.5 * (hi - lo)
    i_n = i_k = i_k2 = 0.0
    for j in range(GAUSS_NODES.shape[0]):
        s = 0.5 * (hi + lo) + half * GAUSS_NODES[j]
        n, _rate, k = normal_at(s, src)
        w = half * GAUSS_WEIGHTS[j]
        i_n += w * n
        i_k += w * k
        i_k2 += w * (hi - s) * k
    return i_n, i_k, i_k2


@njit(cache=True, inline="always")
def _contact(t, src):
    return normal_at(t, src)[0] > 0.0


@njit(cache=True, **NO_REFCOUNT)
def _interval_switches(a, b, src, found):
    """The contact switches inside the base interval [a, b], each bisected to round-off
    between the Gauss nodes where the contact state changes, into ``found`` (room for
    GAUSS_NODES.size + 1); returns their count. Allocates nothing, so that it runs
    without reference counting (docs/design.md): the inlined N(t) reads the source's
    tables, which a counted function takes and releases at each evaluation."""
    count = 0
    samples = GAUSS_NODES.shape[0]
    lo = a + _NUDGE * (b - a)
    state = _contact(lo, src)
    for j in range(samples + 1):
        s = a + 0.5 * (b - a) * (GAUSS_NODES[j] + 1.0) if j < samples else b - _NUDGE * (b - a)
        if _contact(s, src) != state:
            hi = s
            for _ in range(200):
                mid = 0.5 * (lo + hi)
                if mid <= lo or mid >= hi:
                    break
                if _contact(mid, src) == state:
                    lo = mid
                else:
                    hi = mid
            found[count] = hi
            count += 1
            state = not state
        lo = s
    return count


@njit(cache=True)
def _contact_cuts(base, src):
    """The base boundaries with every contact switch inside them
    (:func:`_interval_switches`), and the contact state of each interval."""
    cuts = [base[0]]
    found = np.empty(GAUSS_NODES.shape[0] + 1)
    for i in range(base.shape[0] - 1):
        a, b = base[i], base[i + 1]
        if b <= a:
            continue
        for j in range(_interval_switches(a, b, src, found)):
            if found[j] > cuts[-1]:
                cuts.append(found[j])
        if b > cuts[-1]:
            cuts.append(b)
    states = np.empty(len(cuts) - 1)
    for i in range(states.shape[0]):
        states[i] = 1.0 if _contact(0.5 * (cuts[i] + cuts[i + 1]), src) else 0.0
    return cuts, states


@njit(cache=True, nogil=True)
def build_pieces(base, src):
    """Pieces of one period [base[0], base[-1]] on which N is smooth (rows ``N_COLUMNS``).

    ``base``: the boundaries of the source's own smooth intervals (table nodes, or a
    uniform grid for a closed form). Returns (pieces, max Ṅ [N/s], max Ṅ/K [m/s]), the
    maxima over the contact (-inf where N never rises).
    """
    cuts, states = _contact_cuts(base, src)
    n_cut = states.shape[0]
    starts, ends, left_switch, right_switch = [0.0], [0.0], [False], [False]
    for i in range(n_cut):
        a, b = cuts[i], cuts[i + 1]
        left = states[i] != states[i - 1]  # states[-1]: the period wraps around
        right = states[i] != states[(i + 1) % n_cut]
        points = [a]
        if states[i] != 0.0:  # graded towards the switches at a and/or b
            mid = 0.5 * (a + b) if (left and right) else (b if left else a)
            for j in range(_GRADING, 0, -1):
                if left:
                    points.append(a + (mid - a) * 0.5**j)
            if left and right:
                points.append(mid)
            for j in range(1, _GRADING + 1):
                if right:
                    points.append(b - (b - mid) * 0.5**j)
        points.append(b)
        for j in range(len(points) - 1):
            starts.append(points[j])
            ends.append(points[j + 1])
            left_switch.append(left and j == 0)
            right_switch.append(right and j == len(points) - 2)
    n = len(starts) - 1
    pieces = np.zeros((n, N_COLUMNS))
    best = np.full(2, -np.inf)  # max Ṅ, max Ṅ/K
    where = np.zeros(2)
    for i in range(n):
        _fill_piece(pieces[i], starts[i + 1], ends[i + 1], left_switch[i + 1],
                    right_switch[i + 1], src, best, where)  # fmt: skip
    for which in range(2):
        if best[which] > -np.inf:
            best[which] = _refine(where[which], which == 1, pieces, best[which], src)
    return pieces, best[0], best[1]


@njit(cache=True, **NO_REFCOUNT)
def _fill_piece(row, a, b, left_switch, right_switch, src, best, where):
    """One piece's ``row`` (ends a, b [s]; its values one-sided at an end that is a
    contact switch), and the sampled maxima of Ṅ and Ṅ/K (``best``, at times ``where``)
    raised by its ends and Gauss nodes. Allocates nothing: no reference counting."""
    row[A], row[B] = a, b
    if not _contact(0.5 * (a + b), src):
        return
    row[CONTACT] = 1.0
    row[INT_N], row[INT_K], row[INT_K2] = piece_integrals(a, b, src)
    ta = a + _NUDGE * (b - a) if left_switch else a
    tb = b - _NUDGE * (b - a) if right_switch else b
    row[N_A], row[RATE_A], row[K_A] = normal_at(ta, src)
    row[N_B], row[RATE_B], row[K_B] = normal_at(tb, src)
    row[N_M], row[RATE_M], row[K_M] = normal_at(0.5 * (a + b), src)
    _raise_maxima(ta, row[N_A], row[RATE_A], row[K_A], best, where)
    _raise_maxima(tb, row[N_B], row[RATE_B], row[K_B], best, where)
    for j in range(GAUSS_NODES.shape[0]):
        s = a + 0.5 * (b - a) * (GAUSS_NODES[j] + 1)
        n, rate, k = normal_at(s, src)
        _raise_maxima(s, n, rate, k, best, where)


@njit(cache=True, inline="always")
def _raise_maxima(s, n, rate, k, best, where):
    """Raise the sampled maxima of Ṅ and Ṅ/K (``best``, at times ``where``) by the
    values at time s [s]: one evaluation of N(t) serves both rates."""
    for which in range(2):
        value = _rate_of(n, rate, k, which == 1)
        if value > best[which]:
            best[which] = value
            where[which] = s


@njit(cache=True, inline="always")
def _rate_of(n, rate, k, ratio):
    """Ṅ [N/s], or Ṅ/K [m/s] (``ratio``), from (N, Ṅ, K) at one time; -inf out of
    contact."""
    if n <= 0.0 or (ratio and k <= 0.0):
        return -np.inf
    return rate / k if ratio else rate


@njit(cache=True, inline="always")
def _rate(t, ratio, src):
    """Ṅ [N/s], or Ṅ/K [m/s] (``ratio``), at t; -inf out of contact."""
    n, rate, k = normal_at(t, src)
    return _rate_of(n, rate, k, ratio)


@njit(cache=True, **NO_REFCOUNT)
def _refine(t, ratio, pieces, value, src):
    """Golden-section refinement of a sampled maximum of :func:`_rate` near t."""
    i = min(max(np.searchsorted(pieces[:, A], t, side="right") - 1, 0), pieces.shape[0] - 1)
    h = pieces[i, B] - pieces[i, A]
    lo = max(pieces[i, A] + _NUDGE * h, t - h / 8.0)
    hi = min(pieces[i, B] - _NUDGE * h, t + h / 8.0)
    g = 0.5 * (math.sqrt(5.0) - 1.0)
    x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
    f1, f2 = _rate(x1, ratio, src), _rate(x2, ratio, src)
    for _ in range(80):
        if f1 > f2:
            hi, x2, f2 = x2, x1, f1
            x1 = hi - g * (hi - lo)
            f1 = _rate(x1, ratio, src)
        else:
            lo, x1, f1 = x1, x2, f2
            x2 = lo + g * (hi - lo)
            f2 = _rate(x2, ratio, src)
    return max(value, f1, f2)
