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
import os
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
    "batch_threads",
    "check",
    "check_fits",
    "default_save_every",
    "estimate_simulation",
    "estimate_sweep",
    "event_steps_per_period",
    "shared_chunk_rounds",
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
STEADY_S_PER_ORBIT = 20e-6  # measured 13.5 us per half-orbit table (per amplitude)
# Re-measured 2026-11-24 after the table-read steady kernel (steady_state.mean_velocity_grid,
# idle 2-core machine, both threads): 214 ns per point on 1e6 x 3, 223 ns on 1000 x 1000,
# 213 ns on 2048 x 2048; rounded up ~3x (the machine may be loaded).
STEADY_S_PER_POINT = 0.6e-6
# "time" sweeps (microslip.integrators.shared_lanes): each normal set-up of a chunk (an
# amplitude, or the one forced set-up) integrates its normal tape once, the set-ups in
# parallel over the threads, and advances every force of it on the tape. Measured
# 2026-11-24 on the paper's data, dt = T0/200, idle 2-core machine: 66 ns per set-up
# step (the tape) on one thread, and 1.9 ns per lane-step per thread over a 256 x 256
# map (0.05 s), switches included (~1 in 100 lane-steps, ~0.1-0.2 us each). Rounded up
# ~3x and ~2x (the machine may be loaded). A free vibration's repeated tape takes a
# fraction of this work (PARKED_LANE_PERIODS below).
SHARED_S_PER_SETUP_STEP = 0.2e-6
SHARED_S_PER_LANE_STEP = 4e-9
# On a free vibration's repeated tape (integrators/periodic_tape.py) a set-up's tape is
# one period and the tail, and a rigid lane that starts a period as it started the last
# one takes the rest at once (integrators/lane_parking.py); one that accelerates for
# ever (F > μ m g) never does. Measured 2026-11-27, the paper's 256 x 64 map, 1 thread:
# 0.029, 0.038 and 0.054 s over 20, 74 and 297 periods, against 4.5 ms per period with
# every lane stepped: 6-8 periods' worth (the last run's extra is its A = 0 set-up, which
# has no period); rounded up 2x.
PARKED_LANE_PERIODS = 16.0
# A "time" chunk's own cost (its models, lane arrays, tapes' set-up, the thread hand-out):
# measured 0.95 ms for a chunk of one lane on one set-up over 400 periods (its lane
# parked), 2026-11-27.
TIME_S_PER_CHUNK = 1e-3
# Building a repeating set-up's one-period tape (periodic_tape.cycles, Python around the
# compiled fill_tape): measured 0.047-0.053 ms per set-up, 2026-11-27; rounded up 3x.
TIME_S_PER_CYCLE = 0.15e-3
# One tape buffer per thread (normal_tape.TAPE_ROWS x ROW) and a piece vector.
TAPE_BYTES = 2048 * 21 * 8 + 4096
# "time" sweeps of a MindlinSpring whose contact exponent the Mindlin lanes do not run
# (microslip.integrators.batched): every lane-step is the generic RK4 step with the
# model's switching, the lanes in blocks over the threads. Measured 2026-11-26, 64 forces
# x 16 set-ups, 0.02 s, 2 threads: 0.42 us per lane-step per thread (TangentialSpring,
# free vibration), 1.34 us (MindlinSpring, Viscous + HarmonicForce); rounded up ~3x.
BATCHED_S_PER_LANE_STEP = 4e-6
# "time" sweeps of a TangentialSpring (microslip.integrators.spring_lanes): the tapes as
# above, each lane-step the contact point's closed forms. Measured 2026-11-26, 64 forces
# x 16 amplitudes, 0.05 s, dt = 1/200 of the tangential period, 2 threads: 12 ns per
# lane-step per thread, switches included (~2 % of the lane-steps are searched, ~0.4 us
# each); rounded up ~2.5x.
SPRING_S_PER_LANE_STEP = 3e-8
# "time" sweeps of a MindlinSpring (microslip.integrators.mindlin_lanes): the same lanes'
# cost, and per set-up step the tape and the piece's stiffness, stop-function quartics
# and stick series. Measured 2026-11-26, 8 set-ups x 1 and x 256 forces, 0.05 s, 1
# thread: 0.38-0.53 us per set-up step, 5-6 ns per lane-step; rounded up ~3x (the lanes
# as SPRING_S_PER_LANE_STEP).
MINDLIN_S_PER_SETUP_STEP = 1.5e-6

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
# Sweeps: the result array, the copy read back from the store, the Dataset written out.
SWEEP_BYTES_PER_POINT = 32
BATCH_BYTES_PER_LANE = 256  # coefficients, initial and final states, block scratch
# A Python float in a tuple (32 B), its repr in the JSON definition and fingerprint.
BYTES_PER_AXIS_VALUE = 200
STEADY_BYTES_PER_AMPLITUDE = 3 * 8 * (16 * 256 + 16)  # one orbit table (ys, yds, ydds)
STEADY_TABLES_HELD = 32  # steady_state.BATCH_AMPLITUDES: tables held at once


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


def _duration_text(seconds: float) -> str:
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
        f"{_duration_text(estimate.seconds)} run time and {_bytes_text(estimate.bytes)} memory; "
        f"limits {_duration_text(TIME_LIMIT_S)} run time and {_bytes_text(memory_limit)} memory "
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


# -- sweeps ---------------------------------------------------------------------------------
def batch_threads() -> int:
    """Threads the batched kernel runs its blocks on: the CPUs this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def shared_chunk_rounds(setups: int, threads: int | None = None) -> int:
    """Set-up rounds of a "time" chunk with ``setups`` normal set-ups, ``threads`` at a
    time (default :func:`batch_threads`): each round integrates one tape per thread."""
    threads = batch_threads() if threads is None else threads
    return -(-int(setups) // threads)


def estimate_sweep(
    *,
    method: str,
    n_sets: int,
    n_forces: int,
    n_amplitudes: int,
    lane_steps: float = 0.0,
    setup_steps: float = 0.0,
    chunk_points: int = 1,
    axis_values: int = 0,
    kernel: str = "shared",
    tape_fraction: float = 1.0,
    lane_fraction: float = 1.0,
    stepped_steps: float = 0.0,
    cycles: int = 0,
    n_chunks: int = 0,
) -> Estimate:
    """Work, run time [s] and memory [bytes] of a sweep.

    ``n_sets`` parameter sets, each on ``n_forces`` x ``n_amplitudes`` points. "steady":
    one orbit table per (set, amplitude) and a cycle per point. "time": ``lane_steps``
    trajectory-steps in all (the work reported); run time from ``setup_steps``, the sum
    over chunks of grid steps x :func:`shared_chunk_rounds` (the tapes, a thread each),
    each round also advancing its ``n_forces`` lanes (``kernel="spring"``: a
    TangentialSpring's lanes; ``kernel="mindlin"``: a MindlinSpring's, whose set-up
    steps cost more); with ``kernel="batched"`` (the set-ups the Mindlin lanes hand back) from
    ``lane_steps`` spread over the threads. Where a free vibration's tape repeats, a
    round costs ``tape_fraction`` and ``lane_fraction`` of the shared-normal kernels'
    tape and lane work (:data:`PARKED_LANE_PERIODS`), each of its ``cycles`` set-ups
    :data:`TIME_S_PER_CYCLE`, and the set-ups that do not repeat ``stepped_steps`` at the
    full cost, each as a round of its own (it cannot be shared out); each of
    ``n_chunks`` time chunks adds :data:`TIME_S_PER_CHUNK`. Memory:
    the result
    (``SWEEP_BYTES_PER_POINT`` per point) and the buffers of the chunk of
    ``chunk_points`` points being computed (an in-process run computes one chunk at a
    time; each Dask worker holds one more), and ``axis_values`` values of all axes
    together at ``BYTES_PER_AXIS_VALUE`` each (the spec's tuples and its definition).
    """
    points = float(n_sets) * n_forces * n_amplitudes
    if method == "steady":
        orbits = float(n_sets) * n_amplitudes
        seconds = orbits * STEADY_S_PER_ORBIT + points * STEADY_S_PER_POINT
        buffers = 8 * chunk_points + STEADY_TABLES_HELD * STEADY_BYTES_PER_AMPLITUDE
        work, unit = points, "points"
    elif kernel == "batched":
        seconds = lane_steps * BATCHED_S_PER_LANE_STEP / batch_threads()
        buffers = BATCH_BYTES_PER_LANE * chunk_points
        work, unit = lane_steps, "trajectory-steps"
    else:
        lane_cost = SHARED_S_PER_LANE_STEP if kernel == "shared" else SPRING_S_PER_LANE_STEP
        setup_cost = MINDLIN_S_PER_SETUP_STEP if kernel == "mindlin" else SHARED_S_PER_SETUP_STEP
        per_step = setup_cost + n_forces * lane_cost
        repeated_step = setup_cost * tape_fraction + n_forces * lane_cost * lane_fraction
        seconds = setup_steps * repeated_step + stepped_steps * per_step
        seconds += cycles * TIME_S_PER_CYCLE
        buffers = BATCH_BYTES_PER_LANE * chunk_points + batch_threads() * TAPE_BYTES
        work, unit = lane_steps, "trajectory-steps"
    if method == "time":
        seconds += n_chunks * TIME_S_PER_CHUNK
    return Estimate(
        what=f"sweep (method={method!r}, {points:.3g} points)",
        work=work,
        unit=unit,
        seconds=seconds,
        bytes=points * SWEEP_BYTES_PER_POINT + buffers + axis_values * BYTES_PER_AXIS_VALUE,
    )
