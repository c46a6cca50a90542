"""An independent event-driven scipy reference for the slider model.

Used by the validation tests and by the benchmarks (``benchmarks/`` imports it). It
shares no code with ``microslip``: it reads only the raw fields of a parameter set
(m, g, S, c_n, m2, μ) and integrates eqs. (2.4)–(2.5) with scipy's DOP853 in the
natural scales of docs/model-facts.md, fact 7,

    η = y / y0,  τ = ω t,  ω = sqrt(g / y0),  ξ = x / y0,
    η'' = 1 − r(η),  ξ'' = s (F/(m g) − μ r(η)),  r(η) = max(η, 0)^m2,

so every state component is of order one and one absolute tolerance is a per-component
tolerance scaled by y0, y0 ω, y0, y0 ω in SI. The friction mode (s = ±1 sliding in
direction s, 0 stick) and the contact mode are fixed on each segment, whose right-hand
side is then smooth (analytic for m2 = 2, where r = η² is continued past η = 0), so
DOP853 keeps its order up to the switch. Every switch is a terminal event and the
integration restarts in the new mode there:

* contact → flight: η = 0 falling;  flight → contact: η = 0 rising;
* stick → slip: μ r(η) − |F|/(m g) = 0 falling (the stick margin μ|R| − |F| reaches 0);
  the slider then slides in the direction s = sgn F;
* slip → stick: s ξ' = 0 falling; the slider sticks if |F| <= μ|R| there (eq. 2.2),
  else it slides on in direction sgn F: a reversal when that is −s.

Event location by sign change misses a double crossing inside one step (scipy #9228).
Segments are therefore also split where the switching functions have their extrema: at
the top of the normal motion (η' = 0 rising: minimum of η and of the stick margin) and,
while sliding, where the net force s ξ'' rises through zero (μ r − s F/(m g) falls
through zero: minimum of the speed s ξ'). At a split every switching function is
checked; one that is past its root there crossed twice within a step, and its first
root is located (brentq) on a dense-output rerun of the segment. The stop event watches
s ξ' + 1e-15 rather than s ξ': right after a release the net force is zero to rounding
and s ξ' may dip to -1e-18 before rising, which must not count as a stop (this moves a
located stop by ~1e-15 in τ). Any sign of F and any initial state (y, ẏ, x, ẋ) are
supported.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

# Event kinds recorded by the reference.
CONTACT_LOST = "contact_lost"
CONTACT_MADE = "contact_made"
SLIP_START = "slip_start"
STICK_START = "stick_start"
REVERSAL = "reversal"
_STOP = "stop"  # the slider comes to rest: a stick start, a reversal, or it slides on
_SPLIT = "split"  # an extremum of a switching function (not a switch)

_STOP_OFFSET = 1e-15
_MAX_SEGMENTS = 400_000


@dataclass
class Reference:
    """Reference trajectory in SI units at the requested times, plus its switches."""

    t: np.ndarray
    y: np.ndarray
    ydot: np.ndarray
    x: np.ndarray
    xdot: np.ndarray
    event_t: list[float] = field(default_factory=list)
    event_kind: list[str] = field(default_factory=list)
    event_x: list[float] = field(default_factory=list)

    def events_of(self, kind: str) -> tuple[np.ndarray, np.ndarray]:
        """(times [s], x [m]) of the switches of one kind."""
        idx = [i for i, k in enumerate(self.event_kind) if k == kind]
        return np.array([self.event_t[i] for i in idx]), np.array([self.event_x[i] for i in idx])


def static_deflection(params) -> float:
    """y0 = (m g / (S c_n))^(1/m2) [m], closed form (docs/model-facts.md, fact 1)."""
    return (params.mass * params.g / (params.area * params.c_n)) ** (1.0 / params.m2)


def _sign(value: float) -> int:
    return 1 if value > 0.0 else (-1 if value < 0.0 else 0)


class _Model:
    def __init__(self, params, force: float) -> None:
        self.m2 = float(params.m2)
        self.mu = float(params.mu)
        self.y0 = static_deflection(params)
        self.omega = math.sqrt(params.g / self.y0)
        self.phi = force / (params.mass * params.g)  # F/(m g), signed

    def r(self, eta: float, contact: bool) -> float:
        if not contact:
            return 0.0
        if self.m2 == 2.0:
            return eta * eta
        return max(eta, 0.0) ** self.m2

    def margin(self, eta: float, contact: bool) -> float:
        """(μ|R| − |F|)/(m g) at normal position η in the given contact mode."""
        return self.mu * self.r(eta, contact) - abs(self.phi)

    def rhs(self, contact: bool, s: int):
        """Right-hand side in contact mode ``contact`` and friction mode ``s`` (±1, 0)."""
        phi, mu, m2 = self.phi, self.mu, self.m2
        smu = s * mu
        if contact and m2 == 2.0:
            if s:
                return lambda _t, u: (u[1], 1.0 - u[0] * u[0], u[3], phi - smu * u[0] * u[0])
            return lambda _t, u: (u[1], 1.0 - u[0] * u[0], 0.0, 0.0)
        if contact:

            def rhs(_t, u):
                r = max(u[0], 0.0) ** m2
                return (u[1], 1.0 - r, u[3], (phi - smu * r) if s else 0.0)

            return rhs
        if s:
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


@dataclass
class _Run:
    """Raw output of :func:`_integrate` in natural units."""

    tau: float
    u: np.ndarray
    sample_tau: list = field(default_factory=list)
    sample_u: list = field(default_factory=list)
    events: list = field(default_factory=list)  # (τ, kind, ξ)


def _initial_modes(model: _Model, u: np.ndarray) -> tuple[bool, int]:
    """(contact, friction mode) at an initial state: sgn ξ' when sliding, else (2.2)."""
    # η = 0 counts as contact only when the slider moves into it (or rests there,
    # where η'' = 1 pulls it in).
    contact = u[0] > 0.0 or (u[0] == 0.0 and u[1] >= 0.0)
    if u[3] != 0.0:
        return contact, _sign(u[3])
    if model.margin(u[0], contact) >= 0.0:
        return contact, 0
    return contact, _sign(model.phi)


def _integrate(
    model: _Model,
    u0: np.ndarray,
    tau_end: float,
    *,
    rtol: float,
    atol: float,
    tau_eval: np.ndarray | None = None,
    sticks_wanted: int | None = None,
) -> _Run:
    """Integrate from the natural state ``u0`` = (η, η', ξ, ξ') at τ = 0 to ``tau_end``.

    Stops early at the ``sticks_wanted``-th stick if given. Samples the state at
    ``tau_eval`` (sorted, within [0, tau_end]) and records every switch as (τ, kind, ξ).
    """
    u = np.array(u0, dtype=float)
    contact, s = _initial_modes(model, u)
    period = 2.0 * math.pi / math.sqrt(model.m2)  # small-amplitude normal period in τ
    tau = 0.0

    def net_force_margin(v):
        # μ r − s F/(m g): falls through zero where the sliding speed s ξ' is minimal.
        return model.mu * model.r(v[0], True) - s * model.phi

    # No splits just after a (re)start at a root of a split function: it would end the
    # segment at once. The paper's start, at rest at the top, is such a root (η' = 0).
    at_split_root = u[1] == 0.0 or (s != 0 and contact and net_force_margin(u) == 0.0)
    quiet_until = 0.1 * period if at_split_root else 0.0
    tau_eval = np.empty(0) if tau_eval is None else np.asarray(tau_eval, dtype=float)
    i_eval = 0
    run = _Run(tau, u)
    sticks = segments = 0

    def margin_in_contact(v):
        return model.margin(v[0], True)

    while tau < tau_end:
        events, kinds = [], []
        if contact:
            events.append(_event(lambda v: v[0], -1.0))
            kinds.append(CONTACT_LOST)
        else:
            events.append(_event(lambda v: v[0], +1.0))
            kinds.append(CONTACT_MADE)
        if s != 0:
            events.append(_event(lambda v, s=s: s * v[3] + _STOP_OFFSET, -1.0))
            kinds.append(_STOP)
        elif contact and model.phi != 0.0:
            events.append(_event(margin_in_contact, -1.0))
            kinds.append(SLIP_START)
        n_switching = len(events)
        t_bound = tau_end
        if tau >= quiet_until:
            events.append(_event(lambda v: v[1], +1.0))
            kinds.append(_SPLIT)
            if s != 0 and contact:
                events.append(_event(net_force_margin, -1.0))
                kinds.append(_SPLIT)
        else:
            t_bound = min(tau_end, quiet_until)
        rhs = model.rhs(contact, s)
        # Sliding from rest may last a very short time near the motion threshold: start
        # with a small step so that the speed's return to zero is bracketed, not skipped.
        first_step = min(1e-6, t_bound - tau) if s != 0 and u[3] == 0.0 else None
        segment_eval = tau_eval[i_eval:]
        segment_eval = segment_eval[segment_eval <= t_bound]
        # With t_eval, scipy returns only those points: add t_bound for the end state.
        ends_on_sample = segment_eval.size > 0 and segment_eval[-1] == t_bound
        points = segment_eval if ends_on_sample else np.append(segment_eval, t_bound)
        sol = solve_ivp(
            rhs, (tau, t_bound), u, method="DOP853", rtol=rtol, atol=atol, events=events,
            first_step=first_step, t_eval=points,
        )  # fmt: skip
        if sol.status < 0:
            raise RuntimeError(f"reference integration failed: {sol.message}")
        segments += 1
        if segments > _MAX_SEGMENTS:
            raise RuntimeError("reference integration: too many segments")
        n_samples = min(np.size(sol.t), segment_eval.size)  # a prefix of ``points``
        samples_tau = np.asarray(sol.t, dtype=float)[:n_samples]
        samples_u = np.asarray(sol.y, dtype=float).reshape(4, -1).T[:n_samples]
        if sol.status == 0:  # reached t_bound: no switch
            tau_new, u_new, kind = t_bound, sol.y[:, -1].copy(), None
        else:
            which = min(
                (k for k in range(len(events)) if sol.t_events[k].size),
                key=lambda k: sol.t_events[k][0],
            )
            tau_new = float(sol.t_events[which][0])
            u_new = np.array(sol.y_events[which][0], dtype=float)
            kind = kinds[which]
        if kind == _SPLIT:
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
                    rhs, (tau, tau_new), u, method="DOP853", rtol=rtol, atol=atol,
                    first_step=first_step, dense_output=True,
                )  # fmt: skip
                roots = [_root(events[k], dense.sol, tau, tau_new) for k in missed]
                first = int(np.argmin(roots))
                which = missed[first]
                tau_new = roots[first]
                u_new = dense.sol(tau_new)
                kind = kinds[which]
                keep = samples_tau <= tau_new  # later samples were taken in the old mode
                samples_tau, samples_u = samples_tau[keep], samples_u[keep]
        run.sample_tau.append(samples_tau)
        run.sample_u.append(samples_u)
        i_eval += samples_tau.size
        if kind is None:
            tau, u = tau_new, u_new
            continue
        if kind in (SLIP_START, _STOP) and tau_new <= tau:
            raise RuntimeError(f"reference integration: no progress at τ={tau!r} ({kind})")
        tau, u = tau_new, u_new
        if kind == _SPLIT:
            quiet_until = tau + 0.1 * period
            continue
        if kind == CONTACT_LOST:
            u[0] = 0.0
            contact = False
        elif kind == CONTACT_MADE:
            u[0] = 0.0
            contact = True
        elif kind == SLIP_START:
            s = _sign(model.phi)
            quiet_until = tau + 0.1 * period
        else:  # the slider has come to rest: stick if |F| <= μ|R| (eq. 2.2)
            u[3] = 0.0
            if model.margin(u[0], contact) >= 0.0:
                s = 0
                kind = STICK_START
            elif _sign(model.phi) != s:  # slides off the other way
                s = _sign(model.phi)
                kind = REVERSAL
                quiet_until = tau + 0.1 * period
            else:
                kind = None  # touches zero speed and slides on
        if kind is not None:
            run.events.append((tau, kind, float(u[2])))
        if s == 0 and model.margin(u[0], contact) < 0.0:  # e.g. contact lost while stuck
            s = _sign(model.phi)
            run.events.append((tau, SLIP_START, float(u[2])))
        if kind == STICK_START:
            sticks += 1
            if sticks_wanted is not None and sticks >= sticks_wanted:
                break
    run.tau, run.u = tau, u
    return run


def _top_state(model: _Model, amplitude: float) -> np.ndarray:
    """Natural state at rest at the top of the normal motion, y = y0 − A."""
    return np.array([1.0 - amplitude / model.y0, 0.0, 0.0, 0.0])


def reference_solution(
    params,
    *,
    force: float,
    amplitude: float | None = None,
    initial_state=None,
    t_eval,
    rtol: float = 1e-12,
    atol: float = 1e-14,
) -> Reference:
    """Solve (2.4)–(2.5) under the constant force ``force`` [N] and sample at ``t_eval`` [s].

    Start at rest at the top, y(0) = y0 − A (``amplitude`` A [m]), or from
    ``initial_state`` = (y [m], ẏ [m/s], x [m], ẋ [m/s]) at t = 0; give exactly one.
    ``t_eval`` is sorted. ``atol`` is in the natural units above (y0 for y and x, y0 ω
    for the velocities).
    """
    if (amplitude is None) == (initial_state is None):
        raise ValueError("give exactly one of amplitude or initial_state")
    model = _Model(params, force)
    y0, vel = model.y0, model.y0 * model.omega
    if amplitude is not None:
        u0 = _top_state(model, amplitude)
    else:
        y, ydot, x, xdot = (float(v) for v in initial_state)
        u0 = np.array([y / y0, ydot / vel, x / y0, xdot / vel])
    t_eval = np.asarray(t_eval, dtype=float)
    tau_eval = model.omega * t_eval
    run = _integrate(model, u0, float(tau_eval[-1]), rtol=rtol, atol=atol, tau_eval=tau_eval)
    t_out = np.concatenate(run.sample_tau) / model.omega
    u_out = np.concatenate(run.sample_u)
    if t_out.size != t_eval.size:
        raise RuntimeError("reference integration: lost output points")
    return Reference(
        t=t_out,
        y=u_out[:, 0] * y0,
        ydot=u_out[:, 1] * vel,
        x=u_out[:, 2] * y0,
        xdot=u_out[:, 3] * vel,
        event_t=[tau / model.omega for tau, _kind, _xi in run.events],
        event_kind=[kind for _tau, kind, _xi in run.events],
        event_x=[xi * y0 for _tau, _kind, xi in run.events],
    )


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
    (docs/model-facts.md, fact 6). The first stop still ends the slide that started at t = 0, at
    its own phase; from the first release on every cycle is the same, so the mean is
    Δx/Δt between the second and third stick starts (Δt = one normal period). 0 when
    the slider never moves (F <= μ S c_n max(y0 - A, 0)^m2); inf if it never sticks.
    ``atol`` defaults to 1e-3 rtol in the natural units.
    """
    model = _Model(params, force)
    atol = rtol * 1e-3 if atol is None else atol
    eta_top = 1.0 - amplitude / model.y0
    if model.margin(eta_top, eta_top >= 0.0) >= 0.0:
        return 0.0  # stuck at the top, where μ|R| is smallest: stuck for ever
    period_tau = 2.0 * math.pi / math.sqrt(model.m2)  # small-amplitude normal period
    run = _integrate(
        model,
        _top_state(model, amplitude),
        max_periods * period_tau,
        rtol=rtol,
        atol=atol,
        sticks_wanted=3,
    )
    sticks = [(tau, xi) for tau, kind, xi in run.events if kind == STICK_START]
    if len(sticks) < 3:
        return math.inf
    (t1, x1), (t2, x2) = sticks[1:3]
    return (x2 - x1) / (t2 - t1) * model.y0 * model.omega


def finite_time_mean_velocity(
    params,
    force: float,
    amplitude: float,
    duration: float,
    *,
    rtol: float = 1e-9,
    atol: float | None = None,
) -> float:
    """x(duration)/duration [m/s] from rest at the top (the time-domain job).

    ``atol`` defaults to 1e-3 rtol in the natural units.
    """
    model = _Model(params, force)
    atol = rtol * 1e-3 if atol is None else atol
    run = _integrate(
        model, _top_state(model, amplitude), duration * model.omega, rtol=rtol, atol=atol
    )
    return float(run.u[2]) * model.y0 / duration


def sliding_impulse(params, force: float, amplitude: float, t) -> np.ndarray:
    """∫₀ᵗ (F − μ|R(y)|)/m dt' [m/s] at the times ``t`` [s] (sorted, >= 0).

    The speed change of a slider that slides forward (s = +1) without stopping, the
    normal motion starting at rest at the top, y(0) = y0 − A. Used to build initial
    speeds whose sliding continuation just dips below zero.
    """
    model = _Model(params, force)
    t = np.asarray(t, dtype=float)
    u0 = _top_state(model, amplitude)
    contact = u0[0] >= 0.0
    if not contact or model.m2 != 2.0:
        raise ValueError("sliding_impulse: only m2 = 2 and a start in contact")
    sol = solve_ivp(
        model.rhs(True, 1), (0.0, model.omega * t[-1]), u0, method="DOP853", rtol=1e-13,
        atol=1e-15, t_eval=model.omega * t,
    )  # fmt: skip
    if sol.status != 0 or np.any(sol.y[0] <= 0.0):
        raise RuntimeError("sliding_impulse: the normal motion must stay in contact")
    return sol.y[3] * model.y0 * model.omega
