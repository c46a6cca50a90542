"""The work, run time [s] and memory [bytes] of a sweep, estimated from its sizes alone
(:func:`estimate_sweep`), with the rates of its kernels measured on the project's 2-core
development machine; :mod:`microslip.budget` refuses what exceeds its limits, and
:mod:`microslip.sweeps.kernel_choice` gives the sizes of a sweep's kernel."""

from __future__ import annotations

import math
import os

from microslip.budget import Estimate
from microslip.integrators.batched import block_for
from microslip.integrators.threads import thread_count

__all__ = ["batch_threads", "batched_lane_steps", "estimate_sweep", "shared_chunk_rounds"]

# -- measured rates ------------------------------------------------------------------------
# Measured 2026-11-23 with the rates of microslip.budget (compute_chunk() on 256 x 256,
# 4 x 1024 and 2048 x 4 steady grids, warm cache), rounded up by ~50 %.
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
# every lane stepped: 6-8 periods' worth (the last run's extra was its A = 0 set-up, then
# stepped through every period); rounded up 2x. Once all of a set-up's lanes are
# parked, its periods left cost nothing (shared_lanes._run_cycle).
PARKED_LANE_PERIODS = 16.0
# While any lane of a set-up on a repeated tape is live, the kernel walks every row of
# every period for it: measured 13.6 ns per row with one live lane (a lane at F = μ m g
# that never repeats a period bit for bit), 2026-11-27; rounded up 3x.
SHARED_S_PER_ROW = 40e-9
# A "time" chunk's own cost (its models, lane arrays, tapes' set-up, the thread hand-out):
# measured 0.95 ms for a chunk of one lane on one set-up over 400 periods (its lane
# parked), 2026-11-27.
TIME_S_PER_CHUNK = 1e-3
# Building a repeating set-up's one-period tape (periodic_tape.cycles, Python around the
# compiled fill_tape): measured 0.047-0.053 ms per set-up, 2026-11-27; rounded up 3x.
TIME_S_PER_CYCLE = 0.15e-3
# One tape buffer per thread (normal_tape.TAPE_ROWS x ROW) and a piece vector.
TAPE_BYTES = 2048 * 21 * 8 + 4096
# The set-ups of a "time" sweep that the Mindlin lanes hand back
# (microslip.integrators.batched): every lane-step is the generic RK4 step with the
# model's switching, the lanes in blocks (integrators/batched.block_for) over the
# threads, a run's last block padded (its padding costs as much as its lanes).
# Measured 2026-11-26, 64 forces x 16 set-ups, 0.02 s, 2 threads: 1.34 us per lane-step
# per thread (MindlinSpring, Viscous + HarmonicForce). Re-measured 2026-11-27, m2 = 1.5,
# 512 lanes, 0.005 s, 2 threads: 0.54-0.67 us (free vibration, a flight and two graded
# switches a period), 1.00 us (Viscous + HarmonicForce, 4 N at 1200 Hz). Rounded up
# 1.5x. (Both were 4 us: a 64 x 16 Hertz map with flights was estimated at 68 s and ran
# in 11.3 s.)
BATCHED_S_PER_LANE_STEP = 1.5e-6  # a damped or forced normal motion
BATCHED_FREE_S_PER_LANE_STEP = 1e-6  # a free vibration
# "time" sweeps of a TangentialSpring (microslip.integrators.spring_lanes): the tapes as
# above, each lane-step the contact point's closed forms. Measured 2026-11-26, 64 forces
# x 16 amplitudes, 0.05 s, dt = 1/200 of the tangential period, 2 threads: 12 ns per
# lane-step per thread, switches included (~2 % of the lane-steps are searched, ~0.4 us
# each). Re-measured 2026-11-28 (warm sweeps, 0.05 s, 2 threads, per thread): 5.2-5.6 ns
# per lane-step (256 and 1024 forces, free and forced), the Mindlin lanes 5.9-9 ns;
# rounded up ~2.5x and ~1.7x. A set-up step of a forced spring map (its tape and the
# piece's constants) 270 ns, rounded up ~1.9x.
SPRING_S_PER_LANE_STEP = 1.5e-8
SPRING_S_PER_SETUP_STEP = 0.5e-6
# The spring and Mindlin lanes of a free vibration run on its repeated tape (a period's
# rows, built once): a set-up step is then the walk over a row and its piece's
# constants. Measured 2026-11-28, 4 forces x 64 amplitudes, 2 threads, per thread: ~56 ns
# (spring) and ~90 ns (Mindlin) a step besides the lanes; rounded up ~2.2x.
COMPLIANT_S_PER_REPEATED_ROW = 0.2e-6
# In-process, time chunks are computed LOCAL_BATCH at a time in one shared-normal run
# (sweeps/runner.py), which spreads their set-ups over the threads (a forced model's chunk
# is one set-up: alone, it would keep a single core busy) and lets set-ups that differ
# only in friction coefficients share a tape; small enough for a lively progress bar.
# The estimate counts a forced model's chunks as run that many at once.
LOCAL_BATCH = 16
# "time" sweeps of a MindlinSpring (microslip.integrators.mindlin_lanes): the same lanes'
# cost, and per set-up step the tape and the piece's stiffness, stop-function quartics
# and stick series. Measured 2026-11-26, 8 set-ups x 1 and x 256 forces, 0.05 s, 1
# thread: 0.38-0.53 us per set-up step, 5-6 ns per lane-step; rounded up ~3x (the lanes
# as SPRING_S_PER_LANE_STEP).
# Re-measured 2026-11-28 (forced, 1 force x 32 excitation amplitudes, 2 threads): 0.76 us
# per set-up step per thread; ~2x.
MINDLIN_S_PER_SETUP_STEP = 1.5e-6
# A Mindlin set-up on a rough contact law (m2 = 1.5) that leaves contact: its lanes cross
# each lift-off and touchdown on the scalar RK4 step (integrators/mindlin_windows.py),
# counted as this share of a batched run of them. Measured 2026-11-28, 64 forces x 16
# amplitudes (8 flying) over 0.05 s, 2 threads: 9.4 s against 48 s with the flying set-ups
# handed back to the batched kernel, ~0.2; rounded up 2x.
ROUGH_FLIGHT_SHARE = 0.4
# Sweeps: the result array, the copy read back from the store, the Dataset written out.
SWEEP_BYTES_PER_POINT = 32
BATCH_BYTES_PER_LANE = 256  # coefficients, initial and final states, block scratch
# A Python float in a tuple (32 B), its repr in the JSON definition and fingerprint.
BYTES_PER_AXIS_VALUE = 200
STEADY_BYTES_PER_AMPLITUDE = 3 * 8 * (16 * 256 + 16)  # one orbit table (ys, yds, ydds)
STEADY_TABLES_HELD = 32  # steady_state.BATCH_AMPLITUDES: tables held at once


def batch_threads() -> int:
    """Threads the kernels run at once: numba's thread count
    (:func:`~microslip.integrators.threads.thread_count`, which ``NUMBA_NUM_THREADS`` and
    ``numba.set_num_threads`` lower), at most the CPUs this process may use."""
    try:
        cpus = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cpus = os.cpu_count() or 1
    return max(1, min(cpus, thread_count()))


def batched_lane_steps(lane_steps: float, run_lanes: float = 0.0) -> float:
    """Lane-steps per thread of ``lane_steps`` on the batched kernel, in runs of
    ``run_lanes`` lanes (0: not known, the lanes spread evenly): each run's blocks of
    :func:`~microslip.integrators.batched.block_for` lanes, the last one padded, a round
    of :func:`batch_threads` at a time."""
    threads = batch_threads()
    if run_lanes <= 0.0:
        return lane_steps / threads
    block = block_for(math.ceil(run_lanes), threads)
    blocks = math.ceil(run_lanes / block)
    return lane_steps / run_lanes * math.ceil(blocks / threads) * block


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
    cycles: int = 0,
    n_chunks: int = 0,
    run_lanes: float = 0.0,
    free_vibration: bool = False,
    repeated_tape: bool = False,
) -> Estimate:
    """Work, run time [s] and memory [bytes] of a sweep.

    ``n_sets`` parameter sets, each on ``n_forces`` x ``n_amplitudes`` points. "steady":
    one orbit table per (set, amplitude) and a cycle per point. "time": ``lane_steps``
    trajectory-steps in all (the work reported); run time from ``setup_steps``, the sum
    over chunks of grid steps x :func:`shared_chunk_rounds` (the tapes, a thread each),
    each round also advancing its ``n_forces`` lanes (``kernel="spring"``: a
    TangentialSpring's lanes; ``kernel="mindlin"``: a MindlinSpring's, whose set-up
    steps cost more); with ``kernel="batched"`` (the set-ups the Mindlin lanes hand back) from
    ``lane_steps`` spread over the threads, in runs of ``run_lanes`` lanes (where given)
    padded to whole blocks (:func:`batched_lane_steps`), at the rate of a
    ``free_vibration`` or of a damped or forced one. Where a free vibration's tape repeats, a
    round costs ``tape_fraction`` and ``lane_fraction`` of the shared-normal kernels'
    tape and lane work (:data:`PARKED_LANE_PERIODS`), and a spring or Mindlin set-up step
    :data:`COMPLIANT_S_PER_REPEATED_ROW` (``repeated_tape``), each of its ``cycles`` set-ups
    :data:`TIME_S_PER_CYCLE`; each of ``n_chunks`` time chunks adds
    :data:`TIME_S_PER_CHUNK`. Memory: the result (``SWEEP_BYTES_PER_POINT`` per point)
    and the buffers of the chunk of ``chunk_points`` points being computed (an
    in-process run computes one chunk at a time; each Dask worker holds one more), and
    ``axis_values`` values of all axes together at ``BYTES_PER_AXIS_VALUE`` each (the
    spec's tuples and its definition).
    """
    points = float(n_sets) * n_forces * n_amplitudes
    if method == "steady":
        orbits = float(n_sets) * n_amplitudes
        seconds = orbits * STEADY_S_PER_ORBIT + points * STEADY_S_PER_POINT
        buffers = 8 * chunk_points + STEADY_TABLES_HELD * STEADY_BYTES_PER_AMPLITUDE
        work, unit = points, "points"
    elif kernel == "batched":
        rate = BATCHED_FREE_S_PER_LANE_STEP if free_vibration else BATCHED_S_PER_LANE_STEP
        seconds = batched_lane_steps(lane_steps, run_lanes) * rate
        buffers = BATCH_BYTES_PER_LANE * chunk_points
        work, unit = lane_steps, "trajectory-steps"
    else:
        lane_cost = SHARED_S_PER_LANE_STEP if kernel == "shared" else SPRING_S_PER_LANE_STEP
        setup_cost = {
            "shared": SHARED_S_PER_SETUP_STEP,
            "spring": SPRING_S_PER_SETUP_STEP,
            "mindlin": MINDLIN_S_PER_SETUP_STEP,
        }[kernel]
        if repeated_tape and kernel != "shared":
            setup_cost = COMPLIANT_S_PER_REPEATED_ROW
        per_step = setup_cost * tape_fraction + n_forces * lane_cost * lane_fraction
        seconds = setup_steps * per_step + cycles * TIME_S_PER_CYCLE
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
