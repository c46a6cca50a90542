"""Many trajectories at once: fixed-step RK4 with located switching, vectorised over lanes.

The core ``rk4`` method (:func:`microslip.integrators.kernel.integrate_chunk`) follows
one trajectory: trial step, locate the first switch, switch, go on. Here a *block* of B
trajectories ("lanes") shares the time grid t_k = k·dt, and every step is two passes:

1. a branch-free loop over the B lanes, which LLVM vectorises (AVX2 / AVX-512), takes
   one RK4 step per lane in the lane's current friction mode with exactly the arithmetic
   of :func:`~microslip.integrators.steppers.rk4_step`, and flags the lane when a
   switching function may have changed inside the step (tests below);
2. a scalar loop redoes the flagged lanes, and only those, with the core located
   switching (``rk4_step``, ``first_switch``, ``apply_switch``) exactly as
   ``integrate_chunk`` calls it, through as many switches as the step holds.

The flag tests are conservative supersets of what
:func:`~microslip.integrators.switching.first_switch` detects, so an unflagged step is
one in which the core kernel would have found no switch either, and its state is the
same. Blocks run in parallel over the cores (``prange``). Lanes are padded to whole
blocks with copies of the last lane.

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
  point, as ``integrate_chunk`` allows) always goes to the scalar loop.

On the paper's data a lane is flagged about once per switch (release, stop, loss and
return of contact); redoing a flagged step costs ~0.45 µs (the locating), ~100 times
a vectorised lane-step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit, parallel_chunksize, prange

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators.methods import RK4
from microslip.integrators.steppers import rk4_step
from microslip.integrators.switching import apply_switch, first_switch, initial_direction
from microslip.model.coefficients import AREA_CN, EXPONENT, FORCE, GRAVITY, MASS, MU, SIZE

__all__ = ["DEFAULT_BLOCK", "BatchResult", "simulate_batch", "time_grid"]

DEFAULT_BLOCK = 64
MAX_SWITCHES_PER_STEP = 64  # as kernel._MAX_SWITCHES_PER_STEP

# Lane status.
LANE_OK = 0
LANE_STALLED = 1

_ZERO_ATOL = np.zeros(4)  # unused by RK4; first_switch takes it for the adaptive methods

# Rows of the per-block structure-of-arrays scratch (one column per lane).
_Y, _YD, _X, _XD = 0, 1, 2, 3  # state
_DIR = 4  # friction mode: sliding direction ±1, 0 stick
_T = 5  # lane time if off the grid, else -1
_G, _SCN, _M2, _M, _IM = 6, 7, 8, 9, 10  # g, S c_n, m2, m, 1/m
_FE, _DMU = 11, 12  # F if sliding else 0; direction·μ (so that ẍ = (FE - DMU |R|)/m)
_TLO, _THI = 13, 14  # band of y where the friction test μ|R(y)| < threshold flips
_FLAG = 15
_Y1, _YD1, _X1, _XD1 = 16, 17, 18, 19  # the trial step, also for flagged lanes
_ROWS = 20

# Vector-pass variants, chosen per block (all give rk4_step's bits).
_UNIT_MASS = 0  # m2 == 2 and m == 1: no scaling by 1/m at all
_POW2_MASS = 1  # m2 == 2 and m a power of two: x/m == x·(1/m) exactly
_GENERAL = 2  # divisions by m; y**m2 unless m2 == 2

_BAND = 1e-12  # relative slack of the y band of a friction test (>> rounding)


@njit(cache=True)
def time_grid(t_end, dt):
    """Step ends of the RK4 grid from t = 0: k·dt, the last one clipped to ``t_end``.

    The same rule as ``integrate_chunk``: a grid point within 1e-9·dt of ``t_end`` (or
    past it) is replaced by ``t_end``.
    """
    n = int(t_end / dt) + 3
    out = np.empty(n)
    t = 0.0
    k = 1
    count = 0
    while t < t_end:
        target = 0.0 + k * dt
        if target >= t_end or t_end - target < 1e-9 * dt:
            target = t_end
        k += 1
        if target <= t:
            continue
        out[count] = target
        count += 1
        t = target
    return out[:count]


@njit(cache=True, inline="always")
def _reaction_fast(y, scn):
    # reaction() for m2 == 2: S c_n y², and 0 out of contact (0·0 gives the same bits).
    yp = y if y > 0.0 else 0.0
    return scn * yp * yp


@njit(cache=True, inline="always")
def _accelerations(y, g, scn, m2, m, im, fe, dmu, mode):
    """(ÿ, ẍ) with the bits of normal_acceleration and slip_acceleration.

    ẍ: (F - s·(μ|R|))/m == (FE - DMU·|R|)/m, since (s·μ)|R| = s·(μ|R|) exactly for
    s = ±1, and for stick (FE = DMU = 0) it gives (0 - 0)/m = 0.0.
    """
    if mode == _GENERAL:
        yp = y if y > 0.0 else 0.0
        r = scn * yp * yp if m2 == 2.0 else scn * yp**m2
        r = r if y > 0.0 else 0.0  # as reaction(), whatever 0**m2 gives
        return g - r / m, (fe - dmu * r) / m
    r = _reaction_fast(y, scn)
    if mode == _UNIT_MASS:
        return g - r, fe - dmu * r
    return g - r * im, (fe - dmu * r) * im


@njit(cache=True, inline="always")
def _vector_pass(lanes, h, buf, mode):
    """One RK4 step in every lane of a block, in place; flagged lanes keep their state.

    The trial step is also stored in rows _Y1.._XD1 (the scalar pass reuses it).
    Returns the number of flagged lanes (buf[_FLAG] = 1 for them).
    """
    hh = 0.5 * h
    w = h / 6.0
    h2 = 2.0 * h
    hsq = h * h
    n_flagged = 0
    for i in range(lanes):
        y = buf[_Y, i]
        yd = buf[_YD, i]
        x = buf[_X, i]
        xd = buf[_XD, i]
        d = buf[_DIR, i]
        g = buf[_G, i]
        scn = buf[_SCN, i]
        m2 = buf[_M2, i]
        m = buf[_M, i]
        im = buf[_IM, i]
        fe = buf[_FE, i]
        dmu = buf[_DMU, i]
        # rk4_step: stage k evaluates (ẏ, ÿ, ẋ, ẍ) at (y_k, ẏ_k, ẋ_k).
        a1, a3 = _accelerations(y, g, scn, m2, m, im, fe, dmu, mode)
        b0 = yd + hh * a1
        b2 = xd + hh * a3
        b1, b3 = _accelerations(y + hh * yd, g, scn, m2, m, im, fe, dmu, mode)
        c0 = yd + hh * b1
        c2 = xd + hh * b3
        c1, c3 = _accelerations(y + hh * b0, g, scn, m2, m, im, fe, dmu, mode)
        d0 = yd + h * c1
        d2 = xd + h * c3
        d1, d3 = _accelerations(y + h * c0, g, scn, m2, m, im, fe, dmu, mode)
        y1 = y + w * (yd + 2.0 * b0 + 2.0 * c0 + d0)
        yd1 = yd + w * (a1 + 2.0 * b1 + 2.0 * c1 + d1)
        x1 = x + w * (xd + 2.0 * b2 + 2.0 * c2 + d2)
        xd1 = xd + w * (a3 + 2.0 * b3 + 2.0 * c3 + d3)

        # Switching tests: conservative supersets of first_switch (module docstring).
        turn = (yd != 0.0) & ((yd > 0.0) != (yd1 > 0.0))
        delta = h2 * (abs(yd) + abs(yd1)) + hsq * (abs(a1) + abs(d1))
        delta = delta if turn else 0.0
        y_lo = min(y, y1) - delta
        y_hi = max(y, y1) + delta
        contact = ((y > 0.0) != (y1 > 0.0)) | (turn & (y_lo <= 0.0) & (y_hi >= 0.0))
        friction = (y_lo < buf[_THI, i]) & (y_hi >= buf[_TLO, i])
        v0 = d * xd
        v1 = d * xd1
        near_rest = min(v0, v1) <= h2 * (abs(a3) + abs(d3))  # always true in stick
        stop = (v1 <= 0.0) & (d != 0.0)
        flag = contact | (friction & near_rest) | stop | (buf[_T, i] >= 0.0)
        buf[_Y1, i] = y1
        buf[_YD1, i] = yd1
        buf[_X1, i] = x1
        buf[_XD1, i] = xd1
        buf[_Y, i] = y if flag else y1
        buf[_YD, i] = yd if flag else yd1
        buf[_X, i] = x if flag else x1
        buf[_XD, i] = xd if flag else xd1
        buf[_FLAG, i] = 1.0 if flag else 0.0
        n_flagged += 1 if flag else 0
    return n_flagged


@njit(cache=True)
def _vector_pass_unit_mass(lanes, h, buf):
    return _vector_pass(lanes, h, buf, _UNIT_MASS)


@njit(cache=True)
def _vector_pass_pow2_mass(lanes, h, buf):
    return _vector_pass(lanes, h, buf, _POW2_MASS)


@njit(cache=True)
def _vector_pass_general(lanes, h, buf):
    return _vector_pass(lanes, h, buf, _GENERAL)


@njit(cache=True)
def _set_mode(buf, i, direction, c):
    """Store a lane's friction mode and the y band of its friction test.

    Stick: the stick margin μ|R| - |F| is negative iff μ|R(y)| < |F|. Slip in direction
    s: s·ẍ > 0 iff μ|R(y)| < s·F. μ|R(y)| is non-decreasing in y (also in floating
    point), so each test is "y below a critical height y_c"; the band [TLO, THI]
    brackets y_c with a relative slack far above rounding. Stick only needs THI.
    """
    force = c[FORCE]
    mu = c[MU]
    buf[_DIR, i] = direction
    buf[_FE, i] = force if direction != 0.0 else 0.0
    buf[_DMU, i] = direction * mu
    target = abs(force) if direction == 0.0 else direction * force
    if not target > 0.0:  # μ|R| < target never holds
        lo, hi = -math.inf, -math.inf
    elif not mu * c[AREA_CN] > 0.0:  # μ|R| = 0 < target always holds
        lo, hi = math.inf, math.inf
    else:
        ratio = target / (mu * c[AREA_CN])
        y_c = math.sqrt(ratio) if c[EXPONENT] == 2.0 else ratio ** (1.0 / c[EXPONENT])
        lo, hi = y_c * (1.0 - _BAND), y_c * (1.0 + _BAND)
    buf[_TLO, i] = -math.inf if direction == 0.0 else lo
    buf[_THI, i] = hi


@njit(cache=True)
def _scalar_step(s, direction, t, target, c, s1, have_s1):
    """integrate_chunk's RK4 loop body from (t, s) up to the grid point ``target``.

    ``s1``: when ``have_s1``, rk4_step(s, t, target - t, direction, c), already taken
    (with the same bits) by the vector pass; it is not recomputed.
    Returns (state, direction, time reached, switches, stalled).
    """
    switches = 0
    reuse = have_s1
    while t < target:
        h = target - t
        if reuse:
            reuse = False
        else:
            s1 = rk4_step(s, t, h, direction, c)
        theta, which = first_switch(RK4, s, s1, t, h, direction, c, 1.0, _ZERO_ATOL)
        if which >= 0 and theta < 1.0:
            t_piece = t + theta * h
            s_piece = rk4_step(s, t, theta * h, direction, c)
        else:
            t_piece = target
            s_piece = s1
        if which >= 0:
            switches += 1
            if switches > MAX_SWITCHES_PER_STEP:
                return s, direction, t, switches, True
            s_piece, direction, _kind = apply_switch(which, s_piece, t_piece, direction, c)
        t = t_piece
        s = s_piece
    return s, direction, t, switches, False


@njit(cache=True)
def _is_power_of_two(m):
    """m = 2^k with 1/m finite: then x/m and x·(1/m) are the same rounding of x·2^-k."""
    if not (m > 0.0) or math.isinf(m):
        return False
    mantissa, _exponent = math.frexp(m)
    inv = 1.0 / m
    return mantissa == 0.5 and not math.isinf(inv) and inv * m == 1.0


@njit(cache=True, parallel=True)
def _run_blocks(coeffs, states, directions, times, switches, flagged, status, grid, block):
    """Integrate every block of ``block`` lanes over ``grid`` (in place, rows = lanes)."""
    n_blocks = states.shape[0] // block
    for b in prange(n_blocks):
        lo = b * block
        # A block-local copy: row views of it touch no memory shared between threads
        # (a shared array's reference count would bounce between the cores).
        local_coeffs = coeffs[lo : lo + block].copy()
        buf = np.empty((_ROWS, block))
        mode = _UNIT_MASS
        for i in range(block):
            c = local_coeffs[i]
            buf[_Y, i] = states[lo + i, 0]
            buf[_YD, i] = states[lo + i, 1]
            buf[_X, i] = states[lo + i, 2]
            buf[_XD, i] = states[lo + i, 3]
            buf[_T, i] = -1.0  # on the grid
            buf[_G, i] = c[GRAVITY]
            buf[_SCN, i] = c[AREA_CN]
            buf[_M2, i] = c[EXPONENT]
            buf[_M, i] = c[MASS]
            buf[_IM, i] = 1.0 / c[MASS]
            _set_mode(buf, i, directions[lo + i], c)
            if c[EXPONENT] != 2.0 or not _is_power_of_two(c[MASS]):
                mode = _GENERAL
            elif c[MASS] != 1.0 and mode == _UNIT_MASS:
                mode = _POW2_MASS
        n_switch = np.zeros(block, dtype=np.int64)
        n_flag = np.zeros(block, dtype=np.int64)
        lane_status = np.zeros(block, dtype=np.int64)
        t_prev = 0.0
        for k in range(grid.shape[0]):
            target = grid[k]
            h = target - t_prev
            if mode == _UNIT_MASS:
                count = _vector_pass_unit_mass(block, h, buf)
            elif mode == _POW2_MASS:
                count = _vector_pass_pow2_mass(block, h, buf)
            else:
                count = _vector_pass_general(block, h, buf)
            for i in range(block):
                if count == 0:
                    break
                if buf[_FLAG, i] == 0.0:
                    continue
                count -= 1
                if lane_status[i] == LANE_OK:
                    n_flag[i] += 1
                    on_grid = buf[_T, i] < 0.0  # then the vector trial step is the same
                    t_lane = t_prev if on_grid else buf[_T, i]
                    s = (buf[_Y, i], buf[_YD, i], buf[_X, i], buf[_XD, i])
                    s1 = (buf[_Y1, i], buf[_YD1, i], buf[_X1, i], buf[_XD1, i])
                    c = local_coeffs[i]
                    s, d, t_lane, nsw, stalled = _scalar_step(
                        s, buf[_DIR, i], t_lane, target, c, s1, on_grid
                    )
                    buf[_Y, i] = s[0]
                    buf[_YD, i] = s[1]
                    buf[_X, i] = s[2]
                    buf[_XD, i] = s[3]
                    if d != buf[_DIR, i]:
                        _set_mode(buf, i, d, c)
                    buf[_T, i] = -1.0 if t_lane == target else t_lane
                    n_switch[i] += nsw
                    if stalled:  # frozen where it stalled; reported by the caller
                        lane_status[i] = LANE_STALLED
                        buf[_T, i] = t_lane
            t_prev = target
        for i in range(block):
            states[lo + i, 0] = buf[_Y, i]
            states[lo + i, 1] = buf[_YD, i]
            states[lo + i, 2] = buf[_X, i]
            states[lo + i, 3] = buf[_XD, i]
            directions[lo + i] = buf[_DIR, i]
            times[lo + i] = buf[_T, i] if buf[_T, i] >= 0.0 else t_prev
            switches[lo + i] = n_switch[i]
            flagged[lo + i] = n_flag[i]
            status[lo + i] = lane_status[i]


@njit(cache=True)
def _initial_directions(coeffs, states, out):
    for i in range(states.shape[0]):
        s = (states[i, 0], states[i, 1], states[i, 2], states[i, 3])
        out[i] = initial_direction(s, 0.0, coeffs[i])


@dataclass(frozen=True)
class BatchResult:
    """Final states of a batch of trajectories (SI units), one row per trajectory.

    Attributes
    ----------
    t_end : simulated time [s] (every trajectory starts at t = 0)
    states : (n, 4) final (y [m], ẏ [m/s], x [m], ẋ [m/s])
    direction : (n,) final friction mode: sliding direction ±1, 0 for stick
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
        return self.states[:, 2] / self.t_end


def simulate_batch(
    coeffs: np.ndarray,
    states0: np.ndarray,
    t_end: float,
    dt: float,
    *,
    block: int = DEFAULT_BLOCK,
) -> BatchResult:
    """Integrate many trajectories with RK4 on the grid k·dt and located switching.

    Parameters
    ----------
    coeffs : (SIZE,) or (n, SIZE) array
        Coefficient vectors (:func:`microslip.model.coefficients.pack`), one per
        trajectory or one for all.
    states0 : (n, 4) or (4,) array
        Initial states (y [m], ẏ [m/s], x [m], ẋ [m/s]) at t = 0.
    t_end : float
        End time [s] > 0.
    dt : float
        RK4 step [s] > 0; the grid is k·dt with the last step clipped to ``t_end``.
    block : int
        Lanes per vector block (a multiple of 8 keeps the vector loop free of
        remainders). Results do not depend on it.

    Each trajectory gets, bit for bit, the state that the single-trajectory RK4 kernel
    (``simulate(method="rk4", dt=dt)``) reaches at ``t_end``. Raises ``RuntimeError`` if
    a trajectory stalls (more than 64 switches inside one step).
    """
    states0 = np.asarray(states0, dtype=np.float64)
    if states0.ndim == 1:
        states0 = states0[None, :]
    if states0.ndim != 2 or states0.shape[1] != 4:
        raise ValueError(f"states0 must have shape (n, 4), got {states0.shape}")
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
        return BatchResult(t_end, np.empty((0, 4)), empty, empty, empty.astype(np.int64),
                           empty.astype(np.int64), grid.size)  # fmt: skip
    # Pad to whole blocks with copies of the last trajectory: every lane takes the same
    # code path. Blocks are handed to the threads one at a time (their switching work
    # differs a lot). Results depend on neither.
    n_pad = -(-n // block) * block
    index = np.concatenate([np.arange(n), np.full(n_pad - n, n - 1)])
    lane_coeffs = np.ascontiguousarray(coeffs[index])
    states = np.ascontiguousarray(states0[index])
    directions = np.empty(n_pad)
    _initial_directions(lane_coeffs, states, directions)
    times = np.empty(n_pad)
    switches = np.empty(n_pad, dtype=np.int64)
    flagged = np.empty(n_pad, dtype=np.int64)
    status = np.empty(n_pad, dtype=np.int64)
    with parallel_chunksize(1):
        _run_blocks(lane_coeffs, states, directions, times, switches, flagged, status, grid, block)
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
        direction=directions,
        t_final=times,
        n_switches=switches,
        n_flagged=flagged,
        n_steps=int(grid.size),
    )
