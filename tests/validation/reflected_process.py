"""Independent steady stick–slip cycle from the reflected process (any m2, A > y0 too).

Shares no code with ``microslip``. Under a constant force F >= 0 with Coulomb friction
and a rigid tangential contact, eqs. (2.2) and (2.5) make the slider velocity the
reflected process of the free drift

    G(t) = ∫0^t (F − μ|R(s)|)/m ds,   ẋ(t) = G(t) − min_{s <= t} G(s),

for any normal motion (|R| = S c_n max(y, 0)^m2, eq. 2.3). The normal motion (2.4) is
integrated here with scipy's DOP853 over one period of the free vibration, in the
natural scales η = y/y0, τ = ω t, ω = sqrt(g/y0), with G and its integral
I(τ) = ∫0^τ G as extra states:

    η'' = 1 − r(η),  G' = φ − μ r(η),  I' = G,   r = max(η, 0)^m2,  φ = F/(m g),

split at every contact switch (η = 0), at the bottom (η' = 0) and at the top, so that
every segment has a smooth right-hand side. The extrema of G (μ r = φ) are located as
solver events, not from a closed-form release height. Beyond one period the normal
motion repeats, so G(τ + kT) = G(τ) + k G(T) and I follows by integrating that.
The reflected process is then walked event by event: stuck while G falls (the running
minimum follows it), released at a local minimum of G, stopped where G comes back down
to its level at release (brentq on the dense output). Slip distance, slip time and
peak speed of a cycle follow from I and G at the located instants. From the first stop
on, the cycle is periodic (docs/model-facts.md, fact 6); the second slip is returned.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

_EPS = float(np.finfo(float).eps)


@dataclass(frozen=True)
class Cycle:
    """A steady cycle in SI units (NaN fields and zero mean without motion)."""

    period: float  # normal period T [s]
    slip_time: float  # [s]
    slip_distance: float  # [m]
    peak_velocity: float  # [m/s]
    mean_velocity: float  # slip distance / T [m/s]
    release_time: float  # release instant after a top of the normal motion, mod T [s]
    repeat_error: float  # |second slip − third slip| / second slip (periodicity check)


def _terminal(fun, direction):
    def event(_t, u):
        return fun(u)

    event.terminal = True
    event.direction = direction
    return event


def _marker(fun):
    def event(_t, u):
        return fun(u)

    event.terminal = False
    event.direction = 0.0
    return event


class _Orbit:
    """One period of (η, η', G, I) from the top, as dense-output pieces."""

    def __init__(self, params, force: float, amplitude: float, rtol: float, atol: float):
        m2 = float(params.m2)
        mu = float(params.mu)
        self.y0 = (params.mass * params.g / (params.area * params.c_n)) ** (1.0 / m2)
        self.omega = math.sqrt(params.g / self.y0)
        phi = force / (params.mass * params.g)
        self.pieces: list[tuple[float, float, object]] = []
        self.extrema: list[tuple[float, float]] = []  # (τ, sign of G'' there): +1 minimum

        def rhs_contact(_t, u):
            r = max(u[0], 0.0) ** m2
            return (u[1], 1.0 - r, phi - mu * r, u[2])

        def rhs_flight(_t, u):
            return (u[1], 1.0, phi, u[2])

        def drift(u, contact):
            return phi - mu * (max(u[0], 0.0) ** m2 if contact else 0.0)

        u = np.array([1.0 - amplitude / self.y0, 0.0, 0.0, 0.0])
        contact = u[0] >= 0.0  # at η = 0 at rest, η'' = 1 pulls it into contact
        descending = True  # from the top to the bottom, then back up
        tau = 0.0
        for _ in range(8):
            events = [
                _terminal(lambda v: v[0], -1.0 if contact else 1.0),
                _terminal(lambda v: v[1], -1.0 if descending else 1.0),
            ]
            if contact:
                events.append(_marker(lambda v: drift(v, True)))
            sol = solve_ivp(
                rhs_contact if contact else rhs_flight,
                (tau, tau + 1e3),
                u,
                method="DOP853",
                rtol=rtol,
                atol=atol,
                events=events,
                dense_output=True,
            )
            if sol.status != 1:
                raise RuntimeError(f"orbit integration did not reach a switch: {sol.message}")
            end = min(float(sol.t_events[k][0]) for k in (0, 1) if sol.t_events[k].size)
            self.pieces.append((tau, end, sol.sol))
            if contact:
                for t_root in sol.t_events[2]:
                    if tau < t_root < end:
                        # G' = φ − μ r(η) rises through 0 (a minimum of G) while r falls
                        self.extrema.append((float(t_root), 1.0 if not descending else -1.0))
            u = sol.sol(end)
            tau = end
            if sol.t_events[0].size and float(sol.t_events[0][0]) == end:
                u[0] = 0.0
                contact = not contact
            else:
                u[1] = 0.0
                if not descending:
                    break
                descending = False
        else:
            raise RuntimeError("orbit integration: too many segments")
        self.period = tau
        self.g_period = float(u[2])
        self.i_period = float(u[3])
        self.slides_at_top = drift(np.array([1.0 - amplitude / self.y0]), True) > 0.0
        self.extrema.sort()

    def _piece(self, tau: float):
        for a, b, sol in self.pieces:
            if a <= tau <= b:
                return sol
        raise ValueError(tau)

    def state(self, tau: float) -> tuple[float, float]:
        """(G, I) at any τ >= 0 (natural units)."""
        k = math.floor(tau / self.period)
        s = tau - k * self.period
        if s > self.period:  # rounding
            s = self.period
        g, i = self._piece(s)(s)[2:4]
        big_g = g + k * self.g_period
        big_i = k * self.i_period + self.g_period * self.period * k * (k - 1) / 2.0
        big_i += i + k * self.g_period * s
        return float(big_g), float(big_i)

    def extrema_after(self, tau: float):
        """Extrema of G after τ, in time order, as (τ, +1 min / −1 max)."""
        k = math.floor(tau / self.period)
        while True:
            for t_root, kind in self.extrema:
                t = t_root + k * self.period
                if t > tau:
                    yield t, kind
            k += 1


def reflected_cycle(
    params, *, force: float, amplitude: float, rtol: float = 1e-13, atol: float = 1e-16
) -> Cycle:
    """The steady cycle at constant force F [N] and amplitude A [m], 0 <= F < μ m g.

    ``atol`` is in the natural units (y0 for positions, y0 ω for speeds).
    """
    orbit = _Orbit(params, force, amplitude, rtol, atol)
    y0, omega = orbit.y0, orbit.omega
    period = orbit.period / omega
    if not orbit.extrema:
        nan = math.nan
        return Cycle(period, 0.0, 0.0, 0.0, 0.0, nan, 0.0)

    def g_at(t):
        return orbit.state(t)[0]

    # The walk: the slider starts at rest at the top (τ = 0). If G rises from 0 it slides
    # at once with level 0; otherwise it first sticks until G's next minimum.
    slips = []
    release, level = (0.0, 0.0) if orbit.slides_at_top else (None, None)
    cursor = 0.0
    extrema = orbit.extrema_after(0.0)
    for t_ext, kind in extrema:
        if t_ext > 50.0 * orbit.period:  # F < μ m g sticks within a period or two
            raise RuntimeError("reflected process: no steady cycle within 50 periods")
        if release is None:
            if kind > 0:
                release, level = t_ext, g_at(t_ext)
            cursor = t_ext
            continue
        if kind > 0 and g_at(t_ext) < level:
            # G fell below its level at release before this minimum: the slider stopped
            # in (cursor, t_ext), at the last crossing of the level on the falling branch.
            stop = brentq(
                lambda t, lv=level: g_at(t) - lv, cursor, t_ext, xtol=1e-15, rtol=4 * _EPS
            )
            g_r, i_r = orbit.state(release)
            _g_s, i_s = orbit.state(stop)
            peak = max(g_at(t) for t, _ in _maxima_between(orbit, release, stop)) - level
            slips.append((release, stop, i_s - i_r - g_r * (stop - release), peak))
            if len(slips) == 3:
                break
            release, level = t_ext, g_at(t_ext)
        cursor = t_ext
    (r1, s1, d1, p1), (_r2, _s2, d2, _p2) = slips[1], slips[2]
    distance = d1 * y0
    return Cycle(
        period=period,
        slip_time=(s1 - r1) / omega,
        slip_distance=distance,
        peak_velocity=p1 * y0 * omega,
        mean_velocity=distance / period,
        release_time=(r1 % orbit.period) / omega,
        repeat_error=abs(d2 - d1) / d1,
    )


def _maxima_between(orbit: _Orbit, lo: float, hi: float):
    for t, kind in orbit.extrema_after(lo):
        if t >= hi:
            return
        if kind < 0:
            yield t, kind
