"""Exact steady stick–slip cycle and long-time mean velocity (Fig. 7), for any model.

See docs/model-facts.md, facts 5–6. :func:`mean_velocity` dispatches on the model's
parts: the paper's free vibration uses the closed form below; a damped free vibration
decays to rest (0 below μ m g); a forced contact uses the reflected process over one
period of its periodic normal motion (:mod:`microslip.analysis.forced_sliding`).

With F >= 0 the slider never moves backwards, and because m ÿ = m g - |R| (2.4) the
friction impulse is known from the normal velocity alone:

    ∫ μ|R| dt = μ m g Δt - μ m Δẏ.

While sliding from rest at t_a, (2.5) therefore integrates in closed form:

    ẋ(t) = a (t - t_a) + μ (ẏ(t) - ẏ(t_a)),  a = (F - μ m g)/m,
    x(t) - x(t_a) = a (t - t_a)²/2 + μ (y(t) - y(t_a)) - μ ẏ(t_a)(t - t_a).

For F < μ m g the slider sticks once per normal period T, and from its first stick on
the motion is periodic: it is released when μ|R| falls to F, i.e. when the rising slider
passes y* = (F/(μ S c_n))^(1/m2), and stops at the first later zero of ẋ. The mean
velocity is the slip distance of one cycle divided by T. Only the free normal
vibration is computed numerically (:mod:`microslip.analysis.orbit`), once per amplitude
and shared by every force; y* depends on F alone and is shared by every amplitude. Both
crossings are found on the table without a transcendental call per point
(:func:`orbit.steady_slip`). The compiled kernels, and the map over forces × amplitudes
(:func:`mean_velocity_grid`), are in :mod:`microslip.analysis.steady_kernels`.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from microslip import validation as check
from microslip.analysis import orbit
from microslip.analysis.steady_kernels import BATCH_AMPLITUDES as BATCH_AMPLITUDES
from microslip.analysis.steady_kernels import (
    CY_DISTANCE,
    CY_MEAN,
    CY_PEAK,
    CY_PERIOD,
    CY_RELEASE,
    CY_SIZE,
    CY_SLIP_TIME,
    _no_vibration,
    mean_velocity_grid,
    steady_cycle,
)
from microslip.analysis.steady_kernels import LANES as LANES
from microslip.model.capabilities import require
from microslip.model.coefficients import pack
from microslip.model.composition import Model, as_model
from microslip.model.parameters import Parameters

#: What to use for the tangential parts the steady mean velocity does not cover (its
#: reflected process, identity 5, needs a rigid contact, Coulomb friction, a constant F).
TANGENTIAL_INSTEAD = (
    "the exact steady state needs a rigid contact, Coulomb friction and a constant force "
    "given as force=; use ms.simulate, ms.effective_friction (PrescribedVelocity) or "
    "ms.stick_slip_drive (SpringDrive)"
)

__all__ = ["StickSlipCycle", "mean_velocity", "mean_velocity_grid", "stick_slip_cycle"]

# Table steps per half period: mean velocity to ~1e-11 relative while the contact law is
# smooth along the orbit. With loss of contact and a non-integer m2, y^m2 is not smooth at
# touchdown and the fixed steps lose order there: measured 6.4e-9 (m2 = 1.5) and 8.6e-8
# (m2 = 10/9) at A = 1.3 y0 (tests/validation/test_fact6_steady_state_exponents.py).
ORBIT_STEPS = 256

PAPER_ONLY = {"damping": (None,), "excitation": (None,)}
FALLBACK_PERIODS = 200  # simulated excitation periods where the response is not period-1


@dataclass(frozen=True)
class StickSlipCycle:
    """The steady stick–slip cycle (SI units).

    Attributes
    ----------
    period : normal vibration period T [s]
    slip_time, stick_time : durations of sliding and of sticking per cycle [s]
    slip_distance : distance slid per cycle Δx [m]
    peak_velocity : largest sliding velocity in the cycle [m/s]
    mean_velocity : Δx / T [m/s]
    release_time : time after the highest point of the normal motion at which
        sliding starts, modulo T [s] (NaN without motion)
    """

    period: float
    slip_time: float
    stick_time: float
    slip_distance: float
    peak_velocity: float
    mean_velocity: float
    release_time: float

    @property
    def moves(self) -> bool:
        return self.slip_distance > 0.0


def _checked_params(params: Parameters | Model | None) -> Parameters:
    model = as_model(params)
    require(
        model, "stick_slip_cycle", allowed=PAPER_ONLY,
        instead="use microslip.mean_velocity(model, force=...) for the steady mean velocity",
    )  # fmt: skip
    return model.params


def _cycle_record(params: Parameters, force: float, amplitude: float) -> np.ndarray:
    # F >= 0 only: the closed-form cycle assumes forward sliding (module docstring).
    force = check.force(params, force, nonnegative=True)
    amplitude = check.amplitude(params, amplitude)
    c = pack(params, force)
    record = np.empty(CY_SIZE)
    if amplitude == 0.0:
        record[:] = [_no_vibration(force, c), params.natural_period, 0.0, 0.0, 0.0, np.nan]
        if np.isinf(record[CY_MEAN]):
            record[CY_PERIOD:] = np.nan
        return record
    capacity = orbit.orbit_capacity(ORBIT_STEPS)
    ys, yds, ydds = np.empty(capacity), np.empty(capacity), np.empty(capacity)
    summary = np.empty(orbit.O_SIZE)
    if not orbit.build_half_orbit(amplitude, c, ORBIT_STEPS, ys, yds, summary):
        raise RuntimeError(f"orbit table overflow at amplitude={amplitude!r} m")
    orbit.node_accelerations(ys, summary, c, ydds)
    steady_cycle(force, ys, yds, ydds, summary, c, record)
    return record


def _warn_unbounded(force: float, limit: float, what: str = "mu m g") -> None:
    warnings.warn(
        f"force={force!r} N exceeds {what} = {limit:.6g} N: the slider accelerates "
        "without bound and has no steady mean velocity (returning inf)",
        RuntimeWarning,
        stacklevel=3,
    )


def mean_velocity(
    model_or_params: Model | Parameters | None = None,
    *,
    force: float,
    amplitude: float | None = None,
    initial_normal_state: tuple[float, float] | None = None,
) -> float:
    """Long-time mean sliding velocity v [m/s] (Fig. 7), exact steady state.

    Parameters
    ----------
    model_or_params : Model or Parameters, optional
        The model (the paper's data and parts by default). Parts supported: the
        paper's free vibration; damped free vibration (it decays to rest, so the
        long-time mean is 0 for F < μ m g and unbounded above); any normal excitation
        (the reflected process over one period of the stable periodic normal motion,
        docs/model-facts.md and docs/design.md, sliding on a forced contact).
    force : float
        Constant tangential force F [N], 0 <= F <= 1e6 m g (``params.max_force``).
    amplitude : float, optional
        Free vibration only (required for the paper's model): amplitude
        A = y0 - y_min [m] at the start, 0 <= A <= 1e3 y0. Refused for a forced model.
    initial_normal_state : (y [m], ẏ [m/s]), optional
        Forced models only: the normal state at t = 0 whose steady response is used
        (where several stable periodic responses coexist); default rest at y0.

    Returns
    -------
    float
        0.0 when the slider never moves (F <= μ min N); ``inf`` with a
        ``RuntimeWarning`` when F > μ m g (no steady state; for a prescribed
        penetration the limit is μ times the mean normal force). Where the forced
        response reached is not period-1 the value is a time average of a simulation
        from rest, the x advance over excitation periods 100 to 200 (``RuntimeWarning``
        says so): exact for a steady response of period 1 or 2 (a whole number of its
        periods), up to what is left of the transient after 100 periods (4e-6 to 9e-6
        relative for the period-2 case of tests/validation/test_period_doubling.py).
    """
    model = as_model(model_or_params)
    require(model, "mean_velocity", allowed={}, instead=TANGENTIAL_INSTEAD)
    if model.excitation is None:
        if initial_normal_state is not None:
            raise ValueError(
                "initial_normal_state applies to a model with a normal excitation; the free "
                "vibration starts at rest at y0 - amplitude"
            )
        if model.is_paper:
            if amplitude is None:
                raise ValueError("amplitude [m] is required for the free normal vibration")
            record = _cycle_record(model.params, force, amplitude)
            if np.isinf(record[CY_MEAN]):
                _warn_unbounded(force, model.params.static_friction_force)
            return float(record[CY_MEAN])
        return _damped_free(model, force, amplitude)
    if amplitude is not None:
        raise ValueError(
            f"amplitude={amplitude!r} applies to the free vibration; this model's normal "
            "motion is set by its excitation"
        )
    force = check.force(model.params, force, nonnegative=True)
    from microslip.analysis.forced_sliding import mean_velocities
    from microslip.analysis.periodic import NotPeriodOneError
    from microslip.analysis.sliding_tables import model_sliding_table

    try:
        table = model_sliding_table(model, initial_normal_state)
    except NotPeriodOneError as error:
        return _time_average(model, force, initial_normal_state, str(error))
    value = float(mean_velocities(table, model.params.mu, np.array([force]))[0])
    if np.isinf(value):
        _warn_unbounded(force, model.params.mu * table.mean_normal_force, "mu N_mean")
    return value


def _damped_free(model: Model, force: float, amplitude: float | None) -> float:
    """The damped free vibration decays to rest at y0, where N = m g."""
    params = model.params
    force = check.force(params, force, nonnegative=True)
    if amplitude is not None:
        amplitude = check.amplitude(params, amplitude)
    limit = params.static_friction_force
    if force > limit:
        _warn_unbounded(force, limit)
        return math.inf
    if force == limit and amplitude:
        # G stays bounded: the slider keeps the speed μ max(-ẏ) it had at the end of
        # the transient, which a closed form cannot give.
        raise ValueError(
            f"force={force!r} N equals mu m g on a damped free vibration: the long-time "
            "speed depends on the transient; use microslip.simulate"
        )
    return 0.0


def _time_average(model: Model, force: float, initial_state, reason: str) -> float:
    """x slope of a simulation over the second half of 200 excitation periods."""
    from microslip.simulation import simulate

    warnings.warn(
        f"{reason}; mean_velocity falls back to the time average of a simulation over "
        f"{FALLBACK_PERIODS} excitation periods (second half)",
        RuntimeWarning,
        stacklevel=3,
    )
    period = model.excitation.period
    duration = FALLBACK_PERIODS * period
    start = 0.5 * duration
    state = None if initial_state is None else (initial_state[0], initial_state[1], 0.0, 0.0)
    result = simulate(
        model, force=force, duration=duration, initial_state=state,
        t_eval=np.array([start, duration]),
    )  # fmt: skip
    return float((result.x[-1] - result.x[0]) / (result.t[-1] - result.t[0]))


def stick_slip_cycle(
    params: Parameters | Model | None = None, *, force: float, amplitude: float
) -> StickSlipCycle:
    """The steady stick–slip cycle at force F [N] and amplitude A [m].

    The paper's model only (other parts: :class:`UnsupportedModelError`). Inputs as for
    :func:`mean_velocity`. Raises ``ValueError`` when F > μ m g: the slider then never
    sticks again.
    """
    params = _checked_params(params)
    record = _cycle_record(params, force, amplitude)
    if np.isinf(record[CY_MEAN]):
        raise ValueError(
            f"force={force!r} N exceeds mu m g = {params.static_friction_force:.6g} N: "
            "there is no steady stick-slip cycle"
        )
    period = float(record[CY_PERIOD])
    slip_time = float(record[CY_SLIP_TIME])
    return StickSlipCycle(
        period=period,
        slip_time=slip_time,
        stick_time=period - slip_time,
        slip_distance=float(record[CY_DISTANCE]),
        peak_velocity=float(record[CY_PEAK]),
        mean_velocity=float(record[CY_MEAN]),
        release_time=float(record[CY_RELEASE]),
    )
