"""Independent scipy reference for the slider on a damped and/or excited contact.

Shares no code with ``microslip``: it reads the raw numbers of a ``Model`` (m, g, S,
c_n, m2, μ; the damping's class name and ratio; the excitation's class name, amplitude
and frequency) and writes the equations out again, in the scales η = y/y0, ξ = x/y0,
τ = ω t with ω = sqrt(g/y0), y0 = (m g/(S c_n))^(1/m2):

    η'' = 1 + p(τ) - r,  e = η - ζ(τ),  r = N/(m g) = max(0, r_raw) while e > 0, else 0
    r_raw = e^m2 (elastic) | e^m2 + k e' (Kelvin–Voigt) | e^m2 (1 + k e') (Hunt–Crossley)
    k = c y0 ω/(m g), c = 2 ζ_d sqrt(K_n m), K_n = m2 m g/y0
    p = P0/(m g) sin(Ω τ) (harmonic force), ζ(τ) = Z/y0 sin(Ω τ) (base motion), Ω = 2πf/ω
    ξ'' = φ - s μ r while sliding in direction s (φ = F/(m g)); ξ' = 0 in stick while
    μ r >= |φ| (eq. 2.2)

The contact mode (contact iff e > 0 and r_raw > 0) and the friction mode are fixed on
each segment of scipy's DOP853 integration; every switch is a terminal event where the
integration restarts. The step is capped at 1/40 of the small-amplitude period so that
no double crossing hides inside one step for the cases tested.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

RTOL = 1e-12
ATOL = 1e-14


@dataclass
class Reference:
    """Samples at the requested times (SI) and the contact switches (SI)."""

    t: np.ndarray
    y: np.ndarray
    ydot: np.ndarray
    x: np.ndarray
    xdot: np.ndarray
    separations: list = field(default_factory=list)  # [s], contact -> flight
    touchdowns: list = field(default_factory=list)  # [s], flight -> contact


def _scales(model):
    p = model.params
    y0 = (p.mass * p.g / (p.area * p.c_n)) ** (1.0 / p.m2)
    omega = math.sqrt(p.g / y0)
    return y0, omega


def solve(model, *, force, state0, t_eval, max_segments=100_000) -> Reference:
    """Integrate from ``state0`` = (y, ẏ, x, ẋ) [SI] at t = 0 over ``t_eval`` [s]."""
    p = model.params
    y0, omega = _scales(model)
    mg = p.mass * p.g
    m2, mu, phi = p.m2, p.mu, force / mg
    kind = "none" if model.damping is None else type(model.damping).__name__
    k = 0.0
    if model.damping is not None:
        k_n = m2 * mg / y0
        c = 2.0 * model.damping.ratio * math.sqrt(k_n * p.mass)
        k = c * y0 * omega / mg
    exc = model.excitation
    ex_kind = "none" if exc is None else type(exc).__name__
    big_omega = 0.0 if exc is None else 2.0 * math.pi * exc.frequency / omega
    p0 = exc.amplitude / mg if ex_kind == "HarmonicForce" else 0.0
    z0 = exc.amplitude / y0 if ex_kind == "BaseMotion" else 0.0

    def surface(tau):
        s, co = math.sin(big_omega * tau), math.cos(big_omega * tau)
        return z0 * s, z0 * big_omega * co

    def r_raw(tau, u):
        zs, zsd = surface(tau)
        e, ed = u[0] - zs, u[1] - zsd
        el = max(e, 0.0) ** m2
        if kind == "Viscous":
            return el + k * ed
        if kind == "HuntCrossley":
            return el * (1.0 + k * ed)
        return el

    def gap(tau, u):
        return u[0] - surface(tau)[0]

    def limit_sign(tau, u):  # sign of r_raw as e -> 0+ (at a touchdown)
        ed = u[1] - surface(tau)[1]
        if kind == "Viscous":
            return k * ed
        if kind == "HuntCrossley":
            return 1.0 + k * ed
        return 1.0

    tau_eval = np.asarray(t_eval, dtype=float) * omega
    u = np.array(
        [state0[0] / y0, state0[1] / (y0 * omega), state0[2] / y0, state0[3] / (y0 * omega)]
    )
    tau = 0.0
    e0 = gap(0.0, u)
    contact = e0 > 0.0 and r_raw(0.0, u) > 0.0
    # Contact state: in contact, in flight inside the overlap (e > 0, r_raw <= 0), or
    # in flight outside it (e <= 0).
    where = "contact" if contact else ("over" if e0 > 0.0 else "out")
    r0 = r_raw(0.0, u) if contact else 0.0
    slide = 0.0 if u[3] == 0.0 and abs(phi) <= mu * r0 else (np.sign(u[3]) or np.sign(phi))
    out = np.empty((4, tau_eval.size))
    filled = 0
    seps, tds = [], []
    max_step = 2.0 * math.pi / math.sqrt(m2) / 40.0
    if big_omega > 0.0:
        max_step = min(max_step, 2.0 * math.pi / big_omega / 40.0)
    tau_end = tau_eval[-1]
    damped = kind != "none" and k > 0.0
    for _ in range(max_segments):
        if tau >= tau_end:
            break

        def rhs(tt, uu, contact=contact, slide=slide):
            r = max(r_raw(tt, uu), 0.0) if contact else 0.0
            pp = p0 * math.sin(big_omega * tt)
            return [uu[1], 1.0 + pp - r, uu[3], (phi - slide * mu * r) if slide else 0.0]

        events = []
        names = []

        def ev_gap(tt, uu):
            return gap(tt, uu)

        ev_gap.terminal, ev_gap.direction = True, (1.0 if where == "out" else -1.0)
        events.append(ev_gap)
        names.append("gap")
        if damped and where != "out":

            def ev_raw(tt, uu):
                return r_raw(tt, uu)

            ev_raw.terminal, ev_raw.direction = True, (-1.0 if contact else 1.0)
            events.append(ev_raw)
            names.append("raw")
        if slide:

            def ev_stop(tt, uu, slide=slide):
                return slide * uu[3]

            ev_stop.terminal, ev_stop.direction = True, -1.0
            events.append(ev_stop)
            names.append("stop")
        elif phi != 0.0:

            def ev_slip(tt, uu, contact=contact):
                r = max(r_raw(tt, uu), 0.0) if contact else 0.0
                return mu * r - abs(phi)

            ev_slip.terminal, ev_slip.direction = True, -1.0
            events.append(ev_slip)
            names.append("slip")
        sol = solve_ivp(rhs, (tau, tau_end), u, method="DOP853", rtol=RTOL, atol=ATOL,
                        events=events, dense_output=True, max_step=max_step)  # fmt: skip
        hit = None
        for j, te in enumerate(sol.t_events):
            if te.size and te[0] > tau and (hit is None or te[0] < hit[0]):
                hit = (te[0], j)
        tau_stop = sol.t[-1] if hit is None else hit[0]
        while filled < tau_eval.size and tau_eval[filled] <= tau_stop:
            out[:, filled] = sol.sol(tau_eval[filled])
            filled += 1
        if hit is None:
            u = sol.y[:, -1]
            tau = sol.t[-1]
            continue
        tau = hit[0]
        u = sol.sol(tau).copy()
        name = names[hit[1]]
        if name == "stop":
            u[3] = 0.0
            r = max(r_raw(tau, u), 0.0) if contact else 0.0
            slide = 0.0 if abs(phi) <= mu * r else np.sign(phi)
        elif name == "slip":
            slide = np.sign(phi)
        elif name == "gap" and where == "out":  # touchdown, or flight on into the overlap
            where = "contact" if limit_sign(tau, u) > 0.0 else "over"
        elif name == "gap":  # out of the overlap
            where = "out"
        elif where == "contact":  # N_raw reached 0 inside the overlap
            where = "over"
        else:  # N_raw back above 0 inside the overlap
            where = "contact"
        if (where == "contact") != contact:
            (tds if where == "contact" else seps).append(tau / omega)
        contact = where == "contact"
    else:
        raise RuntimeError("too many segments")
    return Reference(
        t=tau_eval / omega,
        y=out[0] * y0,
        ydot=out[1] * y0 * omega,
        x=out[2] * y0,
        xdot=out[3] * y0 * omega,
        separations=seps,
        touchdowns=tds,
    )
