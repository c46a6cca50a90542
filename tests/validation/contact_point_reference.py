"""An independent scipy reference for the compliant contact point under a known N(t).

Shares no code with ``microslip``: the caller writes out the normal force N(t), its rate
Ṅ(t), the tangential stiffness k_t(t) and a contact function (> 0 in contact) as plain
Python functions of time, from the physics (docs/theory/friction_reduction.md). The body
moves at a prescribed speed v > 0; the spring force f of the massless contact point obeys

    stick   ḟ = k_t v        until μ_s N - f falls through 0: f drops to μ_k N, then
                             slip if k_t v > μ_k Ṅ, else stick again;
    slip    f = μ_k N        (integrated as ḟ = μ_k Ṅ) until k_t v - μ_k Ṅ falls
                             through 0: stick;
    flight  f = 0            until the contact function rises through 0: stick with
                             f = 0, or slip at once if μ_s N(t+) = 0 and μ_s Ṅ < k_t v.

Each mode is integrated by scipy's DOP853 with terminal events (solve_ivp), restarted at
every switch and at every period boundary, with ∫f dt, ∫N dt and the stick time
integrated alongside. The event functions are offset by 1e-13 of their scales so that a
switch lying exactly at a segment's start is not found again. A stick also stops at each
minimum of its margin μ_s N - f: if the margin is negative there, it dipped below 0
between two steps (a graze, which a sign test misses) and the stick ends at the first
root, located by brentq on the segment's dense output.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

FLIGHT, STICK, SLIP = "flight", "stick", "slip"
_OFFSET = 1e-13
_MAX_SEGMENTS = 100_000


@dataclass
class ContactPoint:
    """The data of one reference problem (callables of t [s]; SI units)."""

    normal: object  # N(t) [N], >= 0
    normal_rate: object  # Ṅ(t) [N/s] (one-sided values are fine)
    stiffness: object  # k_t(t) [N/m] in contact
    contact: object  # > 0 in contact
    velocity: float  # v > 0 [m/s]
    mu_static: float
    mu_kinetic: float
    period: float  # T [s] of N(t)
    force_scale: float  # N scale [N] (tolerances, offsets)


def _rhs(problem: ContactPoint, mode: str):
    v, mu_k = problem.velocity, problem.mu_kinetic

    def rhs(t, z):
        if mode == FLIGHT:
            return [0.0, 0.0, 0.0, 0.0]
        n = problem.normal(t)
        if mode == STICK:
            return [problem.stiffness(t) * v, z[0], n, 1.0]
        return [mu_k * problem.normal_rate(t), mu_k * n, n, 0.0]

    return rhs


def _events(problem: ContactPoint, mode: str):
    v, mu_s, mu_k = problem.velocity, problem.mu_static, problem.mu_kinetic
    f_tol = _OFFSET * mu_s * problem.force_scale
    rate_tol = _OFFSET * mu_k * problem.force_scale / problem.period

    def lost(t, z):
        return problem.contact(t)

    def made(t, z):
        return problem.contact(t)

    def stick_ends(t, z):
        return mu_s * problem.normal(t) - z[0] + f_tol

    def slip_ends(t, z):
        return problem.stiffness(t) * v - mu_k * problem.normal_rate(t) + rate_tol

    def margin_minimum(t, z):  # the rate of μ_s N - f rises through 0
        return mu_s * problem.normal_rate(t) - problem.stiffness(t) * v

    events = ((lost, -1), (made, 1), (stick_ends, -1), (slip_ends, -1), (margin_minimum, 1))
    for event, direction in events:
        event.terminal, event.direction = True, direction
    if mode == FLIGHT:
        return [made]
    return [lost, stick_ends, margin_minimum] if mode == STICK else [lost, slip_ends]


def _after_touchdown(problem: ContactPoint, t: float) -> tuple[str, float]:
    later = t + 1e-9 * problem.period
    n = problem.normal(later)
    v, mu_s = problem.velocity, problem.mu_static
    if mu_s * n > 1e-9 * mu_s * problem.force_scale:
        return STICK, 0.0
    if mu_s * problem.normal_rate(later) >= problem.stiffness(later) * v:
        return STICK, 0.0
    return SLIP, problem.mu_kinetic * problem.normal(t)


def average(problem: ContactPoint, *, periods: int = 4, last: int = 1, rtol: float = 1e-12) -> dict:
    """Integrate ``periods`` periods from a sliding start; average over the ``last`` ones.

    Returns ``mu_eff`` = ∫f dt / ∫N dt, ``mean_force`` <f> [N], ``mean_normal`` <N> [N],
    ``stick_fraction`` [-] and the number of switches ``segments``.
    """
    v, mu_k = problem.velocity, problem.mu_kinetic
    scale = problem.force_scale
    atol = np.array([1e-14 * scale, 1e-14 * scale * problem.period] * 2)
    t = 0.0
    if problem.contact(1e-12 * problem.period) > 0.0:
        f = mu_k * problem.normal(0.0)
        mode = SLIP if problem.stiffness(0.0) * v > mu_k * problem.normal_rate(0.0) else STICK
    else:
        mode, f = FLIGHT, 0.0
    z = np.array([f, 0.0, 0.0, 0.0])
    marks = [z.copy()]
    boundary = 1
    segments = 0
    while boundary <= periods:
        segments += 1
        if segments > _MAX_SEGMENTS:
            raise RuntimeError("contact point reference: too many segments")
        end = boundary * problem.period
        sol = solve_ivp(
            _rhs(problem, mode), (t, end), z, method="DOP853", rtol=rtol, atol=atol,
            events=_events(problem, mode), dense_output=True,
        )  # fmt: skip
        if sol.status == 1:
            hit = next(i for i, times in enumerate(sol.t_events) if times.size)
            start = t
            t, z = sol.t_events[hit][0], sol.y_events[hit][0].copy()
            name = _events(problem, mode)[hit].__name__
            if name == "margin_minimum":

                def margin(s, sol=sol):
                    return problem.mu_static * problem.normal(s) - sol.sol(s)[0]

                if margin(t) >= 0.0:  # no graze: the stick goes on just past the minimum
                    t = min(t + 1e-9 * problem.period, end)
                    z = sol.sol(t).copy()
                    continue
                t = brentq(margin, start, t, xtol=1e-15 * problem.period)
                z = sol.sol(t).copy()
                name = "stick_ends"
            if name == "lost":
                mode, z[0] = FLIGHT, 0.0
            elif name == "made":
                mode, z[0] = _after_touchdown(problem, t)
            elif name == "stick_ends":
                z[0] = mu_k * problem.normal(t)
                slides = problem.stiffness(t) * v > mu_k * problem.normal_rate(t)
                mode = SLIP if slides else STICK
            else:
                mode, z[0] = STICK, mu_k * problem.normal(t)
            continue
        t, z = end, sol.y[:, -1].copy()
        marks.append(z.copy())
        boundary += 1
    span = (marks[-1] - marks[-1 - last]) / (last * problem.period)
    return {
        "mu_eff": span[1] / span[2],
        "mean_force": span[1],
        "mean_normal": span[2],
        "stick_fraction": span[3],
        "segments": segments,
    }
