"""Periodic orbits of the forced normal motion: shooting, Floquet multipliers, dense output.

Under a normal excitation of period T the normal motion m ÿ = m g + P(t) - N(δ, δ̇)
(eq. 2.4 with excitation; it never depends on the tangential motion) settles on a
periodic orbit. :func:`periodic_orbit` integrates from rest at y = y0 (or from a given
state at t = 0) for some periods, then solves φ_T(s) = s by Newton's method with the
variational Jacobian Φ - I (:mod:`microslip.analysis.normal_flow`). The eigenvalues of
the monodromy matrix Φ are the Floquet multipliers: the orbit is stable when all lie
inside the unit circle.

If the response reached from rest is not a stable period-1 orbit (a period doubling:
a multiplier beyond -1, or no convergence of the shooting from the transient),
:func:`periodic_orbit` raises :class:`NotPeriodOneError` (``strict=True``, the default)
so that a caller can fall back to a time average.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from microslip.analysis.continuation import NewtonStop
from microslip.analysis.normal_flow import (
    S_FLIGHT,
    S_NMAX,
    S_NMIN,
    S_SIZE,
    S_YMAX,
    S_YMIN,
    STATE_ONLY,
    propagate,
    propagate_each,
)
from microslip.model.capabilities import require
from microslip.model.coefficients import as_tuple
from microslip.model.composition import Model, as_model
from microslip.model.excitation import BaseMotion, HarmonicForce, PrescribedPenetration
from microslip.model.normal import normal_force, prescribed_gap

__all__ = [
    "NotPeriodOneError",
    "PeriodicOrbit",
    "periodic_orbit",
    "shoot",
    "steps_per_period",
    "transient_states",
]

TRANSIENT_PERIODS = 64  # excitation periods from rest before the shooting
STEPS_PER_NATURAL_PERIOD = 96  # 8th-order steps per 1/f0: one-period error near round-off
MIN_STEPS = 64
# The transient before the shooting needs only to land near the orbit for Newton, not
# round-off accuracy: it takes 1/8 of the orbit's steps (12 per natural period, |ω h| ~
# 0.5, well inside the 8th-order method's stability region). Measured (Viscous(0.05),
# HarmonicForce(0.5-5 N, 1400 Hz)): after 64 periods the state is 9e-11 to 6e-6 (in
# state_scale units) off the orbit; against a transient in the orbit's own steps, 1/4
# of them moves it by 4e-12 to 6e-11, 1/8 by 1e-9 to 2e-8 (1/12: up to 6e-7). The
# transient is the largest part of a forced mu_eff map's normal side: 1/8 took it from
# 2.5 to 1.6 ms per amplitude (one thread).
TRANSIENT_STEP_DIVISOR = 8
STABILITY_MARGIN = 1e-9  # stable: every |λ| < 1 + margin
NEWTON_TOL = 1e-13  # relative error of the scaled shooting state (continuation.NewtonStop)
FORCED = (HarmonicForce, BaseMotion, PrescribedPenetration)
FREE_VIBRATION_INSTEAD = (
    "the free vibration has no forcing period: use microslip.free_period or "
    "microslip.mean_velocity(..., amplitude=), or give an excitation"
)


class NotPeriodOneError(ValueError):
    """The response reached from the initial state is not a stable period-1 orbit."""


class ShootingError(ValueError):
    """Newton shooting for a periodic orbit did not converge."""


@dataclass(frozen=True)
class PeriodicOrbit:
    """One period [0, T] of a periodic normal motion, with its stability.

    Attributes
    ----------
    period : float
        T [s], the excitation period.
    t, y, ydot : ndarray
        Nodes [s], [m], [m/s] over [0, T]: every step end and every contact switch.
    accel_start, accel_end : ndarray
        ÿ [m/s^2] at t[k]+ and at t[k+1]- for interval k (one fewer than nodes), so that
        quintic Hermite interpolation
        (:func:`~microslip.analysis.orbit_table.orbit_state`) is exact to high order.
    y0_state : ndarray
        (y [m], ẏ [m/s]) at t = 0.
    multipliers : ndarray
        Floquet multipliers (complex; empty for a prescribed penetration).
    stable : bool
        All |λ| < 1 + 1e-9.
    max_multiplier : float
        max |λ| [1] (0 for a prescribed penetration).
    period_one : bool
        The orbit is a stable period-1 response (False: continued as unstable).
    contact_lost : bool
        N reaches 0 somewhere on the orbit.
    y_min, y_max : float
        Extremes of y [m].
    N_min, N_max : float
        Extremes of the normal force N [N].
    """

    period: float
    t: np.ndarray
    y: np.ndarray
    ydot: np.ndarray
    accel_start: np.ndarray
    accel_end: np.ndarray
    y0_state: np.ndarray
    multipliers: np.ndarray
    stable: bool
    max_multiplier: float
    period_one: bool
    contact_lost: bool
    y_min: float
    y_max: float
    N_min: float
    N_max: float

    @property
    def amplitude(self) -> float:
        """(y_max - y_min)/2 [m]."""
        return 0.5 * (self.y_max - self.y_min)


def steps_per_period(model: Model, frequency: float | None = None) -> int:
    """Fixed step count over one excitation period at ``frequency`` [Hz] (the model's)."""
    f = model.excitation.frequency if frequency is None else frequency
    ratio = model.params.natural_frequency / f
    return max(MIN_STEPS, math.ceil(STEPS_PER_NATURAL_PERIOD * ratio))


def transient_steps(n_steps: int) -> int:
    """Fixed step count per excitation period of a transient (TRANSIENT_STEP_DIVISOR)."""
    return math.ceil(n_steps / TRANSIENT_STEP_DIVISOR)


def state_scale(model: Model) -> np.ndarray:
    """(y0 [m], y0 ω0 [m/s]): the scales of the shooting state."""
    p = model.params
    return np.array(
        [p.static_deflection, p.static_deflection * 2.0 * math.pi * p.natural_frequency]
    )


def shoot(c, period, n_steps, guess, scale, max_iter=30):
    """Newton shooting: the state s at t = 0 with φ_T(s) = s, and the monodromy Φ.

    Works in the scaled state s/scale; stops when the last update, or the error left
    after it as estimated from the rate of convergence
    (:class:`~microslip.analysis.continuation.NewtonStop`), is below NEWTON_TOL
    relative.
    Raises :class:`ShootingError` without convergence.
    """
    s = np.array(guess, dtype=float)
    eye = np.eye(2)
    stop = NewtonStop(NEWTON_TOL)
    for _ in range(max_iter):
        end, phi, _, _, _ = propagate(c, s[0], s[1], 0.0, period, n_steps, False, True)
        residual = (end - s) / scale
        jac = phi * scale[np.newaxis, :] / scale[:, np.newaxis] - eye
        try:
            step = np.linalg.solve(jac, -residual)
        except np.linalg.LinAlgError as exc:
            raise ShootingError("singular shooting Jacobian (a multiplier at 1)") from exc
        if not np.all(np.isfinite(step)):
            break
        s = s + step * scale
        if stop.converged(step, s / scale):
            return s
    raise ShootingError("Newton shooting did not converge to a periodic orbit")


def build_orbit(c, period, n_steps, s) -> PeriodicOrbit:
    """The recorded orbit from the shooting state ``s`` at t = 0 (with its multipliers)."""
    _end, phi, nodes, accel, summary = propagate(c, s[0], s[1], 0.0, period, n_steps, True, True)
    multipliers = np.linalg.eigvals(phi).astype(complex)
    largest = float(np.max(np.abs(multipliers)))
    stable = largest < 1.0 + STABILITY_MARGIN
    return PeriodicOrbit(
        period=float(period),
        t=nodes[0],
        y=nodes[1],
        ydot=nodes[2],
        accel_start=accel[0],
        accel_end=accel[1],
        y0_state=np.array(s, dtype=float),
        multipliers=multipliers,
        stable=bool(stable),
        max_multiplier=largest,
        period_one=bool(stable),
        contact_lost=bool(summary[S_FLIGHT] > 0.0 or summary[S_NMIN] <= 0.0),
        y_min=float(summary[S_YMIN]),
        y_max=float(summary[S_YMAX]),
        N_min=float(summary[S_NMIN]),
        N_max=float(summary[S_NMAX]),
    )


def _prescribed_orbit(model: Model, n_steps: int) -> PeriodicOrbit:
    """The closed-form orbit of a prescribed penetration δ(t) = δ_m + Δ cos ωt (y ≡ δ)."""
    c = as_tuple(model.pack(0.0))  # the laws' one compiled form (docs/design.md)
    ex = model.excitation
    period = ex.period
    t = np.linspace(0.0, period, 4 * n_steps + 1)
    g = np.array([prescribed_gap(tt, c) for tt in t])
    force = np.array([normal_force(tt, g[i, 0], g[i, 1], c) for i, tt in enumerate(t)])
    return PeriodicOrbit(
        period=period,
        t=t,
        y=g[:, 0],
        ydot=g[:, 1],
        accel_start=g[:-1, 2].copy(),
        accel_end=g[1:, 2].copy(),
        y0_state=g[0, :2].copy(),
        multipliers=np.zeros(0, dtype=complex),
        stable=True,
        max_multiplier=0.0,
        period_one=True,
        contact_lost=bool(force.min() <= 0.0),
        y_min=ex.mean - ex.amplitude,
        y_max=ex.mean + ex.amplitude,
        N_min=float(force.min()),
        N_max=float(force.max()),
    )


def periodic_orbit(
    model: Model,
    *,
    initial_state: tuple[float, float] | None = None,
    transient_periods: int = TRANSIENT_PERIODS,
    strict: bool = True,
    transient_state: np.ndarray | None = None,
) -> PeriodicOrbit:
    """The periodic normal motion reached from rest at y = y0 (or from ``initial_state``).

    Parameters
    ----------
    model : Model
        A model with a normal excitation (HarmonicForce, BaseMotion or
        PrescribedPenetration); the free vibration is refused.
    initial_state : (y [m], ẏ [m/s]), optional
        State at t = 0 to start from; default rest at the static deflection y0.
    transient_periods : int
        Excitation periods integrated before shooting (more are tried once if the
        shooting does not land on a stable orbit).
    strict : bool
        Raise :class:`NotPeriodOneError` when the response is not a stable period-1
        orbit; with ``False`` return the (unstable) period-1 orbit found, flagged
        ``period_one=False``.
    transient_state : (y [m], ẏ [m/s]), optional
        The state after the first transient when it is known already: the row of
        :func:`transient_states` for this model (with ``initial_state`` and
        ``transient_periods`` at their defaults). The same bits as integrating it here.

    Returns
    -------
    PeriodicOrbit
    """
    model = as_model(model)
    require(model, "periodic_orbit", allowed={"excitation": FORCED}, instead=FREE_VIBRATION_INSTEAD)
    if not isinstance(transient_periods, int | np.integer) or transient_periods < 0:
        raise ValueError(f"transient_periods must be an int >= 0, got {transient_periods!r}")
    n_steps = steps_per_period(model)
    if isinstance(model.excitation, PrescribedPenetration):
        return _prescribed_orbit(model, n_steps)
    c = model.pack(0.0)
    period = model.excitation.period
    if initial_state is None:
        start = (model.params.static_deflection, 0.0)
    else:
        start = tuple(float(v) for v in initial_state)
        if len(start) != 2 or not all(math.isfinite(v) for v in start):
            raise ValueError(
                f"initial_state must be two finite numbers (y, ydot), got {initial_state!r}"
            )
    if transient_state is not None:
        if initial_state is not None or transient_periods != TRANSIENT_PERIODS:
            raise ValueError(
                f"transient_state is the first transient from rest over {TRANSIENT_PERIODS} "
                "periods (transient_states); it cannot be combined with initial_state or "
                "another transient_periods"
            )
        transient_state = np.asarray(transient_state, dtype=float)
        if transient_state.shape != (2,) or not np.all(np.isfinite(transient_state)):
            raise ValueError(
                f"transient_state must be two finite numbers (y, ydot), got {transient_state!r}"
            )
    scale = state_scale(model)
    state = np.array(start)
    orbit = None
    for attempt, periods in enumerate((transient_periods, 4 * transient_periods + 64)):
        if attempt == 0 and transient_state is not None:
            state = transient_state.copy()
        elif periods > 0:
            # The transient needs the state alone: no variational equation.
            state, _, _, _, _ = propagate(
                c, state[0], state[1], 0.0, periods * period, periods * transient_steps(n_steps),
                False, False,
            )  # fmt: skip
        try:
            s = shoot(c, period, n_steps, state, scale)
        except ShootingError:
            if attempt == 0:
                continue
            if strict:
                raise NotPeriodOneError(
                    f"no period-1 orbit found from the transient at excitation.frequency = "
                    f"{model.excitation.frequency!r} Hz (the response is not period-1)"
                ) from None
            raise
        orbit = build_orbit(c, period, n_steps, s)
        if orbit.stable:
            return orbit
    if strict:
        raise NotPeriodOneError(
            f"the response at excitation.frequency = {model.excitation.frequency!r} Hz is not "
            f"a stable period-1 orbit (largest Floquet multiplier {orbit.max_multiplier:.6g}); "
            "use a time average"
        )
    return orbit


def transient_states(models: list[Model], transient_periods: int = TRANSIENT_PERIODS) -> np.ndarray:
    """(y [m], ẏ [m/s]) after ``transient_periods`` excitation periods from rest at y0
    for each model (HarmonicForce or BaseMotion, nonzero amplitude), the first transient
    of :func:`periodic_orbit`, which takes a row as ``transient_state``. The models run
    side by side over the cores (:func:`normal_flow.propagate_each`), each on its own:
    the same bits as one at a time."""
    steps = np.array(
        [transient_periods * transient_steps(steps_per_period(model)) for model in models],
        dtype=np.int64,
    )
    cs = np.array([model.pack(0.0) for model in models])
    starts = np.array([[model.params.static_deflection, 0.0] for model in models])
    durations = np.array([transient_periods * model.excitation.period for model in models])
    ends = np.empty((len(models), 2))
    phis = np.empty((len(models), 2, 2))
    summaries = np.empty((len(models), S_SIZE))
    propagate_each(cs, starts, durations, steps, False, ends, phis, summaries, STATE_ONLY)
    return ends
