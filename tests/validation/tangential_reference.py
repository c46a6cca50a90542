"""An independent event-driven scipy reference for the tangential side of the model.

Shares no code with ``microslip``: it reads only the raw data of a ``Model`` (m, g, S,
c_n, m2, μ; each part's class name and fields) and writes the equations out again from
the physics (docs/design.md, docs/theory/friction_reduction.md,
docs/theory/stick_slip_drive.md):

    normal     m ÿ = m g − N,  N = S c_n y^m2 for y > 0 (free vibration, eq. 2.4), or the
               prescribed penetration δ(t) = δ_m + Δ cos(2π f t), N = S c_n δ^m2 for δ > 0;
    drive      F = F0 (constant), F0 + F1 sin(2π f_d t) (harmonic), k_d (v_d t − x)
               (spring), or x = v t (kinematic);
    rigid      m ẍ = F − μ(|ẋ|) N sgn ẋ while sliding, ẋ = 0 while |F| <= μ_s N
               (μ = μ_k, or Stribeck μ_k + (μ_s − μ_k) exp(−(|v|/v_s)^q));
    compliant  body m ẍ = F − f; massless contact point u, spring force f:
               stick u̇ = 0, ḟ = k_t ẋ while |f| <= μ_s N; slip f = μ_k N s (s = sgn u̇),
               u̇ = ẋ − ḟ/k_t; flight f = 0, u = x; k_t constant or λ dN/dδ (Mindlin).
               At a slip start f drops from μ_s N to μ_k N and the point jumps by the
               spring's recovery (μ_s − μ_k) N / k_t; at touchdown it starts stuck with a
               relaxed spring.

It integrates in the scales η = y/y0, τ = ω t, ω = sqrt(g/y0), ξ = x/y0, υ = u/y0,
φ = f/(m g), with scipy's DOP853 on segments of fixed modes (contact or flight; the
slip direction s = ±1 or stick 0 of the interface), whose right-hand side is smooth
(r = η² is continued past η = 0 for m2 = 2). Every switch is a terminal event where the
integration restarts in the new mode:

    contact     η (or δ/y0) = 0 falling / rising
    stick       μ_s r − |φ_d| (rigid) or μ_s r − |φ| (compliant) falling through 0
    slip        s ξ' + 1e-15 (rigid) or s υ' (compliant) falling through 0

A double crossing inside one step would be missed by scipy's sign test: each segment is
also split where a switching function has its extremum towards zero (its rate, written
out too, crosses zero), and a function found past its root there is located on the
dense output of the segment (brentq).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

CONTACT_LOST = "contact_lost"
CONTACT_MADE = "contact_made"
SLIP_START = "slip_start"
STICK_START = "stick_start"
REVERSAL = "reversal"
_STOP = "stop"

RTOL = 1e-12
ATOL = 1e-14
_STOP_OFFSET = 1e-15  # a release starts at zero speed: s ξ' may dip to -1e-18 first
_MAX_SEGMENTS = 200_000
_QUIET = 1e-3  # periods without splits after a split at a segment's start
_TRIAL = 1e-9  # periods: trial of a stick at touchdown (both N and f start at 0)
_NEAR_SURFACE = 0.5  # |δ|/y0 below which the gap's extremum is looked for


@dataclass
class Trajectory:
    """Reference trajectory in SI units at the requested times, plus its switches."""

    t: np.ndarray
    y: np.ndarray
    ydot: np.ndarray
    x: np.ndarray
    xdot: np.ndarray
    u: np.ndarray
    f: np.ndarray
    event_t: np.ndarray = field(default_factory=lambda: np.empty(0))
    event_kind: list = field(default_factory=list)
    event_states: np.ndarray = field(default_factory=lambda: np.empty((0, 6)))

    def events_of(self, kind: str) -> tuple[np.ndarray, np.ndarray]:
        """(times [s], states (y, ẏ, x, ẋ, u, f) just after) of the switches of one kind."""
        idx = [i for i, k in enumerate(self.event_kind) if k == kind]
        return self.event_t[idx], self.event_states[idx]


def _sign(value: float) -> int:
    return 1 if value > 0.0 else (-1 if value < 0.0 else 0)


class System:
    """The composed model in scaled variables (module docstring)."""

    def __init__(self, model, force: float | None = None) -> None:
        p = model.params
        if model.damping is not None:
            raise NotImplementedError("the tangential reference has no normal damping")
        self.m2 = float(p.m2)
        self.y0 = (p.mass * p.g / (p.area * p.c_n)) ** (1.0 / self.m2)
        self.omega = math.sqrt(p.g / self.y0)
        self.weight = p.mass * p.g
        self.vel = self.y0 * self.omega
        # friction
        name = type(model.friction).__name__ if model.friction is not None else "Coulomb"
        if name == "Coulomb":
            self.mu_s = self.mu_k = float(p.mu)
        else:
            self.mu_s, self.mu_k = model.friction.mu_static, model.friction.mu_kinetic
        self.stribeck = name == "Stribeck"
        if self.stribeck:
            self.v_s = model.friction.velocity / self.vel
            self.q = model.friction.exponent
        # tangential contact
        name = type(model.tangential).__name__ if model.tangential is not None else "Rigid"
        self.compliant = name in ("TangentialSpring", "MindlinSpring")
        self.mindlin = name == "MindlinSpring"
        self.k_t = (
            model.tangential.stiffness * self.y0 / self.weight
            if name == "TangentialSpring"
            else 0.0
        )
        self.lam = model.tangential.ratio if self.mindlin else 0.0
        # drive
        drive = model.drive
        self.drive = "constant" if drive is None else type(drive).__name__
        self.phi0 = self.phi1 = self.big_w = self.k_d = self.v_d = 0.0
        if drive is None:
            self.phi0 = force / self.weight
        elif self.drive == "ConstantForce":
            self.phi0 = drive.force / self.weight
        elif self.drive == "HarmonicDrive":
            self.phi0 = drive.mean / self.weight
            self.phi1 = drive.amplitude / self.weight
            self.big_w = 2.0 * math.pi * drive.frequency / self.omega
        elif self.drive == "SpringDrive":
            self.k_d = drive.stiffness * self.y0 / self.weight
            self.v_d = drive.velocity / self.vel
        elif self.drive == "PrescribedVelocity":
            self.v_d = drive.velocity / self.vel
        self.kinematic = self.drive == "PrescribedVelocity"
        # normal motion
        self.prescribed = model.excitation is not None
        if self.prescribed:
            if type(model.excitation).__name__ != "PrescribedPenetration":
                raise NotImplementedError("normal motion: free vibration or PrescribedPenetration")
            self.e_m = model.excitation.mean / self.y0
            self.e_a = model.excitation.amplitude / self.y0
            self.w_e = 2.0 * math.pi * model.excitation.frequency / self.omega

    # -- scales --------------------------------------------------------------------------
    def periods(self, amplitude: float) -> list[float]:
        """The time scales [τ] a step must resolve."""
        out = [2.0 * math.pi / math.sqrt(self.m2)]
        e_max = 3.0 + 2.0 * amplitude / self.y0
        if self.prescribed:
            out.append(2.0 * math.pi / self.w_e)
            e_max = self.e_m + self.e_a
        if self.big_w > 0.0:
            out.append(2.0 * math.pi / self.big_w)
        stiffness = self.k_d
        if self.compliant:
            stiffness += (
                self.k_t if not self.mindlin else self.lam * self.m2 * e_max ** (self.m2 - 1.0)
            )
        if stiffness > 0.0 and not self.kinematic:
            out.append(2.0 * math.pi / math.sqrt(stiffness))
        return out

    # -- normal law ----------------------------------------------------------------------
    def gap(self, tau: float, z, contact: bool) -> tuple[float, float, float]:
        """(e, e', e'') = δ/y0 and its τ-derivatives."""
        if self.prescribed:
            c, s = math.cos(self.w_e * tau), math.sin(self.w_e * tau)
            w = self.w_e
            return self.e_m + self.e_a * c, -self.e_a * w * s, -self.e_a * w * w * c
        return z[0], z[1], 1.0 - self.r(tau, z, contact)

    def elastic(self, e: float) -> float:
        if self.m2 == 2.0:
            return e * e
        return max(e, 0.0) ** self.m2

    def r(self, tau: float, z, contact: bool) -> float:
        """N/(m g)."""
        if not contact:
            return 0.0
        e = self.e_m + self.e_a * math.cos(self.w_e * tau) if self.prescribed else z[0]
        return self.elastic(e)

    def r_rates(self, tau: float, z, contact: bool) -> tuple[float, float]:
        """(r', r'') along the motion in contact."""
        e, e1, e2 = self.gap(tau, z, contact)
        if self.m2 == 2.0:
            return 2.0 * e * e1, 2.0 * e1 * e1 + 2.0 * e * e2
        e = max(e, 0.0)
        m2 = self.m2
        first = m2 * e ** (m2 - 1.0) * e1
        second = (
            m2 * (m2 - 1.0) * e ** (m2 - 2.0) * e1 * e1 + m2 * e ** (m2 - 1.0) * e2
            if e > 0
            else 0.0
        )
        return first, second

    def kappa(self, tau: float, z, contact: bool) -> float:
        """k_t y0/(m g)."""
        if not self.mindlin:
            return self.k_t
        e = self.gap(tau, z, contact)[0]
        return self.lam * self.m2 * max(e, 0.0) ** (self.m2 - 1.0)

    # -- tangential laws -----------------------------------------------------------------
    def drive_force(self, tau: float, z) -> float:
        """F/(m g)."""
        if self.drive == "HarmonicDrive":
            return self.phi0 + self.phi1 * math.sin(self.big_w * tau)
        if self.drive == "SpringDrive":
            return self.k_d * (self.v_d * tau - z[2])
        if self.kinematic:
            return 0.0
        return self.phi0

    def drive_rate(self, tau: float, z) -> float:
        if self.drive == "HarmonicDrive":
            return self.phi1 * self.big_w * math.cos(self.big_w * tau)
        if self.drive == "SpringDrive":
            return self.k_d * (self.v_d - z[3])
        return 0.0

    def mu(self, speed: float) -> float:
        if self.stribeck:
            return self.mu_k + (self.mu_s - self.mu_k) * math.exp(
                -((abs(speed) / self.v_s) ** self.q)
            )
        return self.mu_k

    def rhs(self, contact: bool, s: int):
        def fun(tau, z):
            r = self.r(tau, z, contact)
            normal_accel = self.gap(tau, z, contact)[2] if self.prescribed else 1.0 - r
            if self.compliant:
                xidd = 0.0 if self.kinematic else self.drive_force(tau, z) - z[5]
                upsd, phid = self._point_rates(tau, z, contact, s)
            else:
                upsd = phid = 0.0
                if s == 0 or self.kinematic:
                    xidd = 0.0
                else:
                    xidd = self.drive_force(tau, z) - s * self.mu(z[3]) * r
            return [z[1], normal_accel, z[3], xidd, upsd, phid]

        return fun

    def _point_rates(self, tau, z, contact, s) -> tuple[float, float]:
        """(υ', φ') of the compliant contact point."""
        if not contact:
            return z[3], 0.0
        if s == 0:
            return 0.0, self.kappa(tau, z, contact) * z[3]
        rr = self.r_rates(tau, z, contact)[0]
        phid = s * self.mu_k * rr
        if self.mindlin:
            e1 = self.gap(tau, z, contact)[1]
            return z[3] - s * self.mu_k * e1 / self.lam, phid
        return z[3] - phid / self.k_t, phid

    def _point_accel(self, tau, z, contact, s) -> float:
        """υ'' of a sliding compliant contact point."""
        xidd = 0.0 if self.kinematic else self.drive_force(tau, z) - z[5]
        if self.mindlin:
            e2 = self.gap(tau, z, contact)[2]
            return xidd - s * self.mu_k * e2 / self.lam
        r2 = self.r_rates(tau, z, contact)[1]
        return xidd - s * self.mu_k * r2 / self.k_t

    # -- switching functions: (kind, g, its rate, direction) ----------------------------
    def switches(self, contact: bool, s: int) -> list:
        if self.prescribed:
            g_gap = lambda tau, z: self.gap(tau, z, contact)[0]  # noqa: E731
            r_gap = lambda tau, z: self.gap(tau, z, contact)[1]  # noqa: E731
        else:
            g_gap, r_gap = (lambda tau, z: z[0]), (lambda tau, z: z[1])
        # The gap's extremum matters only near the surface (at rest at y0 its rate is 0
        # to rounding): farther than y0/2 the split function keeps the sign it has
        # away from the extremum.
        d = -1.0 if contact else 1.0
        out = [
            (
                CONTACT_LOST if contact else CONTACT_MADE, g_gap,
                lambda tau, z: r_gap(tau, z) if abs(g_gap(tau, z)) < _NEAR_SURFACE else d, d,
            )
        ]  # fmt: skip
        mu_s, r, rates = self.mu_s, self.r, self.r_rates
        if self.compliant and contact and s == 0:
            out.append((
                SLIP_START,
                lambda tau, z: mu_s * r(tau, z, True) - abs(z[5]),
                lambda tau, z: mu_s * rates(tau, z, True)[0]
                - _sign(z[5]) * self.kappa(tau, z, True) * z[3],
                -1.0,
            ))  # fmt: skip
        elif self.compliant and contact:
            out.append((
                _STOP,
                lambda tau, z: s * self._point_rates(tau, z, True, s)[0],
                lambda tau, z: s * self._point_accel(tau, z, True, s),
                -1.0,
            ))  # fmt: skip
        elif not self.compliant and not self.kinematic and s == 0 and contact:
            out.append((
                SLIP_START,
                lambda tau, z: mu_s * r(tau, z, True) - abs(self.drive_force(tau, z)),
                lambda tau, z: mu_s * rates(tau, z, True)[0]
                - _sign(self.drive_force(tau, z)) * self.drive_rate(tau, z),
                -1.0,
            ))  # fmt: skip
        elif not self.compliant and not self.kinematic and s != 0:
            out.append((
                _STOP,
                lambda tau, z: s * z[3] + _STOP_OFFSET,
                lambda tau, z: s * self.drive_force(tau, z) - self.mu(z[3]) * r(tau, z, contact),
                -1.0,
            ))  # fmt: skip
        return out


def _terminal(fun, direction: float):
    def event(tau, z):
        return fun(tau, z)

    event.terminal = True
    event.direction = direction
    return event


class Reference:
    """Integrator of a :class:`System` from a scaled initial state."""

    def __init__(self, model, *, force=None, amplitude: float = 0.0, rtol=RTOL, atol=ATOL):
        self.sys = System(model, force)
        self.rtol, self.atol = rtol, atol
        self.period = min(self.sys.periods(amplitude))
        self.max_step = self.period / 40.0

    def initial_modes(self, tau: float, z) -> tuple[bool, int]:
        sys = self.sys
        e, e1, _ = sys.gap(tau, z, True)
        contact = e > 0.0 or (e == 0.0 and e1 > 0.0)
        if sys.compliant:
            if not contact:
                return False, 0
            if abs(z[5]) <= sys.mu_s * sys.r(tau, z, True):
                return True, 0
            return True, self._slip_start(tau, z)
        if z[3] != 0.0:
            return contact, _sign(z[3])
        phi = sys.drive_force(tau, z)
        if contact and abs(phi) <= sys.mu_s * sys.r(tau, z, True):
            return contact, 0
        return contact, _sign(phi) or _sign(sys.drive_rate(tau, z))

    def _slip_start(self, tau, z) -> int:
        """A compliant point starts to slip: f drops to μ_k N, the point jumps; returns
        the new mode (0 when the point has nothing to slide for and sticks again)."""
        sys = self.sys
        s = _sign(z[5]) or _sign(z[3])
        new = s * sys.mu_k * sys.r(tau, z, True)
        kappa = sys.kappa(tau, z, True)
        if kappa > 0.0:
            z[4] += (z[5] - new) / kappa
        z[5] = new
        if s * sys._point_rates(tau, z, True, s)[0] <= 0.0:
            return 0
        return s

    def run(self, z0, tau_end: float, tau_eval: np.ndarray):
        """Integrate from z0 at τ = 0; samples at ``tau_eval``, events (τ, kind, z)."""
        sys = self.sys
        z = np.array(z0, dtype=float)
        tau = 0.0
        contact, s = self.initial_modes(tau, z)
        samples = np.empty((tau_eval.size, 6))
        i_eval = 0
        events = []
        quiet_until = 0.0
        segments = 0
        while tau < tau_end:
            segments += 1
            if segments > _MAX_SEGMENTS:
                raise RuntimeError("tangential reference: too many segments")
            switches = sys.switches(contact, s)
            evs = [_terminal(g, d) for _k, g, _r, d in switches]
            n_switch = len(evs)
            t_bound = tau_end
            if tau >= quiet_until:
                evs += [_terminal(rate, -d) for _k, _g, rate, d in switches]
            else:
                t_bound = min(tau_end, quiet_until)
            sol = solve_ivp(
                sys.rhs(contact, s), (tau, t_bound), z, method="DOP853", rtol=self.rtol,
                atol=self.atol, events=evs, dense_output=True, max_step=self.max_step,
            )  # fmt: skip
            if sol.status < 0:
                raise RuntimeError(f"tangential reference: {sol.message}")
            if sol.status == 0:
                which, tau_new, z_new = None, t_bound, sol.y[:, -1].copy()
            else:
                which = min(
                    (k for k in range(len(evs)) if sol.t_events[k].size),
                    key=lambda k: sol.t_events[k][0],
                )
                tau_new = float(sol.t_events[which][0])
                z_new = np.array(sol.y_events[which][0], dtype=float)
            kind = None
            if which is not None and which < n_switch:
                kind = switches[which][0]
            elif which is not None:
                # A split at an extremum: a switching function past its root crossed
                # twice within a step; locate its first root.
                missed = []
                for k, (_kind, g, _rate, d) in enumerate(switches):
                    if d * g(tau_new, z_new) > 0.0 and d * g(tau, z) < 0.0:
                        missed.append(k)
                if missed:
                    roots = [
                        brentq(lambda t, g=switches[k][1], d=sol.sol: g(t, d(t)), tau, tau_new,
                               xtol=1e-15, rtol=4 * np.finfo(float).eps)
                        for k in missed
                    ]  # fmt: skip
                    first = int(np.argmin(roots))
                    tau_new = roots[first]
                    z_new = sol.sol(tau_new)
                    kind = switches[missed[first]][0]
                else:  # at the extremum the rate is 0: no split again right away
                    quiet_until = tau_new + _QUIET * self.period
            while i_eval < tau_eval.size and (
                tau_eval[i_eval] < tau_new or (tau_new >= tau_end and tau_eval[i_eval] <= tau_new)
            ):
                samples[i_eval] = sol.sol(tau_eval[i_eval])
                i_eval += 1
            if kind is not None and tau_new <= tau and kind != CONTACT_MADE:
                raise RuntimeError(f"tangential reference: no progress at τ={tau!r} ({kind})")
            tau, z = tau_new, z_new
            if kind is None:
                continue
            contact, s, recorded = self._switch(kind, tau, z, contact, s)
            for name in recorded:
                events.append((tau, name, z.copy()))
        return samples[:i_eval], events

    def _switch(self, kind, tau, z, contact, s):
        """(contact, s, recorded event names) after switch ``kind`` at (τ, z)."""
        sys = self.sys
        if kind in (CONTACT_LOST, CONTACT_MADE) and not sys.prescribed:
            z[0] = 0.0  # on the surface (the located root is within rounding of it)
        if kind == CONTACT_LOST:
            if sys.compliant:
                z[4], z[5] = z[2], 0.0
                return False, 0, [CONTACT_LOST]
            return False, s, [CONTACT_LOST]
        if kind == CONTACT_MADE:
            if not sys.compliant:
                return True, s, [CONTACT_MADE]
            z[4], z[5] = z[2], 0.0
            # Stick with a relaxed spring; N and f both start at 0: try a short stick.
            trial = solve_ivp(
                sys.rhs(True, 0), (tau, tau + _TRIAL * self.period), z, method="DOP853",
                rtol=self.rtol, atol=self.atol,
            )  # fmt: skip
            end = trial.y[:, -1]
            if sys.mu_s * sys.r(trial.t[-1], end, True) - abs(end[5]) < 0.0:
                return True, self._slip_start(tau, z), [CONTACT_MADE, SLIP_START]
            return True, 0, [CONTACT_MADE]
        if kind == SLIP_START:
            if sys.compliant:
                return True, self._slip_start(tau, z), [SLIP_START]
            return contact, _sign(sys.drive_force(tau, z)), [SLIP_START]
        # a stop
        if sys.compliant:
            z[5] = s * sys.mu_k * sys.r(tau, z, True)
            return True, 0, [STICK_START]
        z[3] = 0.0
        phi = sys.drive_force(tau, z)
        if contact and abs(phi) <= sys.mu_s * sys.r(tau, z, True):
            return contact, 0, [STICK_START]
        new = _sign(phi)
        return contact, new, [REVERSAL if new == -s else SLIP_START]


def reference_solution(
    model,
    *,
    t_eval,
    amplitude: float | None = None,
    force: float | None = None,
    rtol: float = RTOL,
    atol: float = ATOL,
) -> Trajectory:
    """Solve the model from the paper's start (rest at y0 − A, ``amplitude`` A [m]; or
    δ(0) = δ_m + Δ with a prescribed penetration), x = 0, a relaxed contact point, ẋ = v
    under a kinematic drive; sample at the sorted ``t_eval`` [s]. ``force`` [N]: the
    constant force of a model without a drive. ``atol`` is in the scaled units."""
    ref = Reference(model, force=force, amplitude=amplitude or 0.0, rtol=rtol, atol=atol)
    sys = ref.sys
    z0 = np.zeros(6)
    if sys.prescribed:
        z0[0] = sys.e_m + sys.e_a
    else:
        z0[0] = 1.0 - (amplitude or 0.0) / sys.y0
    if sys.kinematic:
        z0[3] = sys.v_d
    t_eval = np.asarray(t_eval, dtype=float)
    tau_eval = t_eval * sys.omega
    samples, events = ref.run(z0, float(tau_eval[-1]), tau_eval)
    if samples.shape[0] != t_eval.size:
        raise RuntimeError("tangential reference: lost output points")
    scale = np.array([sys.y0, sys.vel, sys.y0, sys.vel, sys.y0, sys.weight])
    si = samples * scale
    states = np.array([z * scale for _tau, _kind, z in events]).reshape(-1, 6)
    return Trajectory(
        t=t_eval,
        y=si[:, 0],
        ydot=si[:, 1],
        x=si[:, 2],
        xdot=si[:, 3],
        u=si[:, 4],
        f=si[:, 5],
        event_t=np.array([tau / sys.omega for tau, _k, _z in events]),
        event_kind=[kind for _tau, kind, _z in events],
        event_states=states,
    )
