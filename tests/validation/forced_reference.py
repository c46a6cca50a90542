"""An independent scipy reference for the damped, excited normal motion (and sliding on it).

Shares no law with ``microslip``: it reads only the raw data of a ``Model`` (m, g, S,
c_n, m2, μ; the damping part's class name and ratio; the excitation part's class name,
amplitude and frequency) and writes the normal equation out again,

    m ÿ = m g + P(t) − N,   δ = y − z(t),
    N = max(0, N_raw(δ, δ̇)) while δ > 0, else 0,
    N_raw = S c_n δ^m2               (elastic, eq. 2.3)
          = S c_n δ^m2 + c δ̇         (Kelvin–Voigt)
          = S c_n δ^m2 (1 + c δ̇/(m g))   (Hunt–Crossley),
    c = 2 ζ sqrt(K_n m),  K_n = m2 m g / y0,  y0 = (m g / (S c_n))^(1/m2),
    P(t) = P0 sin(2π f t)   (HarmonicForce),   z(t) = Z sin(2π f t)   (BaseMotion).

It is integrated with scipy's DOP853 in the scales η = y/y0, τ = ω t, ω = sqrt(g/y0),
where the law reads η'' = 1 + p(τ) − r, r = N/(m g) = e^m2 + k e' (KV) or
e^m2 (1 + k e') (HC), e = δ/y0, k = c y0 ω/(m g) = 2 ζ sqrt(m2). The contact mode is
fixed on each segment (the right-hand side is then smooth) and every switch is a
terminal event where the integration restarts: contact holds while e > 0 and N_raw > 0,
i.e. while h > 0 with h = min(e, r_raw) (KV), min(e, 1 + k e') (HC), e (elastic). A
maximum step of 1/40 of the small-amplitude period keeps a double crossing of h inside
one step (a grazing, which scipy's sign-change test would miss) out of the cases used.

Quadratures ride along as extra state components over one period: ∫N dt, the work of
P, the work of the moving surface on the body through the contact (−∫N ż dt), the
energy dissipated by the damping law (∫ D δ̇ dt over contact, D = N_raw − S c_n δ^m2)
and ∫ S c_n δ^m2 δ̇ dt over contact (zero over a period unless the body separates while
δ > 0, where the elastic energy stored in the overlap is given up).

Node tables of one period (t, y, ẏ, ÿ at equally spaced nodes) serve the tests of the
reflected process. The tangential motion on top of this normal motion is
``sliding_reference.py``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

RTOL = 1e-12
ATOL = 1e-14
_MAX_SEGMENTS = 200_000

# Quadrature slots (after η, η'): ∫r dτ, ∫p η' dτ, −∫r zs' dτ, ∫d e' dτ, ∫el e' dτ
Q_N, Q_P, Q_BASE, Q_DISS, Q_ELASTIC = range(2, 7)


@dataclass
class Segmented:
    """Result of one integration: final scaled state and the switches (τ, kind)."""

    tau: float
    u: np.ndarray
    contact: bool
    events: list = field(default_factory=list)
    extrema: list = field(default_factory=list)  # η at η' = 0 (scaled)
    samples_tau: list = field(default_factory=list)
    samples_u: list = field(default_factory=list)


class NormalReference:
    """The normal motion of a ``Model`` in scaled variables (see the module docstring)."""

    dim = 2  # scaled state (η, η')

    def __init__(self, model, *, rtol: float = RTOL, atol: float = ATOL) -> None:
        p = model.params
        self.m, self.g, self.m2, self.mu = p.mass, p.g, float(p.m2), p.mu
        self.y0 = (p.mass * p.g / (p.area * p.c_n)) ** (1.0 / p.m2)
        self.omega = math.sqrt(p.g / self.y0)  # time scale [1/s]
        self.k_n = self.m2 * p.mass * p.g / self.y0  # K_n [N/m]
        self.f0 = math.sqrt(self.k_n / p.mass) / (2.0 * math.pi)
        self.rtol, self.atol = rtol, atol
        self.damping = "none"
        self.c = 0.0
        if model.damping is not None:
            self.damping = {"Viscous": "kv", "HuntCrossley": "hc"}[type(model.damping).__name__]
            self.c = 2.0 * model.damping.ratio * math.sqrt(self.k_n * p.mass)
        self.k = self.c * self.y0 * self.omega / (p.mass * p.g)
        self.p0 = self.z0 = 0.0
        self.big_omega = 0.0
        self.excitation = "none"
        if model.excitation is not None:
            name = type(model.excitation).__name__
            self.excitation = {"HarmonicForce": "force", "BaseMotion": "base"}[name]
            if name == "HarmonicForce":
                self.p0 = model.excitation.amplitude / (p.mass * p.g)
            else:
                self.z0 = model.excitation.amplitude / self.y0
            self.big_omega = 2.0 * math.pi * model.excitation.frequency / self.omega
        self.natural_tau = 2.0 * math.pi / math.sqrt(self.m2)  # small-amplitude period in τ
        self.max_step = self.natural_tau / 40.0
        if self.big_omega > 0.0:
            self.max_step = min(self.max_step, 2.0 * math.pi / self.big_omega / 40.0)

    # -- scales ---------------------------------------------------------------------------
    @property
    def period_tau(self) -> float:
        """Excitation period in τ."""
        return 2.0 * math.pi / self.big_omega

    def to_si(self, u) -> tuple[float, float]:
        """(y [m], ẏ [m/s]) from scaled (η, η')."""
        return u[0] * self.y0, u[1] * self.y0 * self.omega

    def from_si(self, y: float, ydot: float) -> np.ndarray:
        return np.array([y / self.y0, ydot / (self.y0 * self.omega)])

    # -- the law ----------------------------------------------------------------------------
    def p(self, tau: float) -> float:
        return self.p0 * math.sin(self.big_omega * tau)

    def surface(self, tau: float) -> tuple[float, float]:
        """(z/y0, (z/y0)')."""
        w = self.big_omega
        return self.z0 * math.sin(w * tau), self.z0 * w * math.cos(w * tau)

    def gap(self, tau: float, u) -> tuple[float, float]:
        zs, zs_rate = self.surface(tau)
        return u[0] - zs, u[1] - zs_rate

    def elastic(self, e: float) -> float:
        if e <= 0.0:
            return 0.0
        return e * e if self.m2 == 2.0 else e**self.m2

    def raw(self, tau: float, u) -> tuple[float, float]:
        """(r_raw, its elastic part) = (N_raw, S c_n δ^m2) / (m g)."""
        e, e_rate = self.gap(tau, u)
        el = self.elastic(e)
        if self.damping == "kv":
            return el + self.k * e_rate, el
        if self.damping == "hc":
            return el * (1.0 + self.k * e_rate), el
        return el, el

    def indicator(self, tau: float, u) -> float:
        """> 0 in contact (δ > 0 and N_raw > 0), continuous across the switches."""
        e, e_rate = self.gap(tau, u)
        if self.damping == "kv":
            return min(e, self.elastic(e) + self.k * e_rate)
        if self.damping == "hc":
            return min(e, 1.0 + self.k * e_rate)
        return e

    def normal_force(self, t: float, y: float, ydot: float) -> float:
        """N [N] at time t [s] and state (y, ẏ) in SI."""
        tau = t * self.omega
        u = self.from_si(y, ydot)
        if self.indicator(tau, u) <= 0.0:
            return 0.0
        return max(0.0, self.raw(tau, u)[0]) * self.m * self.g

    def in_contact(self, tau: float, u) -> bool:
        h = self.indicator(tau, u)
        if h != 0.0:
            return h > 0.0
        # on the switching surface: contact if moving into it
        eps = 1e-9 * self.natural_tau
        return self.indicator(tau + eps, np.asarray(u[:2]) + eps * self._f2(tau, u, True)) > 0.0

    def _f2(self, tau, u, contact):
        r = self.raw(tau, u)[0] if contact else 0.0
        return np.array([u[1], 1.0 + self.p(tau) - r])

    def load(self, tau: float, u, contact: bool) -> float:
        """r = N/(m g) in the given contact mode."""
        return max(0.0, self.raw(tau, u)[0]) if contact else 0.0

    def normal_rhs(self, tau: float, u, contact: bool) -> list[float]:
        """(η', η'') in the given contact mode."""
        return [u[1], 1.0 + self.p(tau) - self.load(tau, u, contact)]

    def rhs(self, contact: bool, quad: bool):
        def f(tau, u):
            if contact:
                r, el = self.raw(tau, u)
            else:
                r = el = 0.0
            out = [u[1], 1.0 + self.p(tau) - r]
            if quad:
                zs_rate = self.surface(tau)[1]
                e_rate = u[1] - zs_rate
                out += [r, self.p(tau) * u[1], -r * zs_rate, (r - el) * e_rate, el * e_rate]
            return out

        return f

    # -- integration --------------------------------------------------------------------
    def integrate(
        self,
        tau0: float,
        u0,
        tau1: float,
        *,
        quad: bool = False,
        extrema: bool = False,
        tau_eval=None,
        contact: bool | None = None,
    ) -> Segmented:
        """Integrate from (τ0, u0) to τ1, restarting at every contact switch."""
        u = np.array(u0[:2], dtype=float)
        if quad:
            u = np.concatenate([u, np.zeros(5)])
        tau = float(tau0)
        contact = self.in_contact(tau, u) if contact is None else contact
        run = Segmented(tau, u, contact)
        tau_eval = np.empty(0) if tau_eval is None else np.asarray(tau_eval, dtype=float)
        i_eval = 0
        segments = 0

        def switch(t, v):
            return self.indicator(t, v)

        switch.terminal = True

        def turn(t, v):
            return v[1]

        turn.terminal = False

        while tau < tau1:
            switch.direction = -1.0 if contact else 1.0
            events = [switch, turn] if extrema else [switch]
            pts = tau_eval[i_eval:]
            pts = pts[pts <= tau1]
            sol = solve_ivp(
                self.rhs(contact, quad), (tau, tau1), u, method="DOP853", rtol=self.rtol,
                atol=self.atol, events=events, max_step=self.max_step, dense_output=pts.size > 0,
            )  # fmt: skip
            if sol.status < 0:
                raise RuntimeError(f"forced reference failed: {sol.message}")
            segments += 1
            if segments > _MAX_SEGMENTS:
                raise RuntimeError("forced reference: too many segments")
            hit = sol.status == 1
            tau_new = float(sol.t_events[0][0]) if hit else float(sol.t[-1])
            u_new = np.array(sol.y_events[0][0] if hit else sol.y[:, -1], dtype=float)
            if pts.size:
                take = pts[pts <= tau_new] if hit else pts
                if hit:  # a sample exactly at the switch belongs to this segment
                    take = take[take <= tau_new]
                run.samples_tau.append(take)
                run.samples_u.append(sol.sol(take).T if take.size else np.empty((0, u.size)))
                i_eval += take.size
            if extrema:
                for t_e, u_e in zip(sol.t_events[1], sol.y_events[1], strict=True):
                    if t_e <= tau_new:
                        run.extrema.append((float(t_e), float(u_e[0])))
            tau, u = tau_new, u_new
            if hit:
                contact = not contact
                run.events.append((tau, "contact_made" if contact else "contact_lost"))
        run.tau, run.u, run.contact = tau, u, contact
        return run

    def strobe(self, u, tau0: float = 0.0, periods: int = 1) -> np.ndarray:
        """The state after ``periods`` excitation periods from (τ0, u)."""
        return self.integrate(tau0, u, tau0 + periods * self.period_tau).u[:2]

    def monodromy(self, u, *, rel_step: float = 1e-5) -> np.ndarray:
        """Finite-difference (central) monodromy matrix of the period map at the state u."""
        u = np.asarray(u[:2], dtype=float)
        mat = np.empty((2, 2))
        for j in range(2):
            h = rel_step * max(abs(u[j]), 1.0)
            du = np.zeros(2)
            du[j] = h
            mat[:, j] = (self.strobe(u + du) - self.strobe(u - du)) / (2.0 * h)
        return mat

    def fixed_point(self, u_guess, *, tol: float = 1e-13, max_iter: int = 30) -> np.ndarray:
        """Newton on P(u) − u = 0 for the stroboscopic map at τ = 0."""
        u = np.asarray(u_guess[:2], dtype=float)
        for _ in range(max_iter):
            residual = self.strobe(u) - u
            jac = self.monodromy(u) - np.eye(2)
            step = np.linalg.solve(jac, -residual)
            u = u + step
            if np.max(np.abs(step)) < tol:
                return u
        raise RuntimeError(f"forced reference: Newton did not converge (last step {step})")

    def settle(self, u0, periods: int) -> np.ndarray:
        """The state at τ = 0 (mod the period) after ``periods`` periods from u0 at τ = 0."""
        return self.strobe(u0, 0.0, periods)

    def steady_orbit(self, u0=None, *, periods: int = 150) -> np.ndarray:
        """Stroboscopic fixed point reached from u0 (default: rest at y = y0, t = 0) by a
        long integration, polished by Newton (checked to move it by less than 1e-3 y0:
        the same attractor)."""
        u0 = np.array([1.0, 0.0]) if u0 is None else np.asarray(u0, dtype=float)
        u = self.settle(u0, periods)
        fixed = self.fixed_point(u)
        if np.max(np.abs(fixed - u)) > 1e-3:
            raise RuntimeError(f"steady state not reached after {periods} periods: {u} vs {fixed}")
        return fixed

    def period_summary(self, u) -> dict[str, float]:
        """One period from the periodic state u at τ = 0: SI amplitude, extrema, averages."""
        run = self.integrate(0.0, u, self.period_tau, quad=True, extrema=True)
        q = run.u
        t_period = self.period_tau / self.omega
        energy = self.m * self.g * self.y0  # scale of the quadratures [J]
        etas = [u[0], run.u[0]] + [e for _t, e in run.extrema]
        return {
            "y_min": min(etas) * self.y0,
            "y_max": max(etas) * self.y0,
            "amplitude": 0.5 * (max(etas) - min(etas)) * self.y0,
            "mean_N": q[Q_N] / self.period_tau * self.m * self.g,
            "work_P": q[Q_P] * energy,
            "work_base": q[Q_BASE] * energy,
            "dissipated": q[Q_DISS] * energy,
            "elastic_balance": q[Q_ELASTIC] * energy,
            "period": t_period,
            "closure": float(np.max(np.abs(run.u[:2] - np.asarray(u[:2])))),
            "contact_lost": any(kind == "contact_lost" for _t, kind in run.events),
        }

    def multipliers(self, u) -> np.ndarray:
        return np.linalg.eigvals(self.monodromy(u))

    def table(self, u, tau_period: float, intervals: int):
        """Node arrays (t [s], y [m], ẏ [m/s], ÿ [m/s^2]) at ``intervals`` + 1 equally
        spaced nodes over [0, τ_period] from the scaled state u at τ = 0; the contact must
        hold all along (checked)."""
        tau = np.linspace(0.0, tau_period, intervals + 1)
        run = self.integrate(0.0, u, tau_period, tau_eval=tau)
        if run.events:
            raise RuntimeError("table: the contact must hold over the whole period")
        states = np.concatenate(run.samples_u).T
        states[:, 0] = u[:2]
        accel = np.array([self.normal_rhs(tt, states[:, i], True)[1] for i, tt in enumerate(tau)])
        w = self.omega
        return tau / w, states[0] * self.y0, states[1] * self.y0 * w, accel * self.y0 * w * w


def free_vibration_table(params, amplitude: float, intervals: int = 1024, **tolerances):
    """One period of the paper's free vibration from rest at the top y0 − A (A < y0): the
    period is twice the time to the lowest point (the orbit is symmetric about it)."""
    from microslip import Model

    ref = NormalReference(Model(params), **tolerances)
    u0 = np.array([1.0 - amplitude / ref.y0, 0.0])
    run = ref.integrate(0.0, u0, 2.0 * ref.natural_tau, extrema=True)
    bottom = next(t for t, eta in run.extrema if t > 0.0 and eta > 1.0)
    return ref.table(u0, 2.0 * bottom, intervals)


def forced_table(model, intervals: int = 512, **tolerances):
    """One period of the steady orbit of ``model`` reached from rest at y0 (200 periods,
    then Newton on the stroboscopic map)."""
    ref = NormalReference(model, **tolerances)
    return ref.table(ref.steady_orbit(periods=200), ref.period_tau, intervals)


def linear_amplitude(k_n: float, mass: float, c: float, p0: float, f: float) -> float:
    """P0 / sqrt((K_n − m ω²)² + (c ω)²) [m] (MODEL.md identity 3)."""
    w = 2.0 * math.pi * f
    return p0 / math.hypot(k_n - mass * w * w, c * w)


def base_linear_amplitude(k_n: float, mass: float, c: float, z0: float, f: float) -> float:
    """Z sqrt(K_n² + (c ω)²) / sqrt((K_n − m ω²)² + (c ω)²) [m]: the body's amplitude under
    base motion z = Z sin ωt of the linear contact (m ẍ + c ẋ + K_n x = K_n z + c ż)."""
    w = 2.0 * math.pi * f
    return z0 * math.hypot(k_n, c * w) / math.hypot(k_n - mass * w * w, c * w)


# -- the folded resonance curve of the tests (paper data, softening m2 = 2) -----------------
FOLD_RATIO_ZETA = 0.02  # Viscous damping ratio
FOLD_FORCE = 0.5  # P0 [N]: the curve folds between ~0.93 f0 and ~0.96 f0
FOLD_AT = 0.95  # f/f0 inside the hysteresis band
UP_SWEEP = (0.6, 0.7, 0.8, 0.85, 0.9, 0.925, 0.95)  # f/f0, from rest at the first
DOWN_SWEEP = (1.45, 1.3, 1.2, 1.1, 1.05, 1.0, 0.975, 0.95)
SWEEP_PERIODS = 80  # excitation periods per sweep step (transient ~exp(-0.13) per period)
FINAL_PERIODS = 240  # at the last frequency, near the fold: slower decay


def folded_model(ratio: float = FOLD_AT):
    """Model(paper data, Viscous(0.02), HarmonicForce(0.5 N, ratio f0))."""
    from microslip import HarmonicForce, Model, Parameters, Viscous

    p = Parameters()
    return Model(
        p,
        damping=Viscous(ratio=FOLD_RATIO_ZETA),
        excitation=HarmonicForce(amplitude=FOLD_FORCE, frequency=ratio * p.natural_frequency),
    )


@functools.lru_cache(maxsize=4)
def swept_state(direction: str):
    """The stable steady state at f = FOLD_AT f0 reached by a stepped frequency sweep of
    the scipy time integration, from rest at y = y0 at the first frequency ("up": from
    0.6 f0, the lower branch; "down": from 1.45 f0, the upper branch). Each step starts
    from the previous step's state at a whole number of periods (forcing phase 0); the
    last state is polished by Newton (moving it by < 1e-3 y0: same attractor).

    Returns (reference, scaled fixed point, period summary).
    """
    ratios = UP_SWEEP if direction == "up" else DOWN_SWEEP
    u = np.array([1.0, 0.0])
    for i, ratio in enumerate(ratios):
        ref = NormalReference(folded_model(ratio))
        u = ref.settle(u, FINAL_PERIODS if i == len(ratios) - 1 else SWEEP_PERIODS)
    fixed = ref.fixed_point(u)
    if np.max(np.abs(fixed - u)) > 1e-3:
        raise RuntimeError(f"sweep {direction}: not settled ({u} vs fixed point {fixed})")
    return ref, fixed, ref.period_summary(fixed)


# -- periodic states used by the identity tests --------------------------------------------
def periodic_cases() -> dict:
    """Damped, excited models with a stable period-1 orbit reached from rest (checked with
    this reference): in contact throughout, and with loss of contact every period."""
    from microslip import BaseMotion, HarmonicForce, HuntCrossley, Model, Parameters, Viscous

    p = Parameters()
    f0, y0 = p.natural_frequency, p.static_deflection
    return {
        "kv_force": Model(p, damping=Viscous(0.03), excitation=HarmonicForce(0.5, 1400.0)),
        "hc_base_loss": Model(
            p, damping=HuntCrossley(0.05), excitation=BaseMotion(0.3 * y0, 0.8 * f0)
        ),
        "kv_force_loss": Model(p, damping=Viscous(0.1), excitation=HarmonicForce(8.0, 0.7 * f0)),
        "hc_force_loss": Model(
            p, damping=HuntCrossley(0.1), excitation=HarmonicForce(8.0, 0.7 * f0)
        ),
        "kv_base_loss": Model(p, damping=Viscous(0.1), excitation=BaseMotion(y0, 0.7 * f0)),
    }


@functools.lru_cache(maxsize=16)
def steady_case(name: str):
    """(model, reference, scaled fixed point reached from rest, period summary)."""
    model = periodic_cases()[name]
    ref = NormalReference(model)
    u = ref.steady_orbit(periods=100)
    return model, ref, u, ref.period_summary(u)
