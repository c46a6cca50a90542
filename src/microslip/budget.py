"""Up-front estimates of steps, run time and memory, and refusal of jobs that exceed them.

Before a long job starts, :func:`microslip.simulate`, :func:`microslip.sweep`,
:func:`microslip.velocity_map` and the CLI estimate its work from the inputs alone (no
compilation, no integration, well under a second) and raise :class:`WorkLimitError`,
one line naming the estimate and the limit, when

* the estimated run time exceeds ``TIME_LIMIT_S`` (10 minutes), or
* the estimated memory exceeds ``MEMORY_FRACTION`` (50 %) of the memory available now
  (``MemAvailable`` of ``/proc/meminfo``, else ``sysconf``'s available pages, else the
  total; also bounded by a cgroup memory limit where there is one).

``allow_large=True`` (CLI: ``--allow-large``) skips the refusal. The estimates are
deliberately conservative (they may overstate the work up to ~2-3 times, never
understate it by much); their rates are measured constants of this module.

:func:`~microslip.mean_velocity` and :func:`~microslip.stick_slip_cycle` are not
checked: each builds one half orbit in a table of fixed size (at most ~4 000 nodes) and
finishes in well under a millisecond for any valid input.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from microslip import validation
from microslip.machine import available_memory
from microslip.model.parameters import Parameters
from microslip.validation import DEFAULT_RK4_STEPS_PER_PERIOD

__all__ = [
    "DEFAULT_MAX_SAMPLES",
    "MEMORY_FRACTION",
    "TIME_LIMIT_S",
    "Estimate",
    "WorkLimitError",
    "available_memory",
    "check",
    "check_fits",
    "default_save_every",
    "duration_text",
    "estimate_simulation",
    "event_steps_per_period",
]

TIME_LIMIT_S = 600.0  # a sane default: 10 minutes
MEMORY_FRACTION = 0.5  # of the memory available when the job starts
DEFAULT_MAX_SAMPLES = 1_000_000  # default_save_every: ~100 MB of NetCDF output at most

# -- measured rates ------------------------------------------------------------------------
# Measured 2026-11-23 on the project's 2-core development machine (AVX-512; load average
# 1-2 from other jobs), warm numba cache, by timing simulate() over 0.5 s of the paper's
# case (F = 0.5 N, A = 1.5e-7 m), compute_chunk() on 256 x 256, 4 x 1024 and 2048 x 4
# steady grids and on a 64 x 64 "time" chunk of 0.01 s; then rounded up by ~50 %.
EVENT_S_PER_STEP = 0.5e-6  # measured 0.31 us per DOP853 step (0.37 us keeping every step)
RK4_S_PER_STEP = 0.25e-6  # measured 0.15 us per RK4 step (0.19 us keeping every step)
S_PER_SAMPLE = 0.1e-6  # measured ~0.05 us per kept sample, on top of the step

# DOP853 work per normal period T0 = 1/f0 (accepted + rejected steps + switching
# instants), the worst of m2 in {1, 1.5, 2, 3}, F/(mu m g) in {-0.5, 0, 0.3, 0.9, 2},
# A/y0 in {0, 0.3, 0.99, 1.5, 10, 1000} over 50 T0, measured 2026-11-23; the worst case
# was m2 = 1, A = 1.5 y0 throughout. Interpolated in log rtol, times EVENT_SAFETY.
_EVENT_RTOL = np.array([1e-13, 1e-11, 1e-9, 1e-6, 1e-3])
_EVENT_STEPS_PER_PERIOD = np.array([116.6, 94.9, 76.9, 48.0, 23.2])
EVENT_SAFETY = 1.2
# Switching instants per T0 (release, stop, loss and return of contact, and reversals),
# an upper bound: each is an extra output boundary and an extra event record.
EVENTS_PER_PERIOD = 6.0

# Memory per kept sample [bytes]: the driver's per-buffer copies and their concatenation
# (t, 4 states, direction: 2 x 48 B), and the derived and output variables of
# SimulationResult.to_xarray() (R, Ft, xddot, state, copies: ~100 B).
BYTES_PER_SAMPLE = 200
BYTES_PER_EVENT = 150
DRIVER_BUFFER_BYTES = (1 << 16) * 48 + (1 << 14) * 48  # integrators.driver buffers


class WorkLimitError(ValueError):
    """A job whose estimated run time or memory exceeds the limits (one-line message)."""


@dataclass(frozen=True)
class Estimate:
    """Estimated work of a job: ``work`` (e.g. 1e9) ``unit`` (e.g. "steps"), run time [s]
    and peak memory [bytes]."""

    what: str
    work: float
    unit: str
    seconds: float
    bytes: float


def duration_text(seconds: float) -> str:
    """``seconds`` [s] as text in s, min, h or days (3 significant digits)."""
    if seconds < 120.0:
        return f"{seconds:.3g} s"
    if seconds < 7200.0:
        return f"{seconds / 60.0:.3g} min"
    if seconds < 172800.0:
        return f"{seconds / 3600.0:.3g} h"
    return f"{seconds / 86400.0:.3g} days"


def _bytes_text(size: float) -> str:
    for unit, scale in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if size >= scale:
            return f"{size / scale:.3g} {unit}"
    return f"{size:.0f} B"


def check(estimate: Estimate, *, allow_large: bool = False) -> None:
    """Raise :class:`WorkLimitError` if ``estimate`` exceeds the time or memory limit."""
    if allow_large:
        return
    available = available_memory()
    memory_limit = MEMORY_FRACTION * available
    if estimate.seconds <= TIME_LIMIT_S and estimate.bytes <= memory_limit:
        return
    raise WorkLimitError(
        f"{estimate.what}: estimated {estimate.work:.3g} {estimate.unit}, "
        f"{duration_text(estimate.seconds)} run time and {_bytes_text(estimate.bytes)} memory; "
        f"limits {duration_text(TIME_LIMIT_S)} run time and {_bytes_text(memory_limit)} memory "
        f"({MEMORY_FRACTION:.0%} of the {_bytes_text(available)} available); "
        "pass allow_large=True (CLI: --allow-large) to go ahead anyway"
    )


def check_fits(estimate: Estimate) -> None:
    """Raise :class:`WorkLimitError` if ``estimate`` needs more memory than is available
    at all: such a job cannot run, so ``allow_large`` does not lift this check."""
    available = available_memory()
    if estimate.bytes <= available:
        return
    raise WorkLimitError(
        f"{estimate.what}: estimated {_bytes_text(estimate.bytes)} memory, more than the "
        f"{_bytes_text(available)} available; make the grid smaller or split it"
    )


# -- simulate -------------------------------------------------------------------------------
def event_steps_per_period(rtol: float) -> float:
    """Conservative DOP853 steps (with rejections and switches) per T0 at ``rtol``."""
    log_rtol = math.log10(rtol)
    logs = np.log10(_EVENT_RTOL)
    if log_rtol < logs[0]:  # order 8: steps grow like rtol^(-1/8)
        spp = _EVENT_STEPS_PER_PERIOD[0] * 10.0 ** ((logs[0] - log_rtol) / 8.0)
    else:
        spp = float(np.interp(log_rtol, logs, _EVENT_STEPS_PER_PERIOD))
    return EVENT_SAFETY * spp


def shortest_period(model: Any) -> float:
    """The period [s] a step must resolve: T0 = 1/f0 for a Parameters; for a
    :class:`~microslip.model.composition.Model` the shortest of T0, the excitation
    period, the drive period (HarmonicDrive) and the tangential oscillation of the body
    on its springs, 2π sqrt(m / (k_t + k_d)) (k_t of a compliant contact, Mindlin's at
    the static deflection; k_d of a SpringDrive; none under a kinematic drive)."""
    params = getattr(model, "params", model)
    period = params.natural_period
    excitation = getattr(model, "excitation", None)
    if excitation is not None:
        period = min(period, excitation.period)
    drive = getattr(model, "drive", None)
    if drive is None or getattr(model, "is_kinematic", False):
        stiffness = 0.0
    else:
        stiffness = getattr(drive, "stiffness", 0.0)
        if getattr(drive, "frequency", 0.0) > 0.0:
            period = min(period, 1.0 / drive.frequency)
    tangential = getattr(model, "tangential", None)
    if stiffness > 0.0 or (tangential is not None and not getattr(model, "is_kinematic", True)):
        if hasattr(tangential, "stiffness"):
            stiffness += tangential.stiffness
        elif hasattr(tangential, "ratio"):
            stiffness += tangential.ratio * params.contact_stiffness
        if stiffness > 0.0:
            period = min(period, 2.0 * math.pi * math.sqrt(params.mass / stiffness))
    return period


def _boundaries(
    params: Any, duration: float, method: str, dt: float | None, rtol: float
) -> tuple[float, float]:
    """(steps, output boundaries) of a run: the boundaries include switching instants.

    ``params``: a Parameters or a Model; periods count in :func:`shortest_period`.
    """
    period = shortest_period(params)
    periods = duration / period
    events = EVENTS_PER_PERIOD * periods
    if method == "rk4":
        step = period / DEFAULT_RK4_STEPS_PER_PERIOD if dt is None else dt
        steps = math.ceil(duration / step)
    else:
        steps = event_steps_per_period(rtol) * periods
    return float(steps), float(steps + events)


def estimate_simulation(
    params: Parameters | Any,
    *,
    duration: float,
    method: str,
    dt: float | None = None,
    rtol: float = 1e-11,
    n_t_eval: int | None = None,
    save_every: int = 1,
) -> Estimate:
    """Steps, run time [s] and memory [bytes] of ``simulate`` with these (validated) inputs.

    ``params``: a Parameters or a Model (with an excitation, the periods below count in
    min(T0, excitation period), :func:`shortest_period`).
    Steps: duration/dt for "rk4"; for "event" the periods duration/T0 times the measured
    steps per period at ``rtol`` (:func:`event_steps_per_period`). Samples kept:
    ``n_t_eval`` if given, else (steps + switching instants)/``save_every``. Memory: the
    samples and switching instants at ``BYTES_PER_SAMPLE`` and ``BYTES_PER_EVENT`` each,
    plus the driver's buffers.
    """
    steps, boundaries = _boundaries(params, duration, method, dt, rtol)
    samples = float(n_t_eval) if n_t_eval is not None else boundaries / save_every + 2.0
    events = EVENTS_PER_PERIOD * duration / shortest_period(params)
    per_step = RK4_S_PER_STEP if method == "rk4" else EVENT_S_PER_STEP
    return Estimate(
        what=f"simulate (method={method!r}, duration={duration:g} s)",
        work=steps,
        unit="steps",
        seconds=steps * per_step + samples * S_PER_SAMPLE,
        bytes=samples * BYTES_PER_SAMPLE + events * BYTES_PER_EVENT + DRIVER_BUFFER_BYTES,
    )


def default_save_every(
    params: Parameters | Any,
    *,
    duration: float,
    method: str,
    dt: float | None = None,
    max_samples: int = DEFAULT_MAX_SAMPLES,
    rtol: float = 1e-11,
) -> int:
    """Smallest n >= 1 such that keeping every n-th step boundary keeps at most
    ``max_samples`` samples (estimated, see :func:`estimate_simulation`).

    ``params`` a Parameters or a Model; ``duration`` [s], ``dt`` [s] (RK4; default
    min(T0, excitation period)/200) and ``rtol`` as for ``simulate``;
    they are validated here too (``ValueError`` naming the field), since the CLI calls
    this before :func:`microslip.simulate`.
    """
    duration = validation.real("duration", duration, minimum=0.0, strict=True)
    method = validation.one_of("method", method, ("event", "rk4"))
    rtol = validation.real("rtol", rtol, minimum=0.0, strict=True)
    max_samples = validation.positive_int("max_samples", max_samples)
    if dt is not None:
        dt = validation.real("dt", dt, minimum=0.0, strict=True)
    _steps, boundaries = _boundaries(params, duration, method, dt, rtol)
    return max(1, math.ceil(boundaries / max_samples))
