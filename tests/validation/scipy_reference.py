"""An independent reference integrator for the slider model, written for the tests.

It shares no code with ``microslip``: it reads only the raw fields of a parameter set
(m, g, S, c_n, m2, μ) and integrates eqs. (2.4)–(2.5) with scipy's DOP853 in the
natural scales of REFERENCE fact 7,

    η = y / y0,  τ = ω t,  ω = sqrt(g / y0),  ξ = x / y0,
    η'' = 1 − r(η),  ξ'' = s (F/(m g) − μ r(η)),  r(η) = max(η, 0)^m2,

(so every state component is of order one and a uniform atol is a per-component atol
scaled to y0, y0 ω, ... in SI). The friction mode s (1 slip, 0 stick) and the contact
mode are held fixed on each segment; every switch is a terminal scipy event and the
integration restarts in the new mode there:

* contact → flight: η = 0 falling;  flight → contact: η = 0 rising;
* stick → slip: μ|R| − F = 0 falling, i.e. μ r(η) − F/(m g) = 0;
* slip → stick: ẋ = 0 falling; the slider sticks if F <= μ|R| there (eq. 2.2).

Inside a segment the right-hand side is the smooth (analytic for m2 = 2) law of that
mode, so DOP853 keeps its order up to the switch. Only F >= 0 is supported (then the
slider never slides backwards, REFERENCE fact 5).

Limitation: like any sign-change event detection (scipy #9228) it can step over a dip of
μ|R| below F that starts and ends inside one step, so it is meant for forces well away
from the motion threshold (the tests use F = 0.5 N against thresholds <= 0.44 N).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

STICK, SLIP = 0, 1
FLIGHT, CONTACT = 0, 1

# Event kinds recorded by the reference.
CONTACT_LOST = "contact_lost"
CONTACT_MADE = "contact_made"
SLIP_START = "slip_start"
STICK_START = "stick_start"


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
    """y0 = (m g / (S c_n))^(1/m2) [m], closed form (REFERENCE fact 1)."""
    return (params.mass * params.g / (params.area * params.c_n)) ** (1.0 / params.m2)


def reference_solution(
    params,
    *,
    force: float,
    amplitude: float,
    t_eval,
    rtol: float = 1e-12,
    atol: float = 1e-14,
) -> Reference:
    """Solve from rest at the top, y(0) = y0 − A, and sample at ``t_eval`` [s] (sorted).

    ``atol`` is in the natural units above (y0 for y and x, y0 ω for the velocities).
    """
    if force < 0.0:
        raise ValueError("the reference supports force >= 0 only")
    m2 = float(params.m2)
    mu = float(params.mu)
    y0 = static_deflection(params)
    omega = math.sqrt(params.g / y0)
    phi = force / (params.mass * params.g)  # F/(m g)
    t_eval = np.asarray(t_eval, dtype=float)
    tau_eval = omega * t_eval
    tau_end = float(tau_eval[-1])

    if m2 == 2.0:

        def r_contact(eta):
            return eta * eta  # analytic continuation: smooth up to the located switch

    else:

        def r_contact(eta):
            return max(eta, 0.0) ** m2

    def rhs_factory(contact, slip):
        def rhs(_tau, u):
            r = r_contact(u[0]) if contact == CONTACT else 0.0
            return [u[1], 1.0 - r, u[3], (phi - mu * r) if slip == SLIP else 0.0]

        return rhs

    def margin(eta, contact):
        """(μ|R| − F)/(m g) at normal position η in the given contact mode."""
        r = r_contact(eta) if contact == CONTACT else 0.0
        return mu * r - phi

    def make_event(fun, direction):
        def event(_tau, u):
            return fun(u)

        event.terminal = True
        event.direction = direction
        return event

    # Initial state and modes: rest at the top of the normal vibration, x = ẋ = 0.
    eta = 1.0 - amplitude / y0
    u = np.array([eta, 0.0, 0.0, 0.0])
    contact = CONTACT if eta >= 0.0 else FLIGHT  # η = 0 at rest: η'' = 1 pulls into contact
    slip = STICK if margin(eta, contact) >= 0.0 else SLIP

    out_t, out_u = [], []
    ev_t, ev_kind, ev_x = [], [], []
    tau = 0.0
    i_eval = 0
    n_segments = 0
    while tau < tau_end:
        # Output times not yet written (one at a restart point was written by the segment
        # that ended there: scipy includes t_eval values up to the event time).
        segment_eval = tau_eval[i_eval:]
        events, kinds = [], []
        if contact == CONTACT:
            events.append(make_event(lambda u: u[0], -1.0))
            kinds.append(CONTACT_LOST)
        else:
            events.append(make_event(lambda u: u[0], +1.0))
            kinds.append(CONTACT_MADE)
        if slip == STICK and phi > 0.0 and contact == CONTACT:
            events.append(make_event(lambda u: margin(u[0], CONTACT), -1.0))
            kinds.append(SLIP_START)
        if slip == SLIP:
            events.append(make_event(lambda u: u[3], -1.0))
            kinds.append(STICK_START)
        # Sliding from rest may last a very short time near the motion threshold: start
        # with a small step so that the speed's return to zero is bracketed, not skipped.
        first_step = None
        if slip == SLIP and u[3] == 0.0:
            first_step = min(1e-6, tau_end - tau)
        sol = solve_ivp(
            rhs_factory(contact, slip),
            (tau, tau_end),
            u,
            method="DOP853",
            rtol=rtol,
            atol=atol,
            events=events,
            t_eval=segment_eval,
            first_step=first_step,
        )
        if sol.status < 0:
            raise RuntimeError(f"reference integration failed: {sol.message}")
        n_segments += 1
        if n_segments > 100_000:
            raise RuntimeError("reference integration: too many switches")
        t_seg = np.asarray(sol.t, dtype=float)
        if t_seg.size:
            out_t.append(t_seg)
            out_u.append(np.asarray(sol.y, dtype=float).T)
            i_eval += t_seg.size
        if sol.status == 0:  # reached tau_end
            break
        # The earliest terminal event ends the segment.
        which = min(
            (k for k in range(len(events)) if sol.t_events[k].size),
            key=lambda k: sol.t_events[k][0],
        )
        tau_new = float(sol.t_events[which][0])
        u = np.array(sol.y_events[which][0], dtype=float)
        kind = kinds[which]
        if tau_new <= tau and kind in (SLIP_START, STICK_START):
            raise RuntimeError(f"reference integration: no progress at τ={tau!r} ({kind})")
        tau = tau_new
        if kind == CONTACT_LOST:
            u[0] = 0.0
            contact = FLIGHT
        elif kind == CONTACT_MADE:
            u[0] = 0.0
            contact = CONTACT
        elif kind == SLIP_START:
            slip = SLIP
        else:  # the slider has come to rest: stick if F <= μ|R| (eq. 2.2)
            u[3] = 0.0
            if margin(u[0], contact) >= 0.0:
                slip = STICK
            else:
                kind = None  # touches zero speed and slides on
        if kind is not None:
            ev_t.append(tau / omega)
            ev_kind.append(kind)
            ev_x.append(u[2] * y0)
        if slip == STICK and margin(u[0], contact) < 0.0:  # e.g. contact lost while stuck
            slip = SLIP
            ev_t.append(tau / omega)
            ev_kind.append(SLIP_START)
            ev_x.append(u[2] * y0)

    t_out = np.concatenate(out_t) / omega
    u_out = np.concatenate(out_u)
    if t_out.size != t_eval.size:
        raise RuntimeError("reference integration: lost output points")
    vel = y0 * omega
    return Reference(
        t=t_out,
        y=u_out[:, 0] * y0,
        ydot=u_out[:, 1] * vel,
        x=u_out[:, 2] * y0,
        xdot=u_out[:, 3] * vel,
        event_t=ev_t,
        event_kind=ev_kind,
        event_x=ev_x,
    )
