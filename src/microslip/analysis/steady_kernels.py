"""Compiled kernels of the exact steady stick–slip cycle (:mod:`microslip.analysis.steady_state`).

``steady_cycle`` fills a cycle record (the ``CY_*`` slots: mean velocity [m/s], period
[s], slip time [s], slip distance [m], peak velocity [m/s], release time [s]) for one
force F [N] on one amplitude's orbit table (:mod:`microslip.analysis.orbit`);
``mean_velocity_grid`` computes the mean velocity [m/s] over forces [N] × amplitudes [m]
(Fig. 7), its work units run over the threads by
:func:`~microslip.integrators.threads.run_ranges`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.analysis import orbit
from microslip.integrators import threads
from microslip.integrators.kernel import as_tuple
from microslip.model.coefficients import AREA_CN, EXPONENT, GRAVITY, MASS, MU
from microslip.model.contact import elastic_force

BATCH_AMPLITUDES = 32  # orbit tables held at once by mean_velocity_grid
LANES = 16  # force lanes per amplitude: the work units of mean_velocity_grid

# Slots of a cycle record.
CY_MEAN, CY_PERIOD, CY_SLIP_TIME, CY_DISTANCE, CY_PEAK, CY_RELEASE = range(6)
CY_SIZE = 6


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
    threshold = mu * elastic_force(summary[orbit.O_TOP], as_tuple(c))
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
    threshold = mu * elastic_force(summary[orbit.O_TOP], as_tuple(c))
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


def mean_velocity_grid(forces, amplitudes, c, steps, out):
    """out[i, j] = mean velocity [m/s] at forces[i] [N], amplitudes[j] [m].

    Amplitudes are taken in batches: their orbit tables are built in parallel, then the
    batch's points are shared out in work units of one amplitude and one lane of forces
    (every LANES-th force, so that each unit spans the whole force range), each phase over
    the threads (:func:`~microslip.integrators.threads.run_ranges`). Each point is
    computed on its own (no state carried between points), so the result is bit-identical
    whatever the grid's split and the thread count. Returns False if an orbit table
    overflowed (not expected for valid input).
    """
    n_f = forces.shape[0]
    n_a = amplitudes.shape[0]
    y_release, accel = _force_terms(forces, c)  # depend on F only: shared by every amplitude
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
        threads.run_ranges(  # 32 orbit tables: ~0.4 ms, short (threads.run_ranges)
            _build_tables, count, start, amplitudes, c, steps, ys, yds, ydds, summary, state,
            interruptible=False,
        )  # fmt: skip
        threads.run_ranges(
            _grid_units, count * lanes, start, lanes, forces, y_release, accel, c, ys, yds,
            ydds, summary, state, out,
        )  # fmt: skip
        failed = failed or bool(np.any(state[:count] == 2))
    return not failed


@njit(cache=True)
def _force_terms(forces, c):
    """(release height [m], slip acceleration F/m - μ g [m/s^2]) of each force [N]."""
    limit = c[MU] * c[MASS] * c[GRAVITY]
    y_release = np.empty(forces.shape[0])
    accel = np.empty(forces.shape[0])
    for i in range(forces.shape[0]):
        y_release[i] = _release_height(forces[i], c)
        accel[i] = (forces[i] - limit) / c[MASS]
    return y_release, accel


@njit(cache=True, nogil=True)
def _build_tables(lo, hi, start, amplitudes, c, steps, ys, yds, ydds, summary, state):
    """Orbit tables b in [lo, hi) of the batch from amplitude ``start`` (a phase of
    :func:`mean_velocity_grid`)."""
    for b in range(lo, hi):
        amplitude = amplitudes[start + b]
        state[b] = 0
        if amplitude != 0.0:
            state[b] = 2
            if orbit.build_half_orbit(amplitude, c, steps, ys[b], yds[b], summary[b]):
                orbit.node_accelerations(ys[b], summary[b], c, ydds[b])
                state[b] = 1


@njit(cache=True, nogil=True)
def _grid_units(lo, hi, start, lanes, forces, y_release, accel, c, ys, yds, ydds, summary,
                state, out):  # fmt: skip
    """Work units [lo, hi) of the batch from amplitude ``start``: unit u is amplitude
    start + u // lanes, forces u % lanes, + lanes, ... (a phase of
    :func:`mean_velocity_grid`)."""
    n_f = forces.shape[0]
    for unit in range(lo, hi):
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
