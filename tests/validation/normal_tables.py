"""Independent node tables of periodic normal motions, from scipy's DOP853 (test helper).

Shares no code with ``microslip``. The normal motion m ÿ = m g + P0 sin(2π f t) - N,
N = max(0, S c_n y^m2 + c ẏ) while y > 0 (Kelvin–Voigt damping by its working-point ratio
ζ, c = 2 ζ sqrt(K_n m), K_n = m2 m g / y0), is integrated in the natural scales
η = y/y0, τ = ω t, ω = sqrt(g/y0):

    η'' = 1 + (P0/(m g)) sin(Ω τ) - n,   n = max(0, η^m2 + 2 ζ sqrt(m2) η'),  Ω = 2π f/ω.

A periodic orbit is found by integrating from rest at y0 and Newton shooting with a
finite-difference Jacobian. Tables hold one period at equally spaced nodes: t [s],
y [m], ẏ [m/s] and ÿ [m/s^2] (the contact must hold all along: checked).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

RTOL = 1e-13
ATOL = 1e-15


class Normal:
    """The scaled normal equation of one contact (SI inputs)."""

    def __init__(self, params, *, zeta=0.0, force_amplitude=0.0, frequency=None):
        self.m2 = params.m2
        self.y0 = (params.mass * params.g / (params.area * params.c_n)) ** (1.0 / params.m2)
        self.omega = math.sqrt(params.g / self.y0)
        self.mass, self.g = params.mass, params.g
        self.damping = 2.0 * zeta * math.sqrt(params.m2)
        self.load = force_amplitude / (params.mass * params.g)
        self.big_omega = 0.0 if frequency is None else 2.0 * math.pi * frequency / self.omega

    def n(self, tau, eta, deta):
        if eta <= 0.0:
            return 0.0
        return max(0.0, eta**self.m2 + self.damping * deta)

    def rhs(self, tau, u):
        return (u[1], 1.0 + self.load * math.sin(self.big_omega * tau) - self.n(tau, *u))

    def solve(self, u0, tau_end, **kwargs):
        return solve_ivp(
            self.rhs, (0.0, tau_end), u0, method="DOP853", rtol=RTOL, atol=ATOL, **kwargs
        )

    def table(self, u0, tau_period, intervals):
        """Node arrays (t, y, ẏ, ÿ) in SI over one period from the scaled state u0."""
        tau = np.linspace(0.0, tau_period, intervals + 1)
        sol = self.solve(u0, tau_period, dense_output=True)
        states = sol.sol(tau)
        states[:, 0] = u0
        accel = np.array([self.rhs(tt, states[:, i])[1] for i, tt in enumerate(tau)])
        contact = [self.n(tt, *states[:, i]) for i, tt in enumerate(tau)]
        assert min(contact) > 0.0, "table helper needs permanent contact"
        w = self.omega
        return (
            tau / w,
            states[0] * self.y0,
            states[1] * self.y0 * w,
            accel * self.y0 * w * w,
        )


def free_vibration_table(params, amplitude, intervals=1024):
    """The paper's free vibration from the top y0 - A (rest), one period (A < y0)."""
    normal = Normal(params)
    u0 = np.array([1.0 - amplitude / normal.y0, 0.0])

    def bottom(tau, u):
        return u[1]

    bottom.direction = -1.0  # the free vibration is symmetric about its lowest point
    bottom.terminal = True
    sol = normal.solve(u0, 100.0, events=bottom)
    tau_period = 2.0 * float(sol.t_events[0][-1])
    return normal.table(u0, tau_period, intervals)


def forced_orbit(params, *, zeta, force_amplitude, frequency, transient_periods=200):
    """Scaled periodic state at τ = 0 and the scaled period, by shooting from rest at y0."""
    normal = Normal(params, zeta=zeta, force_amplitude=force_amplitude, frequency=frequency)
    tau_period = 2.0 * math.pi / normal.big_omega
    u = normal.solve([1.0, 0.0], transient_periods * tau_period).y[:, -1]
    for _ in range(20):
        end = normal.solve(u, tau_period).y[:, -1]
        jac = np.empty((2, 2))
        for i in range(2):
            du = np.zeros(2)
            du[i] = 1e-7
            jac[:, i] = (normal.solve(u + du, tau_period).y[:, -1] - end) / 1e-7
        step = np.linalg.solve(jac - np.eye(2), -(end - u))
        u = u + step
        if np.max(np.abs(step)) < 1e-14:
            break
    return normal, u, tau_period


def forced_table(params, *, zeta, force_amplitude, frequency, intervals=512):
    normal, u, tau_period = forced_orbit(
        params, zeta=zeta, force_amplitude=force_amplitude, frequency=frequency
    )
    return normal.table(u, tau_period, intervals)


def event_driven_mean_velocity(
    normal_rhs, load, u0, period, *, phi, mu, skip, measure, atol, rtol=1e-12, max_step=None
):
    """Mean tangential speed by integrating the whole system, every stick and slip located.

    State (u..., x, ẋ): the normal state u evolves by ``normal_rhs(t, u)``; the friction
    limit is μ ``load(t, u)`` against the drive ``phi`` (same units as ``load``; ẍ =
    phi - μ load while sliding). Sticks when ẋ falls to 0, slides when phi > μ load.
    Returns (x(t_b) - x(t_a))/(t_b - t_a) with t_a = skip T, t_b = (skip + measure) T,
    and the number of releases in [t_a, t_b). ``max_step`` (default T/50) keeps the
    solver from stepping over a sign change of the release function while stuck.
    """
    max_step = period / 50.0 if max_step is None else max_step
    t_a, t_b = skip * period, (skip + measure) * period
    m = len(u0)

    def stick(t, z):
        return (*normal_rhs(t, z[:m]), 0.0, 0.0)

    def slip(t, z):
        return (*normal_rhs(t, z[:m]), z[m + 1], phi - mu * load(t, z[:m]))

    def release(t, z):
        return phi - mu * load(t, z[:m])

    release.direction, release.terminal = 1.0, True

    def stop(t, z):
        return z[m + 1]

    stop.direction, stop.terminal = -1.0, True
    z = np.array([*u0, 0.0, 0.0])
    t = 0.0
    sliding = release(0.0, z) > 0.0
    x_at = {}
    releases = 0
    while t < t_b:
        rhs, event = (slip, stop) if sliding else (stick, release)
        sol = solve_ivp(
            rhs, (t, t_b), z, method="DOP853", rtol=rtol, atol=atol, events=event,
            dense_output=True, max_step=max_step,
        )  # fmt: skip
        t_end = sol.t[-1]
        if t <= t_a <= t_end and "a" not in x_at:
            x_at["a"] = sol.sol(t_a)[m]
        if sol.status == 1:
            t_end = float(sol.t_events[0][0])
            z = sol.y_events[0][0].copy()
            if sliding:
                z[m + 1] = 0.0
            elif t_a <= t_end < t_b:
                releases += 1
            sliding = not sliding
        else:
            z = sol.y[:, -1]
        t = t_end
    return (z[m] - x_at["a"]) / (t_b - t_a), releases
