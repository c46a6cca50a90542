"""The compliant contact point under a known periodic normal force: the exact steady
state over one normal period (docs/theory/friction_reduction.md).

The body moves at a prescribed speed v > 0 (the sign of v only mirrors f). Given N(t),
Ṅ(t) and the tangential stiffness k_t(t) over one period T, the spring force f >= 0 of
the massless contact point obeys

    stick   ḟ = k_t v   until f reaches μ_s N: f drops to μ_k N, and the point slides if
                        k_t v > μ_k Ṅ, else sticks again;
    slip    f = μ_k N   while k_t v > μ_k Ṅ; it sticks where μ_k Ṅ rises through k_t v;
    flight  f = 0       (N = 0); at touchdown the point sticks with f = 0, or slides at
                        once if the limit μ_s N cannot keep ahead of the spring.

A slip or a flight erases the point's memory, so the period map reaches its fixed point
(or a cycle of a few periods, with μ_s > μ_k) right after the first of them.

:func:`~microslip.analysis.normal_pieces.build_pieces` cuts the period into pieces on
which N is smooth, with the Gauss–Legendre integrals of N and of the stiffness and the
end values (:mod:`microslip.analysis.normal_pieces`). :func:`steady_friction` walks
the pieces for each drive speed: the switching instants are roots of smooth functions
(Brent's method, to round-off), the averages are the stored integrals plus
Gauss–Legendre sums on the partial pieces. The normal motion is shared by all speeds.

``src`` = (kind, t, y, ẏ, ÿ+, ÿ-, c): ``CLOSED_FORM`` (a prescribed penetration, N(t)
from the coefficient vector c; the tables are unused) or ``TABLE`` (quintic Hermite
nodes of a periodic orbit, :func:`microslip.analysis.orbit_table.orbit_state`). The
stiffness evaluated is the elastic contact stiffness K(δ) = m2 S c_n δ^(m2-1); the walk
uses ``law`` = (v, μ_s, μ_k, k, λ) with k_t = k (TangentialSpring, k > 0) or λ K(δ)
(MindlinSpring, k = 0).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip._refcount import NO_REFCOUNT
from microslip.analysis.normal_pieces import (
    CONTACT,
    INT_K,
    INT_K2,
    INT_N,
    K_A,
    K_B,
    K_M,
    N_A,
    N_B,
    N_M,
    RATE_A,
    RATE_B,
    RATE_M,
    A,
    B,
    normal_at,
    piece_integrals,
)
from microslip.integrators import threads

__all__ = ["R_COLUMNS", "R_ERROR", "R_FORCE", "R_PERIODS", "R_STICK", "steady_friction"]

# Columns of a speed's result: <f> [N], stick fraction [-], length of the steady cycle in
# normal periods (0: none found within max_periods), relative drift of <f> if none.
R_FORCE, R_STICK, R_PERIODS, R_ERROR = range(4)
R_COLUMNS = 4

FLIGHT, STICK, SLIP = 0.0, 1.0, 2.0
MARGIN, MARGIN_RATE, SLIP_RATE = 0, 1, 2  # μ_s N - f, its rate, k_t v - μ_k Ṅ

_TOL = 1e-13  # thresholds of the switching functions, relative to their scales


@njit(cache=True, inline="always")
def _stiffness(k_elastic, law):
    """k_t [N/m] in contact: the spring's constant k, or Mindlin's λ K(δ)."""
    return law[3] if law[3] > 0.0 else law[4] * k_elastic


@njit(cache=True, inline="always")
def _slip_function(n, rate, k_elastic, law):
    """k_t v - μ_k Ṅ [N/s] where the normal force is n [N], its rate ``rate`` [N/s] and
    the elastic stiffness ``k_elastic`` [N/m] (k_t = 0 out of contact)."""
    v, mu_k = law[0], law[2]
    k = _stiffness(k_elastic, law) if n > 0.0 else 0.0
    return k * v - mu_k * rate


@njit(cache=True, inline="always")
def _switching(which, x, t0, f0, law, src):
    """At time x: the stick margin μ_s N - f (f = f0 + v ∫_t0^x k_t), its rate, or the
    slip function k_t v - μ_k Ṅ (:func:`_slip_function`)."""
    v, mu_s, _mu_k, kconst, lam = law
    n, rate, k_el = normal_at(x, src)
    if which == MARGIN:
        grown = kconst * (x - t0) if kconst > 0.0 else lam * piece_integrals(t0, x, src)[1]
        return mu_s * n - (f0 + v * grown)
    if which == MARGIN_RATE:
        k = _stiffness(k_el, law) if n > 0.0 else 0.0
        return mu_s * rate - k * v
    return _slip_function(n, rate, k_el, law)


@njit(cache=True, **NO_REFCOUNT)
def _root(which, lo, hi, f_lo, f_hi, t0, f0, law, src, xtol):
    """Brent's method: a root of :func:`_switching` in [lo, hi] (f_lo, f_hi of opposite
    signs: the values at the ends, or a stand-in of the right sign)."""
    a, b, fa, fb = lo, hi, f_lo, f_hi
    c, fc = a, fa
    d = e = b - a
    for _ in range(200):
        if fb * fc > 0.0:
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        tol = 4.4e-16 * abs(b) + 0.5 * xtol
        m = 0.5 * (c - b)
        if abs(m) <= tol or fb == 0.0:
            return b
        if abs(e) >= tol and abs(fa) > abs(fb):
            s = fb / fa
            if a == c:
                p, q = 2.0 * m * s, 1.0 - s
            else:
                q, r = fa / fc, fb / fc
                p = s * (2.0 * m * q * (q - r) - (b - a) * (r - 1.0))
                q = (q - 1.0) * (r - 1.0) * (s - 1.0)
            if p > 0.0:
                q = -q
            p = abs(p)
            if 2.0 * p < min(3.0 * m * q - abs(tol * q), abs(e * q)):
                e, d = d, p / q
            else:
                d = e = m
        else:
            d = e = m
        a, fa = b, fb
        b += d if abs(d) > tol else (tol if m > 0.0 else -tol)
        fb = _switching(which, b, t0, f0, law, src)
    return b


@njit(cache=True, **NO_REFCOUNT)
def _touchdown(p, pieces, law, tol_f):
    """(phase, f) at the start of contact piece p after a flight: stuck with a relaxed
    spring, unless the limit μ_s N cannot keep ahead of the spring (sliding then)."""
    v, mu_s, mu_k = law[0], law[1], law[2]
    if (
        mu_s * pieces[p, N_A] > tol_f
        or mu_s * pieces[p, RATE_A] >= _stiffness(pieces[p, K_A], law) * v
    ):
        return STICK, 0.0
    return SLIP, mu_k * pieces[p, N_A]


@njit(cache=True, **NO_REFCOUNT)
def _period(phase, f, law, pieces, src, tol_f, tol_s, xtol):
    """One period from (phase, f) at its start: (phase and f at its end, ∫f dt [N s],
    stick time [s], ok, the smallest stick margin μ_s N - f [N] if the point stuck all
    period long, else -inf)."""
    v, mu_s, mu_k, kconst, lam = law
    total = stick = 0.0
    low = np.inf if phase == STICK else -np.inf  # stays finite only for a whole stick
    p, t = 0, pieces[0, A]
    if pieces[0, CONTACT] != 0.0 and phase == FLIGHT:
        phase, f = _touchdown(0, pieces, law, tol_f)
    guard = 4 * pieces.shape[0] + 1000
    while p < pieces.shape[0]:
        guard -= 1
        if guard < 0:
            return phase, f, total, stick, False, -np.inf
        a, b = pieces[p, A], pieces[p, B]
        if pieces[p, CONTACT] == 0.0:
            low = -np.inf
            phase, f, t = FLIGHT, 0.0, b
            p += 1
            if p < pieces.shape[0] and pieces[p, CONTACT] != 0.0:
                phase, f = _touchdown(p, pieces, law, tol_f)
            continue
        root = -1.0
        if phase == STICK:
            if kconst > 0.0:
                f_b = f + v * kconst * (b - t)
            else:
                f_b = f + v * lam * (pieces[p, INT_K] if t == a else piece_integrals(t, b, src)[1])
            m_b = mu_s * pieces[p, N_B] - f_b
            low = min(low, m_b)
            if m_b < -tol_f:
                root = _root(MARGIN, t, b, tol_f, m_b, t, f, law, src, xtol)
            else:  # the margin may dip below 0 inside the piece: look at its minimum
                if t == a:
                    d_t = mu_s * pieces[p, RATE_A] - _stiffness(pieces[p, K_A], law) * v
                else:
                    d_t = _switching(MARGIN_RATE, t, t, f, law, src)
                d_b = mu_s * pieces[p, RATE_B] - _stiffness(pieces[p, K_B], law) * v
                if d_t < 0.0 < d_b:
                    t_min = _root(MARGIN_RATE, t, b, d_t, d_b, t, f, law, src, xtol)
                    m_min = _switching(MARGIN, t_min, t, f, law, src)
                    low = min(low, m_min)
                    if m_min < -tol_f:
                        root = _root(MARGIN, t, t_min, tol_f, m_min, t, f, law, src, xtol)
            end = root if root > t else b
            span = end - t
            if kconst > 0.0:
                total += f * span + 0.5 * v * kconst * span * span
            elif t == a and end == b:
                total += f * span + v * lam * pieces[p, INT_K2]
            else:
                total += f * span + v * lam * piece_integrals(t, end, src)[2]
            stick += span
            if root > t:  # slip starts: f drops to the kinetic limit
                low = -np.inf
                n_r, rate_r, k_r = normal_at(root, src)
                f = mu_k * n_r
                if _stiffness(k_r, law) * v - mu_k * rate_r > 0.0:
                    phase = SLIP
            else:
                f = f_b
        else:
            low = -np.inf
            s_b = _stiffness(pieces[p, K_B], law) * v - mu_k * pieces[p, RATE_B]
            if s_b < -tol_s:
                root = _root(SLIP_RATE, t, b, tol_s, s_b, t, f, law, src, xtol)
            else:
                if t == a:  # the middle's N, Ṅ, K are the piece's: shared by all speeds
                    s_m = _slip_function(pieces[p, N_M], pieces[p, RATE_M], pieces[p, K_M], law)
                else:
                    s_m = _switching(SLIP_RATE, 0.5 * (t + b), t, f, law, src)
                if s_m < -tol_s:
                    root = _root(SLIP_RATE, t, 0.5 * (t + b), tol_s, s_m, t, f, law, src, xtol)
            if root > t:  # the point stops on the kinetic limit and sticks
                total += mu_k * piece_integrals(t, root, src)[0]
                f = mu_k * normal_at(root, src)[0]
                phase = STICK
            else:
                total += mu_k * (pieces[p, INT_N] if t == a else piece_integrals(t, b, src)[0])
                f = mu_k * pieces[p, N_B]
        if root > t:
            t = root
        else:
            t = b
            p += 1
    return phase, f, total, stick, True, low


@njit(cache=True, **NO_REFCOUNT)
def _steady(law, pieces, src, period, max_periods, tol_f, tol_s, out, work):
    """Iterate the period map from a sliding start to its cycle; fills ``out`` (R_*).
    ``work``: (5, max_periods + 1) scratch, the history of the periods walked (allocated
    once per range of speeds by the caller: per speed it was a tenth of the walk).

    A period the point spends stuck throughout repeats with f raised by the same amount
    G, until its smallest margin is used up: the periods that surely stay stuck are
    taken in one step (∫f dt grows by G T per period), so that a slow drive with
    μ_s > μ_k, whose cycle may span thousands of periods, costs a few steps.
    """
    v, mu_k = law[0], law[2]
    phase, f = FLIGHT, 0.0
    if pieces[0, CONTACT] != 0.0:
        f = mu_k * pieces[0, N_A]
        slides = _stiffness(pieces[0, K_A], law) * v > mu_k * pieces[0, RATE_A]
        phase = SLIP if slides else STICK
    phases, forces, totals, sticks, lengths = work[0], work[1], work[2], work[3], work[4]
    phases[0], forces[0] = phase, f
    done = 0
    k = 0
    while k < max_periods:
        start = f
        phase, f, total, stick, ok, low = _period(
            phase, f, law, pieces, src, tol_f, tol_s, 1e-15 * period
        )
        totals[k], sticks[k], lengths[k] = total, stick, 1.0
        grown = f - start
        skip = math.floor((low - tol_f) / grown) - 1.0 if low > 0.0 and grown > 0.0 else 0.0
        if skip >= 1.0 and k + 1 < max_periods:  # the same stuck period, skip times over
            phases[k + 1], forces[k + 1] = phase, f
            k += 1
            totals[k] = skip * total + grown * period * skip * (skip + 1.0) / 2.0
            sticks[k], lengths[k] = skip * stick, skip
            f += skip * grown
        phases[k + 1], forces[k + 1] = phase, f
        k += 1
        done = k
        if not ok:
            break
        for j in range(k - 1, -1, -1):  # the latest repeat: the shortest cycle
            if phases[j] == phase and abs(forces[j] - f) <= tol_f:
                span = lengths[j:k].sum() * period
                out[R_FORCE] = totals[j:k].sum() / span
                out[R_STICK] = sticks[j:k].sum() / span
                out[R_PERIODS], out[R_ERROR] = lengths[j:k].sum(), 0.0
                return
    half, quarter = max(done // 2, 1), max(done // 4, 1)  # no cycle: the later half
    mean = totals[done - half : done].sum() / (lengths[done - half : done].sum() * period)
    late = totals[done - quarter : done].sum() / (lengths[done - quarter : done].sum() * period)
    out[R_FORCE] = mean
    out[R_STICK] = sticks[done - half : done].sum() / (lengths[done - half : done].sum() * period)
    out[R_PERIODS] = 0.0
    out[R_ERROR] = abs(late - mean) / abs(mean) if mean != 0.0 else np.inf


def steady_friction(speeds, mu_s, mu_k, kconst, lam, pieces, src, period, max_periods, out):
    """The steady <f> [N] at each drive speed |v| > 0 [m/s] (rows of ``out``, R_*).

    ``kconst`` > 0: constant k_t [N/m]; else k_t = ``lam`` K(δ) (Mindlin). ``pieces``
    from :func:`build_pieces` on the same ``src``; ``period`` T [s]. Each speed is
    walked on its own, so its bits do not depend on the others or on the threads
    (:func:`~microslip.integrators.threads.run_ranges`).
    """
    n_max = float(np.max(pieces[:, [N_A, N_B]], initial=0.0))
    rate_scale = float(np.max(np.abs(pieces[:, [RATE_A, RATE_B]]), initial=0.0))
    tol_f, tol_s = _TOL * mu_s * n_max, _TOL * mu_k * rate_scale
    threads.run_ranges(
        _steady_rows, speeds.shape[0], speeds, mu_s, mu_k, kconst, lam, pieces, src, period,
        max_periods, tol_f, tol_s, out, interruptible=False,
    )  # fmt: skip


@njit(cache=True, nogil=True)
def _steady_rows(lo, hi, speeds, mu_s, mu_k, kconst, lam, pieces, src, period, max_periods,
                 tol_f, tol_s, out):  # fmt: skip
    """Rows [lo, hi) of :func:`steady_friction`."""
    work = np.empty((5, max_periods + 1))
    for i in range(lo, hi):
        law = (speeds[i], mu_s, mu_k, kconst, lam)
        _steady(law, pieces, src, period, max_periods, tol_f, tol_s, out[i], work)
