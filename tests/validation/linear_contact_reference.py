"""Closed form of the undamped free vibration on a linear contact (m2 = 1), for the
tests of the normal tape: harmonic about y0 in contact, ω² = g/y0, free fall in flight.
Shares no code with microslip."""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq


def normal_force(params, amplitude):
    """(N(t) [N] for t >= 0, period T [s], t_loss [s]) of the body released at rest at
    y0 - A (A = ``amplitude`` [m]). For A <= y0 it stays in contact (N = m g (1 - (A/y0)
    cos ωt), T = 2π/ω, t_loss = inf); for A > y0 it falls freely to δ = 0, moves
    harmonically about y0 until it leaves the contact at t_loss, and rises freely back to
    the top: T = t_loss + t_touch."""
    y0, g = params.static_deflection, params.g
    weight = params.mass * g
    omega = np.sqrt(g / y0)
    if amplitude <= y0:

        def contact_force(t):
            return weight * (1.0 - amplitude / y0 * np.cos(omega * np.asarray(t)))

        return contact_force, 2.0 * np.pi / omega, np.inf
    t_touch = np.sqrt(2.0 * (amplitude - y0) / g)
    v_touch = g * t_touch

    def y_contact(s):
        return y0 - y0 * np.cos(omega * s) + v_touch / omega * np.sin(omega * s)

    # xtol: brentq's default (2e-12, absolute) is ~1e-5 of this time scale.
    s_loss = brentq(y_contact, np.pi / omega, 2.0 * np.pi / omega, xtol=1e-16 / omega)
    period = 2.0 * t_touch + s_loss

    def force(t):
        s = np.mod(np.asarray(t), period) - t_touch
        inside = (s > 0.0) & (s < s_loss)
        return np.where(inside, weight / y0 * np.maximum(y_contact(s), 0.0), 0.0)

    return force, period, t_touch + s_loss
