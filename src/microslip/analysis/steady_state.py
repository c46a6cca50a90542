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
(:func:`orbit.steady_slip`).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
from numba import njit, prange

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip import validation as check
from microslip.analysis import orbit
from microslip.model.capabilities import require
from microslip.model.coefficients import AREA_CN, EXPONENT, GRAVITY, MASS, MU, pack
from microslip.model.composition import Model, as_model
from microslip.model.contact import elastic_force
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
BATCH_AMPLITUDES = 32  # orbit tables held at once by mean_velocity_grid
LANES = 16  # force lanes per amplitude: the work units of mean_velocity_grid

# Slots of a cycle record.
CY_MEAN, CY_PERIOD, CY_SLIP_TIME, CY_DISTANCE, CY_PEAK, CY_RELEASE = range(6)
CY_SIZE = 6

PAPER_ONLY = {"damping": (None,), "excitation": (None,)}
FALLBACK_PERIODS = 200  # simulated excitation periods where the response is not period-1


@njit(cache=True, inline="always")
def _release_height(force, c):
    """y* [m] where μ|R| = F [N] (2.3); 0 for F <= 0."""
    return (force / (c[MU] * c[AREA_CN])) ** (1.0 / c[EXPONENT]) if force > 0.0 else 0.0


@njit(cache=True)
def steady_cycle(force, ys, yds, ydds, summary, c, out):
    """Fill ``out`` (CY_* slots, SI units) with the steady cycle under force F [N].

    ``ydds`` holds the node accelerations (:func:`orbit.node_accelerations`). No motion
    (F <= μ min|R|): mean velocity 0. No steady state (F > μ m g): mean velocity +inf
    and the other slots NaN.
    """
    period = 2.0 * summary[orbit.O_HALF]
    mu = c[MU]
    mass = c[MASS]
    threshold = mu * elastic_force(summary[orbit.O_TOP], c)
    out[CY_PERIOD] = period
    if not force > threshold:
        out[CY_MEAN] = 0.0
        out[CY_SLIP_TIME] = 0.0
        out[CY_DISTANCE] = 0.0
        out[CY_PEAK] = 0.0
        out[CY_RELEASE] = math.nan
        return
    if force > mu * mass * c[GRAVITY]:
        out[CY_MEAN] = math.inf
        for k in range(CY_PERIOD, CY_SIZE):
            out[k] = math.nan
        return
    accel = (force - mu * mass * c[GRAVITY]) / mass
    slip_time, distance, peak, t_d = orbit.steady_slip(
        _release_height(force, c), accel, mu, ys, yds, ydds, summary
    )
    out[CY_MEAN] = distance / period
    out[CY_SLIP_TIME] = slip_time
    out[CY_DISTANCE] = distance
    out[CY_PEAK] = peak
    out[CY_RELEASE] = period - t_d


@njit(cache=True)
def _no_vibration(force, c):
    """Mean velocity at A = 0: rest up to μ m g, unbounded above."""
    return 0.0 if force <= c[MU] * c[MASS] * c[GRAVITY] else math.inf


@njit(cache=True, error_model="numpy")
def _force_lane(first, stride, forces, y_release, accel, c, ys, yds, ydds, summary, out, j):
    """out[i, j] = mean velocity [m/s] for forces i = first, first + stride, ... on one
    amplitude's orbit table (a work unit of :func:`mean_velocity_grid`; one compiled call
    per unit, with :func:`orbit.steady_slip` inlined: per point, a call would count the
    table's arrays)."""
    mu = c[MU]
    limit = mu * c[MASS] * c[GRAVITY]
    period = 2.0 * summary[orbit.O_HALF]
    threshold = mu * elastic_force(summary[orbit.O_TOP], c)
    for i in range(first, forces.shape[0], stride):
        force = forces[i]
        if not force > threshold:
            out[i, j] = 0.0
        elif force > limit:
            out[i, j] = math.inf
        else:
            _t, distance, _p, _d = orbit.steady_slip(
                y_release[i], accel[i], mu, ys, yds, ydds, summary
            )
            out[i, j] = distance / period


@njit(cache=True, parallel=True)
def mean_velocity_grid(forces, amplitudes, c, steps, out):
    """out[i, j] = mean velocity [m/s] at forces[i] [N], amplitudes[j] [m].

    Amplitudes are taken in batches: their orbit tables are built in parallel, then the
    batch's points are shared out in work units of one amplitude and one lane of forces
    (every LANES-th force, so that each unit spans the whole force range). Each point is
    computed on its own (no state carried between points), so the result is bit-identical
    whatever the grid's split and the thread count. Returns False if an orbit table
    overflowed (not expected for valid input).
    """
    n_f = forces.shape[0]
    n_a = amplitudes.shape[0]
    mu = c[MU]
    mass = c[MASS]
    limit = mu * mass * c[GRAVITY]
    y_release = np.empty(n_f)  # depends on F only: shared by every amplitude
    accel = np.empty(n_f)
    for i in range(n_f):
        y_release[i] = _release_height(forces[i], c)
        accel[i] = (forces[i] - limit) / mass
    capacity = 16 * steps + 16  # orbit.orbit_capacity
    batch = max(min(n_a, BATCH_AMPLITUDES), 1)
    ys = np.empty((batch, capacity))
    yds = np.empty((batch, capacity))
    ydds = np.empty((batch, capacity))
    summary = np.zeros((batch, orbit.O_SIZE))
    state = np.zeros(batch, dtype=np.int64)  # 0: A = 0, 1: table built, 2: overflow
    lanes = max(min(n_f, LANES), 1)
    failed = False
    for start in range(0, n_a, batch):
        count = min(batch, n_a - start)
        for b in prange(count):
            amplitude = amplitudes[start + b]
            state[b] = 0
            if amplitude != 0.0:
                state[b] = 2
                if orbit.build_half_orbit(amplitude, c, steps, ys[b], yds[b], summary[b]):
                    orbit.node_accelerations(ys[b], summary[b], c, ydds[b])
                    state[b] = 1
        for unit in prange(count * lanes):
            b = unit // lanes
            j = start + b
            if state[b] == 0:
                for i in range(unit % lanes, n_f, lanes):
                    out[i, j] = _no_vibration(forces[i], c)
                continue
            if state[b] == 2:
                continue
            _force_lane(
                unit % lanes, lanes, forces, y_release, accel, c, ys[b], yds[b], ydds[b],
                summary[b], out, j,
            )  # fmt: skip
        for b in range(count):
            failed = failed or state[b] == 2
    return not failed


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
