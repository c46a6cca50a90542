"""Checks at the API boundary: one clear ``ValueError`` naming the field and its value."""

from __future__ import annotations

import math
from typing import Any

import numpy as np


def real(name: str, value: Any, *, minimum: float | None = None, strict: bool = False) -> float:
    """``value`` as a finite float, optionally bounded below (``strict``: > minimum)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ValueError(f"{name} must be a real number, got {value!r}")
    try:
        value = float(value)
    except OverflowError:  # a Python int beyond the float range, e.g. 10**400
        raise ValueError(
            f"{name} must be finite, got an integer of {len(str(value))} digits"
        ) from None
    if not math.isfinite(value):
        raise ValueError(f"{name} must be finite, got {value!r}")
    if minimum is not None:
        if strict and value <= minimum:
            raise ValueError(f"{name} must be > {minimum:g}, got {value!r}")
        if not strict and value < minimum:
            raise ValueError(f"{name} must be >= {minimum:g}, got {value!r}")
    return value


def _short(value: Any) -> str:
    """repr of ``value``, cut to one readable line."""
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."


def positive_int(name: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    return int(value)


def one_of(name: str, value: Any, choices: tuple[str, ...]) -> str:
    if value not in choices:
        raise ValueError(f"{name} must be one of {', '.join(choices)}; got {value!r}")
    return value


def real_array(name: str, values: Any) -> np.ndarray:
    """A 1-D float array with finite entries.

    Only numbers are accepted: None, strings (also "0.3" or ["0.3"]), booleans and
    objects numpy cannot hold as numbers (e.g. Python ints beyond the float range) are
    refused rather than converted.
    """

    def not_real() -> ValueError:  # built only when raised: a repr of 1e3 values takes ms
        return ValueError(f"{name} must be an array of real numbers, got {_short(values)}")

    if values is None or isinstance(values, (str, bytes)):
        raise not_real()
    try:
        array = np.asarray(values)
    except (TypeError, ValueError, OverflowError):
        raise not_real() from None
    if array.dtype.kind not in "iuf":
        raise not_real()
    array = array.astype(float, copy=False)
    if array.ndim == 0:
        array = array.reshape(1)
    if array.ndim != 1:
        raise ValueError(f"{name} must be one-dimensional, got shape {array.shape}")
    if array.size == 0:
        raise ValueError(f"{name} must not be empty")
    bad = ~np.isfinite(array)
    if bad.any():
        raise ValueError(
            f"{name} must be finite, got {float(array[bad][0])!r} at index {np.argmax(bad)}"
        )
    return array


# An RK4 step must resolve the contact vibration: at most this fraction of T0 = 1/f0.
RK4_MAX_STEP_FRACTION = 0.1
# The default RK4 step dt = T0/200 (simulate, time-domain sweeps, work estimates).
DEFAULT_RK4_STEPS_PER_PERIOD = 200


def rk4_step(dt: float, period: float, *, where: str = "") -> None:
    """Refuse an RK4 step ``dt`` [s] that does not resolve the normal period ``period`` [s].

    ``dt`` must be <= ``RK4_MAX_STEP_FRACTION`` T0: a coarser step misses the contact
    vibration and returns meaningless velocities. ``where`` names the parameter set
    (for sweeps: the one with the shortest T0).
    """
    limit = RK4_MAX_STEP_FRACTION * period
    if dt > limit:
        raise ValueError(
            f"dt={dt!r} s is too large to resolve the contact vibration{where} "
            f"(T0 = {period:.4g} s); use dt <= {limit:.4g} s"
        )


def force(params: Any, value: Any, *, name: str = "force", nonnegative: bool = False) -> float:
    """A force [N] within ``params.max_force`` = 1e6 m g (and >= 0 if ``nonnegative``)."""
    value = real(name, value)
    if nonnegative and value < 0.0:
        raise ValueError(
            f"{name} must be >= 0 N here (the steady state is computed for forward "
            f"sliding only; simulate() accepts F < 0), got {value!r}"
        )
    if abs(value) > params.max_force:
        raise ValueError(
            f"|{name}|={abs(value)!r} N exceeds the supported 1e6 m g = {params.max_force:.6g} N"
        )
    return value


def amplitude(params: Any, value: Any, *, name: str = "amplitude") -> float:
    """An amplitude A = y0 - y_min [m] in [0, ``params.max_amplitude`` = 1e3 y0]."""
    value = real(name, value, minimum=0.0)
    if value > params.max_amplitude:
        raise ValueError(
            f"{name}={value!r} m exceeds the supported 1e3 y0 = {params.max_amplitude:.6g} m"
        )
    return value


# Tolerances of the event method. rtol below ~50 unit roundoffs (2.2e-16) asks DOP853 for
# more than double precision gives (Hairer's dop853 refuses rtol < 10 eps for the same
# reason); above 1e-2 the switching instants and the mean velocity lose every digit.
# atol is in units of the natural scales (y0, y0 ω0, μ y0, μ y0 ω0): below the unit
# roundoff it cannot be met on a state of the natural size, above 1e-2 it allows errors
# of a percent of the static deflection.
RTOL_RANGE = (1e-14, 1e-2)
ATOL_RANGE = (1e-16, 1e-2)
# Shortest simulated time, in normal periods T0 = 1/f0: below it the run is one step
# much shorter than any switching, and x(T)/T is rounding noise (1e-300 s gave v = 0).
MIN_DURATION_PERIODS = 1e-6


def tolerance(name: str, value: Any, bounds: tuple[float, float]) -> float:
    """A tolerance within ``bounds`` (``RTOL_RANGE`` or ``ATOL_RANGE``)."""
    value = real(name, value)
    low, high = bounds
    if not low <= value <= high:
        raise ValueError(f"{name}={value!r} is outside the supported range [{low:g}, {high:g}]")
    return value


def duration(value: Any, period: float, *, name: str = "duration", where: str = "") -> float:
    """A simulated time [s] of at least ``MIN_DURATION_PERIODS`` normal periods ``period``."""
    value = real(name, value, minimum=0.0, strict=True)
    shortest = MIN_DURATION_PERIODS * period
    if value < shortest:
        raise ValueError(
            f"{name}={value!r} s is shorter than {MIN_DURATION_PERIODS:g} T0 = {shortest:.4g} s"
            f"{where} (T0 = {period:.4g} s)"
        )
    return value


# Most values on one axis of a sweep (force, amplitude, a swept field), also the most a
# range start:stop:count may produce: 1e7 values are 80 MB as an array and several
# hundred MB as the sweep's per-value definition; a grid needs far fewer per axis.
MAX_AXIS_VALUES = 10_000_000
