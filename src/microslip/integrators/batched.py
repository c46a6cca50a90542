"""Many trajectories at once: fixed-step RK4 with located switching, vectorised over lanes.

The core ``rk4`` method (:func:`microslip.integrators.kernel.integrate_chunk`) follows
one trajectory: trial step, locate the first switch, switch, go on. Here a *block* of B
trajectories ("lanes") shares the time grid t_k = k·dt, and every step is two passes:

1. a branch-free loop over the B lanes (:mod:`microslip.integrators.paper_pass`),
   which LLVM vectorises (AVX2 / AVX-512), takes one RK4 step per lane of the paper's
   model in the lane's current friction mode with exactly the arithmetic of
   :func:`~microslip.integrators.steppers.rk4_step`, and flags the lane when a
   switching function may have changed inside the step (tests below);
2. a scalar loop redoes the flagged lanes, and only those, with the core located
   switching (``rk4_step``, then :func:`~microslip.integrators.kernel.piece_end` and
   the model's ``apply_switch``) exactly as ``integrate_chunk`` does, through as many
   switches as the step holds.

Lanes of any other model (damping, excitation) are always flagged: every step of theirs
is the generic scalar kernel step of ``simulate(method="rk4")``, with the model's own
laws (:mod:`microslip.model.system`). No law is implemented twice.

The flag tests are conservative supersets of what
:func:`~microslip.integrators.switching.first_switch` detects, so an unflagged step is
one in which the core kernel would have found no switch either, and its state is the
same. Blocks run in parallel over the cores (:mod:`~microslip.integrators.threads`).
Lanes are padded to whole blocks with copies of the last lane.

Bit-for-bit reproducibility. The vector loop is compiled *without* fastmath: no FMA
contraction, no reassociation. A division by m becomes a multiplication by 1/m only
when m is a power of two (both are then the same rounding of the same exact number), and
for m = 1 it is dropped. Every lane therefore computes, operation for operation, the
bits of the scalar ``rk4_step``, whether it runs in a vector register, a scalar
remainder or the fix-up loop: a lane's result does not depend on the block size, its
position in the block, the other lanes or the thread, and equals the single-trajectory
``integrate_chunk`` result (``simulate(method="rk4")``) bit for bit. fastmath would buy
about 10–20 % on the vector pass (FMA contraction) at the price of that identity.

The vector tests, for a step of length h from s0 = (y0, ẏ0, x0, ẋ0) to s1:

* contact gap y: y changes sign; or ẏ changes sign (a turning point, where a double
  crossing can hide) and the band [min(y0, y1) - δ, max(y0, y1) + δ] contains 0, with
  δ = 2h(|ẏ0| + |ẏ1|) + h²(|ÿ0| + |ÿ at stage 4|) a generous bound on how far y can
  go past its end values;
* friction: every friction test of ``first_switch`` has the form μ|R(y)| < T (stick
  margin negative: T = |F|; net force s·ẍ positive while sliding in direction s:
  T = s·F). μ|R(y)| is non-decreasing in y, also in floating point, so each test is
  "y below a critical height y_c = (T/(μ S c_n))^(1/m2)". Stick is flagged when the
  lowest y of the step (less δ at a turning point) is below y_c(1 + 1e-12); a sliding
  speed extremum (s·ẍ changing sign) when the y range of the step meets the band
  y_c(1 ± 1e-12) *and* the speed comes within 2h(|ẍ0| + |ẍ at stage 4|) of zero;
* slip: s·ẋ1 <= 0 (the slider stops, or reverses);
* a lane whose time is off the grid (a switch located a rounding error past a grid
  point, as ``integrate_chunk`` allows), or of another model than the paper's, always
  goes to the scalar loop.

On the paper's data a lane is flagged about once per switch (release, stop, loss and
return of contact); redoing a flagged step costs ~0.45 µs (the locating), ~100 times
a vectorised lane-step.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import paper_pass as pp
from microslip.integrators import threads
from microslip.integrators.kernel import (
    MAX_SWITCHES_PER_STEP,
    as_tuple,
    copy_state,
    graded_target,
    piece_end,
    time_grid,
)
from microslip.integrators.methods import RK4, WORK_ROWS
from microslip.integrators.steppers import rk4_step
from microslip.integrators.switching import NO_SWITCH, may_switch
from microslip.model.coefficients import SIZE
from microslip.model.samples import full_states
from microslip.model.switches import apply_switch, initial_mode
from microslip.model.switching_functions import graded_after
from microslip.model.system import N_STATE, X, slip_directions, state_tuple

__all__ = ["DEFAULT_BLOCK", "BatchResult", "block_for", "simulate_batch", "time_grid"]

DEFAULT_BLOCK = 64
MIN_BLOCK = 8  # lanes: a vector loop free of remainders (8 doubles of AVX-512)
# Steps between a block's progress reports (threads.report): a store each, rare enough
# that the threads' slots, side by side in one array, do not bounce between the cores.
REPORT_STEPS = 256

# Lane status.
LANE_OK = 0
LANE_STALLED = 1


@njit(cache=True)
def scalar_step(s, mode, t, target, dt, graded_from, c, s1, have_s1, piece, trial, extremum,
                 work, atol):  # fmt: skip
    """integrate_chunk's RK4 loop body from (t, s) up to the grid point ``target``.

    ``s`` (updated in place) is the lane's state; ``s1``: when ``have_s1``,
    rk4_step(s, t, target - t, mode, c), already taken (with the same bits) by the
    vector pass; it is not recomputed. ``graded_from``: the time [s] of the graded
    switch the lane is leaving by graded steps (kernel.graded_target), NaN if none.
    Returns (mode, time reached, switches, stalled, graded_from).
    """
    switches = 0
    reuse = have_s1
    while t < target:
        end = target
        if graded_from == graded_from:  # leaving a graded switch: as integrate_chunk
            end, _on_grid, grading = graded_target(t, target, graded_from, dt)
            if not grading:
                graded_from = math.nan
        h = end - t
        if not (reuse and end == target):
            rk4_step(s, t, h, mode, c, s1, work)
        reuse = False
        if may_switch(t, h, mode, c, state_tuple(s), state_tuple(s1)):
            theta, which = piece_end(
                RK4, s, s1, t, h, mode, c, 1.0, atol, piece, trial, extremum, work
            )
        else:
            theta, which = NO_SWITCH, -1
            copy_state(s1, piece)
        t_piece = t + theta * h if which >= 0 and theta < 1.0 else end
        if which >= 0:
            switches += 1
            if switches > MAX_SWITCHES_PER_STEP:
                return mode, t, switches, True, graded_from
            mode, _kind = apply_switch(which, t_piece, piece, mode, c)
            if graded_after(which, mode, c):
                graded_from = t_piece
        t = t_piece
        copy_state(piece, s)
    return mode, t, switches, False, graded_from


@njit(cache=True, nogil=True)
def _run_blocks(b_lo, b_hi, coeffs, states, directions, times, switches, flagged, status, grid,
                dt, block, stop):  # fmt: skip
    """Integrate blocks [b_lo, b_hi) of ``block`` lanes over ``grid`` (in place, rows =
    lanes; a range of :func:`threads.run_ranges`, which returns at the next step once
    ``stop[0]`` is set: :func:`threads.stop_flag`, and reports each block's share of the
    grid done in its progress slot every REPORT_STEPS steps)."""
    for b in range(b_lo, b_hi):
        lo = b * block
        # A block-local copy: row views of it touch no memory shared between threads
        # (a shared array's reference count would bounce between the cores).
        local_coeffs = coeffs[lo : lo + block].copy()
        buf = np.empty((pp._ROWS, block))
        # Scratch of the scalar pass, one set per block: no allocation per step.
        s = np.empty(N_STATE)
        s1 = np.empty(N_STATE)
        piece = np.empty(N_STATE)
        trial = np.empty(N_STATE)
        extremum = np.empty(N_STATE)
        work = np.empty((WORK_ROWS, N_STATE))
        atol = np.zeros(N_STATE)  # unused by RK4
        variant = pp._UNIT_MASS
        for i in range(block):
            lane_variant = pp.init_lane(buf, i, states[lo + i], directions[lo + i], local_coeffs[i])
            variant = max(variant, lane_variant)
        n_switch = np.zeros(block, dtype=np.int64)
        n_flag = np.zeros(block, dtype=np.int64)
        lane_status = np.zeros(block, dtype=np.int64)
        graded_from = np.full(block, math.nan)  # per lane, see scalar_step
        t_prev = 0.0
        for k in range(grid.shape[0]):
            if stop[0] != 0:
                return  # interrupted: the results are not read
            target = grid[k]
            h = target - t_prev
            count = pp.vector_pass(variant, block, h, buf)
            for i in range(block):
                if count == 0:
                    break
                if buf[pp._FLAG, i] == 0.0:
                    continue
                count -= 1
                if lane_status[i] == LANE_OK:
                    n_flag[i] += 1
                    on_grid = buf[pp._T, i] < 0.0
                    # On the grid, the vector trial step of a paper lane is rk4_step's.
                    reuse = on_grid and buf[pp._GEN, i] == 0.0
                    t_lane = t_prev if on_grid else buf[pp._T, i]
                    for j in range(N_STATE):
                        s[j] = buf[pp._S + j, i]
                        s1[j] = buf[pp._S1 + j, i]
                    mode = buf[pp._DIR, i]
                    # The laws take the coefficients as a tuple (see kernel.as_tuple).
                    c = as_tuple(local_coeffs[i])
                    if reuse and not may_switch(
                        t_lane, h, mode, c, state_tuple(s), state_tuple(s1)
                    ):
                        # A flag the core screening clears: scalar_step would take s1 as
                        # it is. Decided here, without a compiled call that takes arrays.
                        for j in range(N_STATE):
                            buf[pp._S + j, i] = s1[j]
                        continue
                    # (A graded lane is a Mindlin one, of another model than the paper's:
                    # always flagged, so every step of its grading comes here.)
                    d, t_lane, nsw, stalled, graded = scalar_step(
                        s, mode, t_lane, target, dt, graded_from[i], c, s1, reuse, piece,
                        trial, extremum, work, atol,
                    )  # fmt: skip
                    graded_from[i] = graded
                    for j in range(N_STATE):
                        buf[pp._S + j, i] = s[j]
                    if d != mode:
                        pp.set_mode(buf, i, d, local_coeffs[i])
                    buf[pp._T, i] = -1.0 if t_lane == target else t_lane
                    n_switch[i] += nsw
                    if stalled:  # frozen where it stalled; reported by the caller
                        lane_status[i] = LANE_STALLED
                        buf[pp._T, i] = t_lane
            t_prev = target
            if k % REPORT_STEPS == REPORT_STEPS - 1:
                threads.report(stop, b, (k + 1) / grid.shape[0])
        for i in range(block):
            for j in range(N_STATE):
                states[lo + i, j] = buf[pp._S + j, i]
            directions[lo + i] = buf[pp._DIR, i]
            times[lo + i] = buf[pp._T, i] if buf[pp._T, i] >= 0.0 else t_prev
            switches[lo + i] = n_switch[i]
            flagged[lo + i] = n_flag[i]
            status[lo + i] = lane_status[i]


def block_for(n_lanes: int, threads: int) -> int:
    """Lanes per block of a run of ``n_lanes`` on ``threads``: DEFAULT_BLOCK, or fewer (a
    multiple of MIN_BLOCK) where that gives every thread a block or pads a small run
    less: a padded lane costs what a lane does, and a lane of a model other than the
    paper's is stepped by the scalar loop whatever its block."""
    per_thread = -(-int(n_lanes) // max(int(threads), 1))
    return int(min(DEFAULT_BLOCK, max(MIN_BLOCK, -(-per_thread // MIN_BLOCK) * MIN_BLOCK)))


@njit(cache=True)
def _initial_modes(coeffs, states, out):
    for i in range(states.shape[0]):
        out[i] = initial_mode(0.0, states[i], as_tuple(coeffs[i]))  # as the laws take it


@dataclass(frozen=True)
class BatchResult:
    """Final states of a batch of trajectories (SI units), one row per trajectory.

    Attributes
    ----------
    t_end : simulated time [s] (every trajectory starts at t = 0)
    states : (n, n_state) final states in the model's layout (y [m], ẏ [m/s], x [m], ẋ [m/s])
    direction : (n,) final slip direction of the interface: ±1, 0 for stick
    t_final : (n,) time each trajectory reached [s]: ``t_end``, or a rounding error past
        it when a switch was located there (as in the single-trajectory kernel)
    n_switches : (n,) number of switching instants (stick/slip, contact) per trajectory
    n_flagged : (n,) number of steps redone by the scalar located-switching pass
    n_steps : number of grid steps
    """

    t_end: float
    states: np.ndarray
    direction: np.ndarray
    t_final: np.ndarray
    n_switches: np.ndarray
    n_flagged: np.ndarray
    n_steps: int

    @property
    def mean_velocity(self) -> np.ndarray:
        """x(t_end)/t_end [m/s]: mean velocity over the run (x starts at 0 [m])."""
        return self.states[:, X] / self.t_end


def simulate_batch(
    coeffs: np.ndarray,
    states0: np.ndarray,
    t_end: float,
    dt: float,
    *,
    block: int = DEFAULT_BLOCK,
    on_done: Callable[[float], None] | None = None,
) -> BatchResult:
    """Integrate many trajectories with RK4 on the grid k·dt and located switching.

    Parameters
    ----------
    coeffs : (SIZE,) or (n, SIZE) array
        Coefficient vectors (:func:`microslip.model.coefficients.pack`), one per
        trajectory or one for all.
    states0 : (n, n_state) or (n_state,) array
        Initial states in the model's layout (y [m], ẏ [m/s], x [m], ẋ [m/s]) at t = 0.
    t_end : float
        End time [s] > 0.
    dt : float
        RK4 step [s] > 0; the grid is k·dt with the last step clipped to ``t_end``.
    block : int
        Lanes per vector block (a multiple of 8 keeps the vector loop free of
        remainders). Results do not depend on it.
    on_done : callable, optional
        Progress: told the fraction [1] of the batch done since its last call, as the
        blocks advance (:func:`threads.run_ranges`).

    Each trajectory gets the state that the single-trajectory RK4 kernel
    (``simulate(method="rk4", dt=dt)``) reaches at ``t_end`` (bit for bit: both run the
    same arithmetic). Raises ``RuntimeError`` if
    a trajectory stalls (more than 64 switches inside one step).
    """
    states0 = full_states(states0)
    if states0.ndim == 1:
        states0 = states0[None, :]
    if states0.ndim != 2 or states0.shape[1] != N_STATE:
        raise ValueError(f"states0 must have shape (n, {N_STATE}), got {states0.shape}")
    n = states0.shape[0]
    coeffs = np.asarray(coeffs, dtype=np.float64)
    if coeffs.ndim == 1:
        coeffs = np.broadcast_to(coeffs, (n, coeffs.shape[0]))
    if coeffs.ndim != 2 or coeffs.shape[1] != SIZE:
        raise ValueError(f"coeffs must have shape (n, {SIZE}) or ({SIZE},), got {coeffs.shape}")
    if coeffs.shape[0] != n:
        raise ValueError(f"coeffs has {coeffs.shape[0]} rows but states0 has {n}")
    if not (np.all(np.isfinite(states0)) and np.all(np.isfinite(coeffs))):
        raise ValueError("coeffs and states0 must be finite")
    t_end = float(t_end)
    dt = float(dt)
    if not (math.isfinite(t_end) and t_end > 0.0):
        raise ValueError(f"t_end must be finite and > 0, got {t_end!r}")
    if not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f"dt must be finite and > 0, got {dt!r}")
    if isinstance(block, bool) or not isinstance(block, (int, np.integer)) or block < 1:
        raise ValueError(f"block must be an integer >= 1, got {block!r}")
    block = int(block)

    grid = time_grid(t_end, dt)
    if n == 0:
        empty = np.empty(0)
        return BatchResult(t_end, np.empty((0, N_STATE)), empty, empty, empty.astype(np.int64),
                           empty.astype(np.int64), grid.size)  # fmt: skip
    # Pad to whole blocks with copies of the last trajectory: every lane takes the same
    # code path. Blocks are handed to the threads one at a time (their switching work
    # differs a lot). Results depend on neither.
    n_pad = -(-n // block) * block
    index = np.concatenate([np.arange(n), np.full(n_pad - n, n - 1)])
    lane_coeffs = np.ascontiguousarray(coeffs[index])
    states = np.ascontiguousarray(states0[index])
    directions = np.empty(n_pad)
    _initial_modes(lane_coeffs, states, directions)
    times = np.empty(n_pad)
    switches = np.empty(n_pad, dtype=np.int64)
    flagged = np.empty(n_pad, dtype=np.int64)
    status = np.empty(n_pad, dtype=np.int64)
    n_blocks = n_pad // block
    stop = threads.stop_flag(n_blocks)
    told = None if on_done is None else (lambda blocks: on_done(blocks / n_blocks))
    threads.run_ranges(
        _run_blocks, n_blocks, lane_coeffs, states, directions, times, switches, flagged,
        status, grid, dt, block, stop, per_task=1, stop=stop, on_done=told,
    )  # fmt: skip
    states, directions, times = states[:n], directions[:n], times[:n]
    switches, flagged, status = switches[:n], flagged[:n], status[:n]
    stalled = np.flatnonzero(status == LANE_STALLED)
    if stalled.size:
        i = int(stalled[0])
        raise RuntimeError(
            f"switching stalled in trajectory {i} at t={float(times[i])!r} s: more than "
            f"{MAX_SWITCHES_PER_STEP} switches without progress (inconsistent friction law?)"
        )
    return BatchResult(
        t_end=t_end,
        states=states,
        direction=slip_directions(directions),
        t_final=times,
        n_switches=switches,
        n_flagged=flagged,
        n_steps=int(grid.size),
    )
