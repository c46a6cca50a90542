"""One period of a model's normal motion as a :class:`SlidingTable` (reflected process).

A body that obeys the normal equation (harmonic force, base motion) is read from its
periodic orbit (:func:`microslip.analysis.periodic.periodic_orbit`). A prescribed
penetration has no normal equation: N(t) is a known function of time, and the table
holds w with ẅ = N̄/m - N(t)/m, ẇ and w from Gauss–Legendre quadrature of the
closed-form N(t) on the pieces between contact switches (w periodic, N̄ the mean of N);
:mod:`microslip.analysis.forced_sliding` then treats w as y with g -> N̄/m.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from microslip.analysis.forced_sliding import SlidingTable, sliding_table
from microslip.model.composition import Model
from microslip.model.excitation import HarmonicForce, PrescribedPenetration, prescribed_gap
from microslip.model.normal import raw_normal_force

__all__ = ["PRESCRIBED_INTERVALS", "model_sliding_table", "prescribed_sliding_table"]

PRESCRIBED_INTERVALS = 1024  # nodes of the prescribed-penetration table per period
_GAUSS = np.polynomial.legendre.leggauss(10)


def orbit_sliding_table(model: Model, orbit) -> SlidingTable:
    """The table of a periodic orbit (fields t, y, ydot, accel_start, accel_end)."""
    p = model.params
    ex = model.excitation
    p0, omega = 0.0, 0.0
    if isinstance(ex, HarmonicForce):
        p0, omega = ex.amplitude, 2.0 * math.pi * ex.frequency
    return sliding_table(
        orbit.t, orbit.y, orbit.ydot, orbit.accel_start, orbit.accel_end,
        mass=p.mass, gravity=p.g, force_amplitude=p0, omega=omega,
    )  # fmt: skip


def _switches(raw, period: float, samples: int) -> list[float]:
    """Times in (0, T) where N_raw changes sign (contact switches of the prescribed law)."""
    grid = np.linspace(0.0, period, samples + 1)
    values = np.array([raw(t) for t in grid])
    out = []
    for a, b, fa, fb in zip(grid[:-1], grid[1:], values[:-1], values[1:], strict=True):
        if fa == 0.0 and a > 0.0:
            out.append(float(a))
        elif fa * fb < 0.0:
            out.append(float(brentq(raw, a, b, xtol=1e-15 * period, rtol=8.9e-16)))
    return out


def prescribed_sliding_table(model: Model, intervals: int = PRESCRIBED_INTERVALS) -> SlidingTable:
    """The sliding table of a prescribed penetration δ(t) = δ_m + Δ cos ωt."""
    c = model.pack(0.0)
    mass = model.params.mass
    period = model.excitation.period

    def raw(t: float) -> float:  # N_raw where δ > 0, else -1 (no contact)
        return raw_normal_force(t, 0.0, 0.0, c) if prescribed_gap(t, c)[0] > 0.0 else -1.0

    events = _switches(raw, period, 8 * intervals)
    grid = np.linspace(0.0, period, intervals + 1)
    keep = [t for t in grid if all(abs(t - e) > 1e-9 * period for e in events)]
    t = np.unique(np.concatenate([keep, events, [0.0, period]]))
    nodes, weights = _GAUSS
    n = t.size - 1
    accel_start, accel_end = np.empty(n), np.empty(n)
    impulse = np.empty(n)  # ∫ N/m over each interval
    moment = np.empty(n)  # ∫ (t_{k+1} - s) N(s)/m ds
    for k in range(n):
        a, b = t[k], t[k + 1]
        contact = raw(0.5 * (a + b)) > 0.0

        def force(s: float, contact: bool = contact) -> float:
            return max(raw_normal_force(s, 0.0, 0.0, c), 0.0) if contact else 0.0

        s = 0.5 * (b - a) * nodes + 0.5 * (a + b)
        f = np.array([force(v) for v in s]) / mass
        w = 0.5 * (b - a) * weights
        impulse[k] = np.dot(w, f)
        moment[k] = np.dot(w, (b - s) * f)
        accel_start[k] = -force(a) / mass
        accel_end[k] = -force(b) / mass
    g_eff = impulse.sum() / period  # N̄/m
    h = np.diff(t)
    ydot = np.concatenate([[0.0], np.cumsum(g_eff * h - impulse)])
    y = np.concatenate([[0.0], np.cumsum(ydot[:-1] * h + 0.5 * g_eff * h * h - moment)])
    start_speed = -y[-1] / period  # ẇ(0) that makes w periodic
    ydot += start_speed
    y += start_speed * t
    return sliding_table(
        t, y, ydot, accel_start + g_eff, accel_end + g_eff, mass=mass, gravity=g_eff
    )


def model_sliding_table(model: Model, initial_state=None) -> SlidingTable:
    """The sliding table of a forced model's steady normal motion.

    Raises :class:`microslip.analysis.periodic.NotPeriodOneError` where the response from
    ``initial_state`` (rest at y0 by default) is not a stable period-1 orbit.
    """
    if isinstance(model.excitation, PrescribedPenetration):
        return prescribed_sliding_table(model)
    from microslip.analysis.periodic import periodic_orbit

    return orbit_sliding_table(model, periodic_orbit(model, initial_state=initial_state))
