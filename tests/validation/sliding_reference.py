"""An independent scipy reference of the whole system: the forced normal motion with sliding.

Shares no law with ``microslip``. The normal motion is ``forced_reference.NormalReference``
(its scaled law, contact indicator and step cap), or any object with the same small
interface (``dim``, ``normal_rhs``, ``load``, ``indicator``, ``in_contact``, ``max_step``,
``rtol``, ``atol``), such as :class:`KinematicLoad`, a normal force known in closed
form. The tangential motion (rigid tangential contact, Coulomb friction, constant F,
eqs. 2.2 and 2.5) adds ξ = x/y0 in the same scales (τ = ω t, ω = sqrt(g/y0)):

    ξ'' = φ − s μ r   while sliding in direction s (φ = F/(m g), r = N/(m g)),
    ξ' = 0            in stick, while μ r >= |φ|.

Contact and friction modes are fixed on each segment of scipy's DOP853 integration and
every switch is a terminal event where the integration restarts: the contact indicator
(touchdown, lift-off, separation where N_raw reaches 0), stick→slip (μ r falls to |φ|)
and slip→stop (ξ' reaches 0).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy_reference import Reference

_MAX_SEGMENTS = 200_000
_STOP_OFFSET = 1e-15  # a release leaves ξ' = −1e-18 by rounding: not a stop


@dataclass
class Run:
    """One integration in scaled variables: samples at the requested τ and the switches."""

    tau: np.ndarray
    samples: np.ndarray  # (normal dim + 2, len(tau))
    sticks: list = field(default_factory=list)  # (τ, ξ) at each stick start
    releases: list = field(default_factory=list)  # τ of each stick→slip
    separations: list = field(default_factory=list)  # τ, contact → flight
    touchdowns: list = field(default_factory=list)  # τ, flight → contact


class KinematicLoad:
    """A normal force r(τ) = N/(m g) known in closed form (no normal state), for
    :class:`SlidingReference`; ``max_step`` keeps a release inside one step."""

    dim = 0
    indicator = None

    def __init__(self, load, *, mass, g, mu, max_step, rtol=1e-12, atol=1e-14) -> None:
        self._load = load
        self.m, self.g, self.mu = mass, g, mu
        self.max_step, self.rtol, self.atol = max_step, rtol, atol

    def normal_rhs(self, tau, v, contact):
        return []

    def load(self, tau, v, contact):
        return max(0.0, self._load(tau))

    def in_contact(self, tau, v):
        return True


class SlidingReference:
    """Normal + tangential motion, every switch located: state (normal..., ξ, ξ')."""

    def __init__(self, normal, force: float) -> None:
        self.n = normal
        self.phi = force / (normal.m * normal.g)
        self.mu = normal.mu

    def integrate(self, state0, tau1: float, tau_eval=()) -> Run:
        """From the scaled state (normal..., ξ, ξ') at τ = 0 to τ1; samples at ``tau_eval``."""
        n, phi, mu = self.n, self.phi, self.mu
        m = n.dim
        u = np.array(state0, dtype=float)
        tau_eval = np.asarray(tau_eval, dtype=float)
        run = Run(tau=tau_eval, samples=np.empty((m + 2, tau_eval.size)))
        filled = 0
        tau = 0.0
        contact = n.in_contact(tau, u)
        slide = float(np.sign(u[m + 1]))
        if slide == 0.0 and abs(phi) > mu * n.load(tau, u, contact):
            slide = float(np.sign(phi))
        for _ in range(_MAX_SEGMENTS):
            if tau >= tau1:
                break

            def f(t, v, contact=contact, slide=slide):
                r = n.load(t, v, contact)
                acc = phi - slide * mu * r if slide else 0.0
                return [*n.normal_rhs(t, v, contact), v[m + 1], acc]

            events, kinds = [], []
            if n.indicator is not None:

                def switch(t, v):
                    return n.indicator(t, v)

                switch.terminal, switch.direction = True, -1.0 if contact else 1.0
                events.append(switch)
                kinds.append("contact")
            if slide:

                def stop(t, v, slide=slide):
                    return slide * v[m + 1] + _STOP_OFFSET

                stop.terminal, stop.direction = True, -1.0
                events.append(stop)
                kinds.append("stop")
            elif phi != 0.0:

                def release(t, v, contact=contact):
                    return mu * n.load(t, v, contact) - abs(phi)

                release.terminal, release.direction = True, -1.0
                events.append(release)
                kinds.append("release")
            sol = solve_ivp(
                f, (tau, tau1), u, method="DOP853", rtol=n.rtol, atol=n.atol, events=events,
                max_step=n.max_step, dense_output=tau_eval.size > filled,
            )  # fmt: skip
            if sol.status < 0:
                raise RuntimeError(f"sliding reference failed: {sol.message}")
            hits = [j for j in range(len(events)) if sol.t_events[j].size]
            which = min(hits, key=lambda j: sol.t_events[j][0]) if hits else None
            tau_new = float(sol.t[-1]) if which is None else float(sol.t_events[which][0])
            while filled < tau_eval.size and tau_eval[filled] <= tau_new:
                run.samples[:, filled] = sol.sol(tau_eval[filled])
                filled += 1
            tau = tau_new
            if which is None:
                u = sol.y[:, -1].copy()
                continue
            u = np.array(sol.y_events[which][0], dtype=float)
            kind = kinds[which]
            if kind == "contact":
                contact = not contact
                (run.touchdowns if contact else run.separations).append(tau)
                if not slide and abs(phi) > mu * n.load(tau, u, contact):
                    slide = float(np.sign(phi))
                    run.releases.append(tau)
            elif kind == "release":
                slide = float(np.sign(phi))
                run.releases.append(tau)
            else:
                u[m + 1] = 0.0
                if abs(phi) <= mu * n.load(tau, u, contact):
                    slide = 0.0
                    run.sticks.append((tau, float(u[m])))
                else:
                    slide = float(np.sign(phi))
        else:
            raise RuntimeError("sliding reference: too many segments")
        return run

    def run(self, u0, tau1: float) -> list[tuple[float, str, float]]:
        """From the normal state u0 with the slider at rest; the stick starts (τ, kind, ξ)."""
        sticks = self.integrate([*u0[: self.n.dim], 0.0, 0.0], tau1).sticks
        return [(t, "stick", x) for t, x in sticks]

    def mean_velocity(self, u_periodic, periods: int = 6) -> float:
        """Steady mean velocity [m/s] from a periodic normal state at τ = 0: Δξ/Δτ between
        the second stick start and the last one a whole number of periods later."""
        n = self.n
        sticks = self.run(u_periodic, periods * n.period_tau)
        if len(sticks) < 3:
            raise RuntimeError(f"sliding reference: only {len(sticks)} sticks")
        t_a, _, x_a = sticks[1]
        for t_b, _, x_b in reversed(sticks[2:]):
            whole = (t_b - t_a) / n.period_tau
            if abs(whole - round(whole)) < 1e-6 and round(whole) >= 1:
                return (x_b - x_a) / (t_b - t_a) * n.y0 * n.omega
        raise RuntimeError("sliding reference: sticks not periodic")

    def window_mean_velocity(self, state0, tau_a: float, tau_b: float) -> tuple[float, int]:
        """(ξ(τb) − ξ(τa))/(τb − τa) from the scaled state0 at τ = 0 (scaled), and the
        number of releases in [τa, τb)."""
        run = self.integrate(state0, tau_b, [tau_a, tau_b])
        xi = run.samples[self.n.dim]
        releases = sum(1 for t in run.releases if tau_a <= t < tau_b)
        return (xi[1] - xi[0]) / (tau_b - tau_a), releases


def solve(model, *, force: float, state0, t_eval) -> Reference:
    """Integrate ``model`` under the force F [N] from state0 = (y, ẏ, x, ẋ) [SI] at t = 0;
    samples at ``t_eval`` [s] (increasing) and the contact switches (``events_of``
    "contact_lost" / "contact_made", times [s])."""
    from forced_reference import NormalReference

    normal = NormalReference(model)
    y0, w = normal.y0, normal.omega
    scaled = [state0[0] / y0, state0[1] / (y0 * w), state0[2] / y0, state0[3] / (y0 * w)]
    tau_eval = np.asarray(t_eval, dtype=float) * w
    run = SlidingReference(normal, force).integrate(scaled, float(tau_eval[-1]), tau_eval)
    s = run.samples
    return Reference(
        t=tau_eval / w,
        y=s[0] * y0,
        ydot=s[1] * y0 * w,
        x=s[2] * y0,
        xdot=s[3] * y0 * w,
        event_t=[t / w for t in run.separations + run.touchdowns],
        event_kind=["contact_lost"] * len(run.separations) + ["contact_made"] * len(run.touchdowns),
        event_x=[float("nan")] * (len(run.separations) + len(run.touchdowns)),
    )


def kinematic_mean_velocity(load, period: float, *, force: float, mass, g, mu, skip, measure):
    """Mean velocity [m/s] and releases under a normal force N(t) [N] known in closed form,
    averaged over periods skip..skip+measure (scales t/T, x/(g T²))."""
    normal = KinematicLoad(
        lambda s: load(s * period) / (mass * g), mass=mass, g=g, mu=mu, max_step=1.0 / 50.0,
        atol=1e-15,
    )  # fmt: skip
    value, releases = SlidingReference(normal, force).window_mean_velocity(
        [0.0, 0.0], float(skip), float(skip + measure)
    )
    return value * g * period, releases
