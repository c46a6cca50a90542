"""Quadrature along a ``microslip.periodic_orbit`` (its node arrays and ``orbit_state``).

The orbit has a node at every contact switch, so each node interval is smooth and an
8-point Gauss–Legendre rule per interval, evaluated on the quintic Hermite interpolant,
integrates smooth functions of (t, y, ẏ) to near round-off. The integrands (N, P ẏ, ...)
are written by the caller with the independent laws of ``forced_reference``.
"""

from __future__ import annotations

import numpy as np

_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(8)


def interval_states(orbit):
    """Gauss points (t [s], y [m], ẏ [m/s], weights [s]) over one period of ``orbit``."""
    from microslip.analysis.orbit_table import orbit_state

    tn = np.asarray(orbit.t, dtype=float)
    args = (tn, np.asarray(orbit.y), np.asarray(orbit.ydot))
    acc = (np.asarray(orbit.accel_start), np.asarray(orbit.accel_end))
    ts, ys, yds, ws = [], [], [], []
    for k in range(tn.size - 1):
        h = tn[k + 1] - tn[k]
        if h <= 0.0:
            continue
        for x, w in zip(_NODES, _WEIGHTS, strict=True):
            t = tn[k] + 0.5 * h * (x + 1.0)
            y, yd = orbit_state(t, *args, *acc)
            ts.append(t)
            ys.append(y)
            yds.append(yd)
            ws.append(0.5 * h * w)
    return np.array(ts), np.array(ys), np.array(yds), np.array(ws)


def orbit_average(orbit, integrand) -> float:
    """(1/T) ∫₀ᵀ integrand(t, y, ẏ) dt along the orbit."""
    ts, ys, yds, ws = interval_states(orbit)
    values = np.array([integrand(t, y, yd) for t, y, yd in zip(ts, ys, yds, strict=True)])
    return float(np.sum(values * ws) / orbit.period)
