"""Exact steady stick–slip cycle and long-time mean velocity (Fig. 7).

See docs/model-facts.md, facts 5–6.

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
and shared by every force.
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
from microslip.model.coefficients import AREA_CN, EXPONENT, GRAVITY, MASS, MU, pack
from microslip.model.contact import reaction
from microslip.model.parameters import Parameters

__all__ = ["StickSlipCycle", "mean_velocity", "mean_velocity_grid", "stick_slip_cycle"]

# Table steps per half period: mean velocity to ~1e-11 relative while the contact law is
# smooth along the orbit. With loss of contact and a non-integer m2, y^m2 is not smooth at
# touchdown and the fixed steps lose order there: measured 6.4e-9 (m2 = 1.5) and 8.6e-8
# (m2 = 10/9) at A = 1.3 y0 (tests/validation/test_fact6_steady_state_exponents.py).
ORBIT_STEPS = 256

# Slots of a cycle record.
CY_MEAN, CY_PERIOD, CY_SLIP_TIME, CY_DISTANCE, CY_PEAK, CY_RELEASE = range(6)
CY_SIZE = 6


@njit(cache=True)
def steady_cycle(force, ys, yds, summary, c, out):
    """Fill ``out`` (CY_* slots, SI units) with the steady cycle under force F [N].

    No motion (F <= μ min|R|): mean velocity 0. No steady state (F > μ m g): mean
    velocity +inf and the other slots NaN.
    """
    period = 2.0 * summary[orbit.O_HALF]
    mu = c[MU]
    mass = c[MASS]
    y_top = summary[orbit.O_TOP]
    threshold = mu * reaction(y_top, 0.0, c)
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
    y_release = (force / (mu * c[AREA_CN])) ** (1.0 / c[EXPONENT])
    t_d = orbit.time_at_height(y_release, ys, yds, summary, c)
    _y, speed_d = orbit.orbit_state(t_d, ys, yds, summary, c)
    accel = (force - mu * mass * c[GRAVITY]) / mass
    # ẋ(t) = accel (t + t_d) + μ (ẏ(t) + speed_d) with the release at t = -t_d (top at 0);
    # it decreases on [t_d, T - t_d], from its peak to accel·T <= 0.
    lo = t_d
    hi = period - t_d
    t = 0.5 * (lo + hi)
    for _ in range(200):
        y, yd = orbit.orbit_state(t, ys, yds, summary, c)
        v = accel * (t + t_d) + mu * (yd + speed_d)
        if v > 0.0:
            lo = t
        else:
            hi = t
        dv = (force - mu * reaction(y, yd, c)) / mass
        t_new = t - v / dv if dv < 0.0 else 0.5 * (lo + hi)
        if not (lo < t_new < hi):
            t_new = 0.5 * (lo + hi)
        converged = abs(t_new - t) <= 2e-16 * period or hi - lo <= 2e-16 * period
        t = t_new
        if converged:
            break
    y_stop, _yd = orbit.orbit_state(t, ys, yds, summary, c)
    slip_time = t + t_d
    distance = (
        0.5 * accel * slip_time * slip_time + mu * (y_stop - y_release) + mu * speed_d * slip_time
    )
    # Just above the threshold these terms cancel down to rounding of y (~1e-13 y0); the
    # slider never moves backwards (F >= 0), so a negative residue is no slip at all.
    distance = max(distance, 0.0)
    out[CY_MEAN] = distance / period
    out[CY_SLIP_TIME] = slip_time
    out[CY_DISTANCE] = distance
    out[CY_PEAK] = max(2.0 * (accel * t_d + mu * speed_d), 0.0)
    out[CY_RELEASE] = period - t_d


@njit(cache=True)
def _no_vibration(force, c):
    """Mean velocity at A = 0: rest up to μ m g, unbounded above."""
    return 0.0 if force <= c[MU] * c[MASS] * c[GRAVITY] else math.inf


@njit(cache=True, parallel=True)
def mean_velocity_grid(forces, amplitudes, c, steps, out):
    """out[i, j] = mean velocity [m/s] at forces[i] [N], amplitudes[j] [m].

    Returns False if an orbit table overflowed (not expected for valid input).
    """
    ok = True
    capacity = 16 * steps + 16
    for j in prange(amplitudes.shape[0]):
        amplitude = amplitudes[j]
        if amplitude == 0.0:
            for i in range(forces.shape[0]):
                out[i, j] = _no_vibration(forces[i], c)
            continue
        ys = np.empty(capacity)
        yds = np.empty(capacity)
        summary = np.empty(orbit.O_SIZE)
        cycle = np.empty(CY_SIZE)
        if not orbit.build_half_orbit(amplitude, c, steps, ys, yds, summary):
            ok = False
            continue
        for i in range(forces.shape[0]):
            steady_cycle(forces[i], ys, yds, summary, c, cycle)
            out[i, j] = cycle[CY_MEAN]
    return ok


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


def _checked_params(params: Parameters | None) -> Parameters:
    params = Parameters() if params is None else params
    if not isinstance(params, Parameters):
        raise ValueError(f"params must be a microslip.Parameters, got {type(params).__name__}")
    return params


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
    ys, yds, summary = np.empty(capacity), np.empty(capacity), np.empty(orbit.O_SIZE)
    if not orbit.build_half_orbit(amplitude, c, ORBIT_STEPS, ys, yds, summary):
        raise RuntimeError(f"orbit table overflow at amplitude={amplitude!r} m")
    steady_cycle(force, ys, yds, summary, c, record)
    return record


def _warn_unbounded(params: Parameters, force: float) -> None:
    warnings.warn(
        f"force={force!r} N exceeds mu m g = {params.static_friction_force:.6g} N: the "
        "slider accelerates without bound and has no steady mean velocity (returning inf)",
        RuntimeWarning,
        stacklevel=3,
    )


def mean_velocity(params: Parameters | None = None, *, force: float, amplitude: float) -> float:
    """Long-time mean sliding velocity v [m/s] (Fig. 7), exact steady state.

    Parameters
    ----------
    params : Parameters, optional
        Model constants (paper's data by default).
    force : float
        Constant tangential force F [N], 0 <= F <= 1e6 m g (``params.max_force``).
    amplitude : float
        Normal vibration amplitude A = y0 - y_min [m], 0 <= A <= 1e3 y0
        (``params.max_amplitude``).

    Returns
    -------
    float
        0.0 exactly when F <= μ S c_n max(y0 - A, 0)^m2 (the slider never moves);
        ``inf`` with a ``RuntimeWarning`` when F > μ m g (no steady state).
    """
    params = _checked_params(params)
    record = _cycle_record(params, force, amplitude)
    if np.isinf(record[CY_MEAN]):
        _warn_unbounded(params, force)
    return float(record[CY_MEAN])


def stick_slip_cycle(
    params: Parameters | None = None, *, force: float, amplitude: float
) -> StickSlipCycle:
    """The steady stick–slip cycle at force F [N] and amplitude A [m].

    Inputs as for :func:`mean_velocity`. Raises ``ValueError`` when F > μ m g: the
    slider then never sticks again.
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
