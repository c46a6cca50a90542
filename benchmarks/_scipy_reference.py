"""An event-driven scipy reference for the mean sliding velocity (benchmarks only).

Independent of microslip's integrators: it reads the raw fields of a ``Parameters``
(m, g, S, c_n, m2, μ) and integrates eqs. (2.4)–(2.5) with ``solve_ivp`` in the natural
scales of REFERENCE fact 7,

    η = y/y0,  τ = ω t,  ω = sqrt(g/y0),  ξ = x/(μ y0),
    η'' = 1 - r(η),  ξ'' = s (φ - r(η)),  r(η) = max(η, 0)^m2,  φ = F/(μ m g),

so every state component is of order one and one absolute tolerance is a per-component
tolerance scaled by y0, y0 ω, μ y0, μ y0 ω in SI (default atol = 1e-3 rtol). The
friction mode (s = 1 slip, 0 stick) and the contact mode are fixed on each segment,
whose right-hand side is then smooth (analytic for m2 = 2, where r = η² is continued past
η = 0); every switch is a terminal event and the integration restarts in the new mode:

* contact → flight: η = 0 falling;  flight → contact: η = 0 rising;
* stick → slip: r(η) - φ = 0 falling (the stick margin μ|R| - F reaches 0);
* slip → stick: ξ' = 0 falling; then stick if F <= μ|R| (eq. 2.2), else slide on.

Event location by sign change misses a double crossing inside one step (scipy #9228).
Segments are therefore also split where the switching functions have their extrema: at
the top of the normal motion (η' = 0 rising: minimum of η and of the stick margin) and,
while sliding, where the margin falls through zero (minimum of the speed). At a split
every switching function is checked; one that is past its root there crossed twice
within a step, and its first root is located (brentq) on a dense-output rerun of the
segment. The stop event watches ξ' + 1e-14 rather than ξ': right after a release the
net force is zero to rounding and ξ' may dip to -1e-17 before rising, which must not
count as a stop (this moves a located stop by ~1e-14 in τ). Only F >= 0 is supported
(the slider then never slides backwards, REFERENCE fact 5).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

_STOP_OFFSET = 1e-14


class _Model:
    def __init__(self, params, force: float) -> None:
        if force < 0.0 or not params.mu > 0.0:
            raise ValueError("the reference supports force >= 0 and mu > 0 only")
        self.m2 = float(params.m2)
        self.y0 = (params.mass * params.g / (params.area * params.c_n)) ** (1.0 / self.m2)
        self.omega = math.sqrt(params.g / self.y0)
        self.mu = float(params.mu)
        self.phi = force / (self.mu * params.mass * params.g)
        self.tangential_scale = self.mu * self.y0  # x = μ y0 ξ [m]

    def r(self, eta: float, contact: bool) -> float:
        if not contact:
            return 0.0
        if self.m2 == 2.0:
            return eta * eta
        return max(eta, 0.0) ** self.m2

    def rhs(self, contact: bool, slip: bool):
        phi = self.phi
        if contact and self.m2 == 2.0:
            if slip:
                return lambda _t, u: (u[1], 1.0 - u[0] * u[0], u[3], phi - u[0] * u[0])
            return lambda _t, u: (u[1], 1.0 - u[0] * u[0], 0.0, 0.0)
        if contact:
            m2 = self.m2

            def rhs(_t, u):
                r = max(u[0], 0.0) ** m2
                return (u[1], 1.0 - r, u[3], (phi - r) if slip else 0.0)

            return rhs
        if slip:
            return lambda _t, u: (u[1], 1.0, u[3], phi)
        return lambda _t, u: (u[1], 1.0, 0.0, 0.0)


def _event(fun, direction: float):
    def event(_t, u):
        return fun(u)

    event.terminal = True
    event.direction = direction
    return event


def _root(event, interpolant, lo: float, hi: float) -> float:
    """Root of ``event`` along a dense-output interpolant, bracketed by [lo, hi]."""
    return brentq(
        lambda t: event(t, interpolant(t)), lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps
    )


def _integrate(
    model: _Model, amplitude: float, tau_end: float, sticks_wanted: int, rtol: float, atol: float
):
    """Integrate from rest at the top; stop at ``tau_end`` or at the n-th stick start.

    Returns (τ, ξ) at the end and the list of (τ, ξ) at each stick start.
    """
    eta = 1.0 - amplitude / model.y0
    u = np.array([eta, 0.0, 0.0, 0.0])
    contact = eta >= 0.0  # at η = 0, at rest, η'' = 1 pulls it into contact
    slip = model.r(eta, contact) - model.phi < 0.0
    period = 2.0 * math.pi / math.sqrt(model.m2)  # small-amplitude normal period in τ
    tau = 0.0
    quiet_until = 0.1 * period  # split events are off just after a restart at a root of one
    # (the start is the top of the normal motion)
    sticks: list[tuple[float, float]] = []
    segments = 0
    if model.m2 == 2.0:
        margin = lambda u: u[0] * u[0] - model.phi  # noqa: E731
    else:
        margin = lambda u: max(u[0], 0.0) ** model.m2 - model.phi  # noqa: E731
    while tau < tau_end:
        events, kinds = [], []
        if contact:
            events.append(_event(lambda u: u[0], -1.0))
            kinds.append("contact_lost")
        else:
            events.append(_event(lambda u: u[0], +1.0))
            kinds.append("contact_made")
        if slip:
            events.append(_event(lambda u: u[3] + _STOP_OFFSET, -1.0))
            kinds.append("stop")
        elif contact and model.phi > 0.0:
            events.append(_event(margin, -1.0))
            kinds.append("release")
        n_switching = len(events)
        # Splits that keep a double crossing out of any one segment (scipy only sees sign
        # changes between step ends): at the top of the normal motion (η' = 0 rising) the
        # gap η and the stick margin have their minima; while sliding, the speed has its
        # minimum where the margin falls through zero.
        t_bound = tau_end
        if tau >= quiet_until:
            events.append(_event(lambda u: u[1], +1.0))
            kinds.append("split")
            if slip and contact:
                events.append(_event(margin, -1.0))
                kinds.append("split")
        else:
            t_bound = min(tau_end, quiet_until)
        rhs = model.rhs(contact, slip)
        first_step = min(1e-6, t_bound - tau) if slip and u[3] == 0.0 else None
        sol = solve_ivp(
            rhs,
            (tau, t_bound),
            u,
            method="DOP853",
            rtol=rtol,
            atol=atol,
            events=events,
            first_step=first_step,
        )
        if sol.status < 0:
            raise RuntimeError(f"reference integration failed: {sol.message}")
        segments += 1
        if segments > 200_000:
            raise RuntimeError("reference integration: too many segments")
        if sol.status == 0:
            tau = t_bound
            u = sol.y[:, -1]
            continue
        which = min(
            (k for k in range(len(events)) if sol.t_events[k].size),
            key=lambda k: sol.t_events[k][0],
        )
        tau_new = float(sol.t_events[which][0])
        u_new = np.array(sol.y_events[which][0], dtype=float)
        kind = kinds[which]
        if kind == "split":
            # The segment ends at an extremum: a switching function that is past its
            # root here crossed twice within one step. Locate its first root.
            missed = [
                k
                for k in range(n_switching)
                if events[k].direction * (events[k](tau_new, u_new) - events[k](tau, u)) > 0.0
                and events[k](tau, u) * events[k](tau_new, u_new) < 0.0
            ]
            if missed:
                dense = solve_ivp(
                    rhs,
                    (tau, tau_new),
                    u,
                    method="DOP853",
                    rtol=rtol,
                    atol=atol,
                    first_step=first_step,
                    dense_output=True,
                )
                roots = [_root(events[k], dense.sol, tau, tau_new) for k in missed]
                first = int(np.argmin(roots))
                which = missed[first]
                tau_new = roots[first]
                u_new = dense.sol(tau_new)
                kind = kinds[which]
        tau, u = tau_new, u_new
        if kind == "split":
            quiet_until = tau + 0.1 * period
        elif kind == "contact_lost":
            u[0] = 0.0
            contact = False
            if not slip and model.phi > 0.0:  # nothing holds the slider in flight
                slip = True
        elif kind == "contact_made":
            u[0] = 0.0
            contact = True
        elif kind == "release":
            slip = True
            quiet_until = tau + 0.1 * period
        else:  # stop: the slider sticks if F <= μ|R| (eq. 2.2)
            u[3] = 0.0
            if model.r(u[0], contact) - model.phi >= 0.0:
                slip = False
                sticks.append((tau, float(u[2])))
                if len(sticks) >= sticks_wanted:
                    break
    return tau, float(u[2]), sticks


def steady_mean_velocity(
    params,
    force: float,
    amplitude: float,
    *,
    rtol: float = 1e-12,
    atol: float | None = None,
    max_periods: float = 12.0,
) -> float:
    """Long-time mean velocity [m/s] from the steady cycle.

    After its first stick the motion is periodic with one stick per normal period
    (REFERENCE fact 6). The first stop still ends the slide that started at t = 0, at
    its own phase; from the first release on every cycle is the same, so the mean is
    Δx/Δt between the second and third stick starts (Δt = one normal period). 0 when
    the slider never moves (F <= μ S c_n max(y0 - A, 0)^m2); inf if it never sticks.
    """
    model = _Model(params, force)
    atol = rtol * 1e-3 if atol is None else atol
    eta_top = 1.0 - amplitude / model.y0
    if model.r(eta_top, eta_top >= 0.0) - model.phi >= 0.0:
        return 0.0  # stuck at the top, where μ|R| is smallest: stuck for ever
    period_tau = 2.0 * math.pi / math.sqrt(model.m2)  # small-amplitude normal period
    _tau, _xi, sticks = _integrate(model, amplitude, max_periods * period_tau, 3, rtol, atol)
    if len(sticks) < 3:
        return math.inf
    (t1, x1), (t2, x2) = sticks[1:3]
    return (x2 - x1) / (t2 - t1) * model.tangential_scale * model.omega


def finite_time_mean_velocity(
    params,
    force: float,
    amplitude: float,
    duration: float,
    *,
    rtol: float = 1e-9,
    atol: float | None = None,
) -> float:
    """x(duration)/duration [m/s] from rest at the top (the time-domain job)."""
    model = _Model(params, force)
    atol = rtol * 1e-3 if atol is None else atol
    tau_end = duration * model.omega
    _tau, xi, _sticks = _integrate(model, amplitude, tau_end, 10**9, rtol, atol)
    return xi * model.tangential_scale / duration
