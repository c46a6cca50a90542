"""Exact steady sliding over one period of a periodic normal motion (any normal excitation).

Under a constant force F >= 0 with a rigid tangential contact and Coulomb friction, the
sliding velocity is the reflected process of the free drift (docs/model-facts.md, facts
5–6; docs/design.md, sliding on a forced contact)

    v(t) = G(t) - min_{s <= t} G(s),    G(t) = ∫0^t (F - μ N)/m ds,

whatever the normal motion. The friction impulse is known from the normal motion alone:
m ÿ = m g + P(t) - N gives ∫N dt = m g Δt + ∫P dt - m Δẏ, so with
Q(t) = ∫0^t N/m ds = g t + Π(t)/m - (ẏ(t) - ẏ(0)), Π(t) = ∫0^t P ds = P0 (1 - cos ωt)/ω,

    G(t) = F t/m - μ Q(t),

and the slip distance of a slip from rest at t_r to the stop at t_s = t_r + Δ is

    Δx = (F/m - μ g) Δ²/2 - (μ P0/m) [cos(ω t_r) Δ/ω - (sin ω t_s - sin ω t_r)/ω²]
         + μ [y(t_s) - y(t_r) - ẏ(t_r) Δ].

Base motion has P = 0 (y absolute). A prescribed penetration has no normal equation: a
table of w with ẅ = N̄/m - N(t)/m (N̄ the mean of N, quadrature of the closed-form N(t))
plays the part of y with g -> N̄/m (:func:`prescribed_table`).

Steady state: G drifts by -D per period, D = (μ N̄ - F) T/m, N̄ = m g for a body that obeys
the normal equation (identity ⟨N⟩ = m g). H(t) = G(t) + D t/T is periodic and does not
depend on F; from a global minimum t* of H the motion is periodic and the mean velocity
is the slip distance over [t*, t* + T] divided by T, with every release (N falls below
F/μ) and stop (G back at its level at release) inside the period located on the quintic
Hermite dense output of the node table. F > μ N̄: no steady state (inf).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import threads

__all__ = ["SAMPLES", "SlidingTable", "mean_velocities", "sliding_table", "slip_intervals"]

# Sub-samples per node interval on which releases and stops are bracketed before they are
# refined on the dense output. A slip shorter than one sub-sample that starts and ends
# inside it (a near-tangency of N with F/μ) is missed; its distance is O(h^3 Ġ').
SAMPLES = 8
_ITERATIONS = 100


@njit(cache=True, inline="always")
def _hermite(y0, v0, a0, y1, v1, a1, h, s):
    """Quintic Hermite value, slope and curvature on [0, h] at fraction s."""
    s2 = s * s
    s3 = s2 * s
    s4 = s3 * s
    s5 = s4 * s
    value = (
        y0 * (1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5)
        + h * v0 * (s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5)
        + h * h * a0 * 0.5 * (s2 - 3.0 * s3 + 3.0 * s4 - s5)
        + h * h * a1 * 0.5 * (s3 - 2.0 * s4 + s5)
        + h * v1 * (-4.0 * s3 + 7.0 * s4 - 3.0 * s5)
        + y1 * (10.0 * s3 - 15.0 * s4 + 6.0 * s5)
    )
    d0 = -30.0 * s2 + 60.0 * s3 - 30.0 * s4
    slope = (
        (y1 - y0) * (-d0) / h
        + v0 * (1.0 - 18.0 * s2 + 32.0 * s3 - 15.0 * s4)
        + h * a0 * 0.5 * (2.0 * s - 9.0 * s2 + 12.0 * s3 - 5.0 * s4)
        + h * a1 * 0.5 * (3.0 * s2 - 8.0 * s3 + 5.0 * s4)
        + v1 * (-12.0 * s2 + 28.0 * s3 - 15.0 * s4)
    )
    c0 = -60.0 * s + 180.0 * s2 - 120.0 * s3
    curvature = (
        (y1 - y0) * (-c0) / (h * h)
        + v0 * (-36.0 * s + 96.0 * s2 - 60.0 * s3) / h
        + a0 * 0.5 * (2.0 - 18.0 * s + 36.0 * s2 - 20.0 * s3)
        + a1 * 0.5 * (6.0 * s - 24.0 * s2 + 20.0 * s3)
        + v1 * (-24.0 * s + 84.0 * s2 - 60.0 * s3) / h
    )
    return value, slope, curvature


@njit(cache=True)
def _local(k, t, tn, yn, vn, a0, a1):
    """(y, ẏ, ÿ) at local time t in node interval k."""
    h = tn[k + 1] - tn[k]
    s = (t - tn[k]) / h
    s = min(max(s, 0.0), 1.0)
    return _hermite(yn[k], vn[k], a0[k], yn[k + 1], vn[k + 1], a1[k], h, s)


@njit(cache=True)
def _eval(k, wrap, t, tn, yn, vn, a0, a1, scalars):
    """(Q, N, y, ẏ) at absolute time t (local t - wrap T, node interval k)."""
    period, g, mass, p0, omega = scalars[0], scalars[1], scalars[2], scalars[3], scalars[4]
    local = t - wrap * period
    y, v, a = _local(k, local, tn, yn, vn, a0, a1)
    force = 0.0
    impulse = 0.0
    if p0 != 0.0:
        force = p0 * math.sin(omega * local)
        impulse = p0 * (1.0 - math.cos(omega * local)) / omega
    q = g * local + impulse / mass - (v - vn[0]) + wrap * g * period
    n = mass * (g - a) + force
    return q, n, y, v


@njit(cache=True)
def _prepare(tn, yn, vn, a0, a1, scalars, samples, ts, qs, ns):
    """Fill the sample arrays (length n samples + 1) and return (t*, first sample > t*)."""
    n = tn.shape[0] - 1
    for k in range(n):
        for i in range(samples):
            j = k * samples + i
            t = tn[k] + (tn[k + 1] - tn[k]) * i / samples
            q, nn, _y, _v = _eval(k, 0, t, tn, yn, vn, a0, a1, scalars)
            ts[j], qs[j], ns[j] = t, q, nn
    last = n * samples
    q, nn, _y, _v = _eval(n - 1, 0, tn[n], tn, yn, vn, a0, a1, scalars)
    ts[last], qs[last], ns[last] = tn[n], q, nn
    # t*: global minimum of H ∝ g t - Q (independent of F); refined where N falls through m g.
    g, mass = scalars[1], scalars[2]
    best = 0
    for j in range(last):
        if g * ts[j] - qs[j] < g * ts[best] - qs[best]:
            best = j
    lo = ts[best - 1] if best > 0 else ts[0]
    hi = ts[best + 1]
    k_lo = (best - 1) // samples if best > 0 else 0
    t_star = ts[best]
    # H' = g - N/m goes from <= 0 to >= 0 at the minimum: bisect inside one node interval.
    for side in range(2):
        a = lo if side == 0 else ts[best]
        b = ts[best] if side == 0 else hi
        k = k_lo if side == 0 else best // samples
        fa = g - _eval(k, 0, a, tn, yn, vn, a0, a1, scalars)[1] / mass
        fb = g - _eval(k, 0, b, tn, yn, vn, a0, a1, scalars)[1] / mass
        if fa < 0.0 < fb:
            for _ in range(_ITERATIONS):
                mid = 0.5 * (a + b)
                if mid <= a or mid >= b:
                    break
                if g - _eval(k, 0, mid, tn, yn, vn, a0, a1, scalars)[1] / mass < 0.0:
                    a = mid
                else:
                    b = mid
            t_star = 0.5 * (a + b)
            break
    first = best + 1 if t_star >= ts[best] else best
    return t_star, first


@njit(cache=True)
def _release(force, mu, k, wrap, lo, hi, tn, yn, vn, a0, a1, scalars):
    """First time in (lo, hi] where μ N falls below F (N(lo) >= F/μ assumed; else lo)."""
    level = force / mu
    if _eval(k, wrap, lo, tn, yn, vn, a0, a1, scalars)[1] < level:
        return lo
    for _ in range(_ITERATIONS):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if _eval(k, wrap, mid, tn, yn, vn, a0, a1, scalars)[1] < level:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


@njit(cache=True)
def _stop(force, mu, level, k, wrap, lo, hi, tn, yn, vn, a0, a1, scalars):
    """Time in (lo, hi] where G comes back down to ``level`` (G(lo) > level >= G(hi))."""
    mass = scalars[2]
    for _ in range(_ITERATIONS):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        q = _eval(k, wrap, mid, tn, yn, vn, a0, a1, scalars)[0]
        if force * mid / mass - mu * q > level:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@njit(cache=True)
def _distance(force, mu, t_r, y_r, v_r, t_s, y_s, scalars):
    """Slip distance [m] from rest at t_r to the stop at t_s (closed form, module docstring)."""
    g, mass, p0, omega = scalars[1], scalars[2], scalars[3], scalars[4]
    span = t_s - t_r
    out = 0.5 * (force / mass - mu * g) * span * span + mu * (y_s - y_r - v_r * span)
    if p0 != 0.0:
        shift = math.cos(omega * t_r) * span / omega
        shift -= (
            2.0
            * math.cos(0.5 * omega * (t_s + t_r))
            * math.sin(0.5 * omega * span)
            / (omega * omega)
        )
        out -= mu * p0 / mass * shift
    # A slip just past the threshold cancels down to rounding; F >= 0 never slides back.
    return max(out, 0.0)


@njit(cache=True)
def _walk(force, mu, tn, yn, vn, a0, a1, scalars, samples, ts, qs, ns, t_star, first, events):
    """Slip distance over [t*, t* + T] [m] and the number of slips; the first slips are
    written to ``events`` rows (release time, stop time, distance) modulo T."""
    period, mass = scalars[0], scalars[2]
    last = ts.shape[0] - 1
    t_end = t_star + period
    level = force / mu
    sliding = False
    g_r = t_r = y_r = v_r = 0.0
    total = 0.0
    count = 0
    t_prev = t_star
    j = first
    while True:
        wrap_prev = (j - 1) // last
        k = ((j - 1) % last) // samples  # node interval of the sub-interval (j-1, j]
        wrap = j // last
        t_j = ts[j % last] + wrap * period
        q_j = qs[j % last] + wrap * scalars[1] * period
        n_j = ns[j % last]
        at_end = t_j >= t_end
        if at_end:
            t_j = t_end
            q_j, n_j, _y, _v = _eval(k, wrap_prev, t_j, tn, yn, vn, a0, a1, scalars)
        g_j = force * t_j / mass - mu * q_j
        for _ in range(3):  # at most release, stop, release inside one sub-interval
            if not sliding:
                if not n_j < level:
                    break
                t_r = _release(force, mu, k, wrap_prev, t_prev, t_j, tn, yn, vn, a0, a1, scalars)
                q_r, _n, y_r, v_r = _eval(k, wrap_prev, t_r, tn, yn, vn, a0, a1, scalars)
                g_r = force * t_r / mass - mu * q_r
                sliding = True
                t_prev = t_r
                if g_j > g_r:
                    break
                # Released and back below within one sub-interval: a sub-sample slip.
                sliding = False
                t_prev = t_j
                break
            if g_j > g_r and not at_end:
                break
            t_s = t_j
            if g_j <= g_r and t_prev > t_r:
                t_s = _stop(force, mu, g_r, k, wrap_prev, t_prev, t_j, tn, yn, vn, a0, a1, scalars)
            y_s = _eval(k, wrap_prev, t_s, tn, yn, vn, a0, a1, scalars)[2]
            d = _distance(force, mu, t_r, y_r, v_r, t_s, y_s, scalars)
            total += d
            if count < events.shape[0]:
                events[count, 0] = t_r % period
                events[count, 1] = t_s % period
                events[count, 2] = d
            count += 1
            sliding = False
            t_prev = t_s
        if at_end:
            break
        t_prev = t_j
        j += 1
    return total, count


@njit(cache=True, nogil=True)
def _mean_velocities(lo, hi, forces, mu, tn, yn, vn, a0, a1, scalars, samples, ts, qs, ns,
                     ts_star, out):  # fmt: skip
    """out[i] for forces [lo, hi) of :func:`mean_velocities` (a range of threads.run_ranges)."""
    period, g, mass = scalars[0], scalars[1], scalars[2]
    n_min = ns.min()
    for i in range(lo, hi):
        force = forces[i]
        if force > mu * mass * g:
            out[i] = math.inf
        elif not force > mu * n_min:
            out[i] = 0.0
        else:
            events = np.empty((0, 3))
            total, _count = _walk(
                force, mu, tn, yn, vn, a0, a1, scalars, samples, ts, qs, ns,
                ts_star[0], int(ts_star[1]), events,
            )  # fmt: skip
            out[i] = total / period


@dataclass(frozen=True)
class SlidingTable:
    """One period of a normal motion prepared for the reflected process (SI units).

    Attributes
    ----------
    t, y, ydot, accel_start, accel_end : node arrays over [0, T] (quintic Hermite per
        interval; y [m], ẏ [m/s], ÿ [m/s^2] one-sided at the interval ends)
    scalars : (T [s], g_eff [m/s^2], m [kg], P0 [N], ω [rad/s]); g_eff = N̄/m
    samples, ts, qs, ns : sub-samples per interval, sample times [s], Q [m/s], N [N]
    start : (t* [s], index of the first sample after t*)
    """

    t: np.ndarray
    y: np.ndarray
    ydot: np.ndarray
    accel_start: np.ndarray
    accel_end: np.ndarray
    scalars: np.ndarray
    samples: int
    ts: np.ndarray
    qs: np.ndarray
    ns: np.ndarray
    start: np.ndarray

    @property
    def period(self) -> float:
        return float(self.scalars[0])

    @property
    def mean_normal_force(self) -> float:
        """N̄ [N], the mean normal force over the period (m g_eff)."""
        return float(self.scalars[1] * self.scalars[2])

    @property
    def min_normal_force(self) -> float:
        """Smallest sampled N [N] over the period."""
        return float(self.ns.min())

    def _args(self) -> tuple:
        return (self.t, self.y, self.ydot, self.accel_start, self.accel_end, self.scalars)


def sliding_table(
    t: np.ndarray,
    y: np.ndarray,
    ydot: np.ndarray,
    accel_start: np.ndarray,
    accel_end: np.ndarray,
    *,
    mass: float,
    gravity: float,
    force_amplitude: float = 0.0,
    omega: float = 0.0,
    samples: int = SAMPLES,
) -> SlidingTable:
    """Prepare a periodic normal orbit (nodes over exactly one period, t[0] = 0) for sliding.

    ``mass`` m [kg], ``gravity`` g [m/s^2] (N̄/m for a prescribed penetration's table),
    ``force_amplitude`` P0 [N] and ``omega`` ω [rad/s] of a harmonic normal force
    P = P0 sin ωt on the body (0 for base motion, free vibration or a prescribed
    penetration). The orbit must be periodic (y(T) = y(0), ẏ(T) = ẏ(0)).
    """
    arrays = [np.ascontiguousarray(a, dtype=float) for a in (t, y, ydot, accel_start, accel_end)]
    t, y, ydot, accel_start, accel_end = arrays
    if t[0] != 0.0 or np.any(np.diff(t) <= 0.0):
        raise ValueError("orbit nodes must start at t = 0 and increase strictly")
    if not (y.size == ydot.size == t.size and accel_start.size == accel_end.size == t.size - 1):
        raise ValueError("orbit node arrays have inconsistent lengths")
    scalars = np.array([t[-1], gravity, mass, force_amplitude, omega], dtype=float)
    size = (t.size - 1) * samples + 1
    ts, qs, ns = np.empty(size), np.empty(size), np.empty(size)
    t_star, first = _prepare(t, y, ydot, accel_start, accel_end, scalars, samples, ts, qs, ns)
    return SlidingTable(
        t, y, ydot, accel_start, accel_end, scalars, samples, ts, qs, ns,
        np.array([t_star, float(first)]),
    )  # fmt: skip


def mean_velocities(table: SlidingTable, mu: float, forces: np.ndarray) -> np.ndarray:
    """Exact steady mean velocity [m/s] for each force F [N] (>= 0) on the table's orbit.

    0 where F <= μ min N (no release), inf where F > μ N̄ (no steady state).
    """
    forces = np.ascontiguousarray(forces, dtype=float)
    out = np.empty(forces.shape[0])
    threads.run_ranges(
        _mean_velocities, forces.shape[0], forces, float(mu), *table._args(), table.samples,
        table.ts, table.qs, table.ns, table.start, out, interruptible=False,
    )  # fmt: skip
    return out


def slip_intervals(table: SlidingTable, mu: float, force: float, *, capacity: int = 64):
    """The steady slips of one period: (release [s], stop [s], distance [m]) rows.

    Times are modulo T (a slip may wrap past T). Empty when the slider never moves;
    ``ValueError`` when F > μ N̄ (no steady state).
    """
    if force > mu * table.mean_normal_force:
        raise ValueError(f"force={force!r} N exceeds mu N_mean: no steady stick-slip cycle")
    if not force > mu * table.min_normal_force:
        return np.empty((0, 3))
    events = np.empty((capacity, 3))
    _total, count = _walk(
        float(force), float(mu), *table._args(), table.samples, table.ts, table.qs, table.ns,
        table.start[0], int(table.start[1]), events,
    )  # fmt: skip
    return events[: min(count, capacity)].copy()
