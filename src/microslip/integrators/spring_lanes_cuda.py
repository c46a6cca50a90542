"""The spring lanes (``TangentialSpring``) on an NVIDIA GPU (optional: numba's CUDA target).

The lanes of :func:`microslip.integrators.spring_lanes.run_spring_lanes` with the work
split as for the rigid lanes (:mod:`microslip.integrators.shared_lanes_cuda`, whose
block pipeline this uses): the normal tapes on the CPU cores, one thread per lane on
the GPU. Each thread runs the CPU kernel's own law over its set-up's pieces:
:func:`~microslip.integrators.spring_lanes.flight_step` in flight (a lift-off relaxes the
spring), :func:`~microslip.integrators.spring_pass.free_piece` on a contact piece
without a switch (its piece constants computed by the thread itself, with
:func:`~microslip.integrators.spring_pass.piece_constants`), and
:func:`~microslip.integrators.spring_lane_law.lane_piece` through the switches, and
the CPU kernel's spans: a stuck lane takes a span of rows at once where
:func:`~microslip.integrators.spring_pass.stuck_span` proves it stuck throughout
(:func:`spring_span`; the blocks of tapes are whole spans). The kernel
(:func:`lanes_kernel`) takes the contact piece's and the span's laws as device
functions, and the Mindlin lanes (:mod:`~microslip.integrators.mindlin_lanes_cuda`) run
it with theirs. A lane's result depends only on its parameters and its set-up's tape;
the GPU's FMA contraction and its sine make the bits differ from the CPU kernel's by
rounding, and under numba's CUDA simulator they are the CPU kernel's.
"""

from __future__ import annotations

import functools

import numpy as np
from numba import float64

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import normal_tape as nt
from microslip.integrators.rigid_pass import SPAN_ROWS
from microslip.integrators.shared_lanes_cuda import cuda, cuda_unavailable, run_lanes, span_rows
from microslip.integrators.spring_lane_law import FLIGHT, PIECE, lane_piece, set_piece, set_spring
from microslip.integrators.spring_lanes import flight_step, pack_lanes, starts_in_flight
from microslip.integrators.spring_pass import (
    FM,
    FORCE,
    FS,
    KM,
    MODE,
    MU_K,
    MU_S,
    V,
    X,
    free_piece,
    piece_constants,
    span_constants,
    stuck_span,
)
from microslip.integrators.tape_row import flight_piece
from microslip.model.coefficients import GRAVITY, MASS

# Columns of the per-set-up constants.
S_OMEGA, S_KT, S_MASS, S_GRAVITY = range(4)
STALLED, COARSE = -1, -2  # a contact piece's switch count when the lane cannot go on


def lanes_kernel(setup_lane, contact_piece, span_piece, scratch_size):
    """A CUDA kernel of compliant lanes, one thread per lane through its set-up's pieces
    as :func:`~microslip.integrators.spring_lanes.run_spring_lanes` (a lift-off relaxes
    the spring, :func:`~microslip.integrators.spring_lanes.flight_step` in flight), with
    ``contact_piece(tapes, g, r, a, h, setups, pieces, scratch, force, fm, km, mu_s,
    mu_k, x, v, f, mode)`` -> (flagged, switches, x, v, f, mode) on a contact piece
    (switches STALLED or COARSE end the lane; only STALLED marks it stalled),
    ``span_piece(tapes, g, r0, r1, setups, pieces, force, mu_s, x, v, f)`` -> (stuck, x,
    v, f) for a stuck lane over the span of rows [r0, r1) (stuck: it took the span), a
    thread-local ``scratch`` of ``scratch_size`` floats that ``setup_lane(scratch,
    setups, g)`` prepares once per lane. Compiled on its first launch."""

    @cuda.jit
    def compliant_kernel(tapes, rows, lane_group, setups, pieces, lanes, flying, switches,
                         flagged, stalled):  # fmt: skip
        i = cuda.grid(1)
        if i >= lanes.shape[1]:
            return
        g = lane_group[i]
        scratch = cuda.local.array(scratch_size, float64)
        setup_lane(scratch, setups, g)
        force, fm, km = lanes[FORCE, i], lanes[FM, i], lanes[KM, i]
        mu_s, mu_k = lanes[MU_S, i], lanes[MU_K, i]
        x, v, f, mode = lanes[X, i], lanes[V, i], lanes[FS, i], lanes[MODE, i]
        in_air = flying[i] != 0
        n_switches = 0
        n_flagged = 0
        ended = False
        for r0 in range(0, rows[g], SPAN_ROWS):  # the CPU kernel's spans (blocks of whole spans)
            r1 = min(r0 + SPAN_ROWS, rows[g])
            if mode == 0.0:
                stuck, x1, v1, f1 = span_piece(
                    tapes, g, r0, r1, setups, pieces, force, mu_s, x, v, f
                )
                if stuck:  # stuck throughout: the span's map of its stick
                    x, v, f = x1, v1, f1
                    continue
            for r in range(r0, r1):
                h = tapes[g, r, nt.H]
                a = (
                    tapes[g, r, nt.A0], tapes[g, r, nt.A1], tapes[g, r, nt.A2],
                    tapes[g, r, nt.A3], tapes[g, r, nt.A4],
                )  # fmt: skip
                if flight_piece(a):
                    if not in_air:  # lift-off: the spring relaxes (f = 0, u = x)
                        mode, f = FLIGHT, 0.0
                    in_air = True
                    x, v = flight_step(x, v, fm, h)
                    continue
                in_air = False  # a lane that lands is flagged: the piece applies the touchdown
                flag, n, x, v, f, mode = contact_piece(
                    tapes, g, r, a, h, setups, pieces, scratch, force, fm, km, mu_s, mu_k, x, v,
                    f, mode,
                )  # fmt: skip
                if flag:
                    n_flagged += 1
                if n < 0:
                    if n == STALLED:
                        stalled[i] = 1
                    ended = True
                    break
                n_switches += n
            if ended:
                break
        lanes[X, i], lanes[V, i], lanes[FS, i], lanes[MODE, i] = x, v, f, mode
        flying[i] = 1 if in_air else 0
        switches[i] += n_switches
        flagged[i] += n_flagged

    return compliant_kernel


def spring_setup(piece, setups, g):
    """Write set-up g's spring into the thread's scratch ``piece`` (``setup_lane`` of
    :func:`lanes_kernel`)."""
    set_spring(piece, setups[g, S_OMEGA], setups[g, S_KT], setups[g, S_MASS],
               setups[g, S_GRAVITY])  # fmt: skip


def spring_piece(tapes, g, r, a, h, setups, pieces, piece, force, fm, km, mu_s, mu_k, x, v, f,
                 mode):  # fmt: skip
    """A spring lane over contact piece r of set-up g (``contact_piece`` of
    :func:`lanes_kernel`, compiled as a device function): the CPU kernel's closed form
    where the piece holds no switch (:func:`~microslip.integrators.spring_pass.free_piece`),
    else :func:`~microslip.integrators.spring_lane_law.lane_piece`; ``piece`` is the
    thread's scratch (its spring written by :func:`spring_setup`), ``setups`` and
    ``pieces`` unused. (A device function, not ``@njit``: under the simulator it gets
    the simulator's arrays, which compiled code cannot take.)"""
    set_piece(piece, a, h)
    k = piece_constants(a, piece, h * tapes[g, r, nt.INT1], h * h * tapes[g, r, nt.KINT1])
    flag, x1, v1, f1 = free_piece(k, mode, x, v, f, force, fm, km, mu_s, mu_k)
    if not flag:
        return False, 0, x1, v1, f1, mode
    x, v, f, mode, n = lane_piece(a, piece, force, fm, km, mu_s, mu_k, x, v, f, mode)
    return True, n, x, v, f, mode


def spring_span(tapes, g, r0, r1, setups, pieces, force, mu_s, x, v, f):
    """A stuck spring lane over rows [r0, r1) of set-up g's tape as one turn of its
    oscillator (``span_piece`` of :func:`lanes_kernel`, ``pieces`` unused): (stuck, x
    [m], ẋ [m/s], f [N]) of :func:`~microslip.integrators.spring_pass.stuck_span`, the
    span summed by
    :func:`~microslip.integrators.normal_tape.extend_span` in row order as on the CPU.
    (The loop is ``nt.span``'s, as in the rigid lanes' ``lane_span``: under numba's CUDA
    simulator a compiled function cannot take the kernel's arrays.)"""
    span = nt.EMPTY_SPAN
    for r in range(r0, r1):
        span = nt.extend_span(
            span, tapes[g, r, nt.H], tapes[g, r, nt.INT1], tapes[g, r, nt.KINT1],
            tapes[g, r, nt.PMIN], tapes[g, r, nt.PMAX],
        )  # fmt: skip
    length, p_min = span[0], span[3]
    k = span_constants(setups[g, S_OMEGA], setups[g, S_KT], setups[g, S_MASS], length)
    return stuck_span(k, p_min, 0.0, x, v, f, force, mu_s)


@functools.cache
def _kernel():
    device = cuda.jit(device=True)
    return lanes_kernel(device(spring_setup), device(spring_piece), device(spring_span), PIECE)


def start_lanes(normal_coeffs, normal_states0, lanes, starts):
    """(lane_group, flying): each lane's set-up, and 1 for the lanes of a set-up that
    starts out of contact, which are put in flight (mode FLIGHT), as on the CPU."""
    n_groups = normal_coeffs.shape[0]
    flying = np.zeros(lanes.shape[1], dtype=np.int64)
    for g in range(n_groups):
        if starts_in_flight(normal_coeffs[g], normal_states0[g, 0], normal_states0[g, 1]):
            lanes[MODE, starts[g] : starts[g + 1]] = FLIGHT
            flying[starts[g] : starts[g + 1]] = 1
    return np.repeat(np.arange(n_groups), np.diff(starts)), flying


def run_spring_lanes_cuda(normal_coeffs, normal_states0, stiffness, group_of_lane, forces,
                          mu_static, mu_kinetic, t_end, dt, tape_rows=None,
                          periods=None):  # fmt: skip
    """:func:`~microslip.integrators.spring_lanes.run_spring_lanes` with the lanes on the
    GPU (same arguments and returns, SI units); ``tape_rows`` as for
    :func:`~microslip.integrators.shared_lanes_cuda.run_shared_cuda`, ``periods`` as
    for :func:`~microslip.integrators.shared_lanes.run_shared`. Raises
    RuntimeError when no GPU can be used or a normal integration or a lane fails."""
    reason = cuda_unavailable()
    if reason is not None:
        raise RuntimeError(reason)
    normal_coeffs = np.ascontiguousarray(normal_coeffs, dtype=np.float64)
    states0 = np.asarray(normal_states0, dtype=np.float64)
    lanes, starts, stiffness = pack_lanes(
        normal_coeffs, stiffness, group_of_lane, forces, mu_static, mu_kinetic
    )
    if lanes.shape[1] == 0:
        none = np.zeros(0, dtype=np.int64)
        return lanes[X], lanes[V], lanes[FS], lanes[MODE], none, none
    mass = normal_coeffs[:, MASS]
    setups = np.stack(
        [np.sqrt(stiffness / mass), stiffness, mass, normal_coeffs[:, GRAVITY]], axis=1
    )
    lane_group, flying = start_lanes(normal_coeffs, states0, lanes, starts)
    return run_lanes(
        _kernel(), "spring-lane kernel (CUDA)", normal_coeffs, states0, lanes, lane_group,
        t_end, dt, span_rows(normal_coeffs.shape[0], tape_rows),
        before=(setups, np.zeros((1, 1, 1))), after=(flying,), periods=periods,
        results=lane_results,
    )  # fmt: skip


def lane_results(lanes, switches, flagged):
    """(x [m], ẋ [m/s], f [N], mode, switches, flagged) per lane, as the CPU kernels
    return them, from the compliant kernel's lane array and counts."""
    return lanes[X], lanes[V], lanes[FS], lanes[MODE], switches, flagged
