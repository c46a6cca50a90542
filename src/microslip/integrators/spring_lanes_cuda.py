"""The spring lanes (``TangentialSpring``) on an NVIDIA GPU (optional: numba's CUDA target).

The lanes of :func:`microslip.integrators.spring_lanes.run_spring_lanes` with the work
split as for the rigid lanes (:mod:`microslip.integrators.shared_lanes_cuda`, whose
block pipeline this uses): the normal tapes on the CPU cores, one thread per lane on
the GPU. Each thread runs the CPU kernel's own law over its set-up's pieces:
:func:`~microslip.integrators.spring_lanes.flight_step` in flight (a lift-off relaxes the
spring), :func:`~microslip.integrators.spring_lanes.free_piece` on a contact piece
without a switch (its piece constants computed by the thread itself, with
:func:`~microslip.integrators.spring_lanes.piece_constants`), and
:func:`~microslip.integrators.spring_lane_law.lane_piece` through the switches. A lane's
result depends only on its parameters and its set-up's tape; the GPU's FMA contraction
and its sine make the bits differ from the CPU kernel's by rounding, and under numba's
CUDA simulator they are the CPU kernel's.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numba import float64

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import normal_tape as nt
from microslip.integrators.shared_lanes_cuda import cuda, cuda_unavailable, run_lanes
from microslip.integrators.spring_lane_law import FLIGHT, PIECE, lane_piece, set_piece, set_spring
from microslip.integrators.spring_lanes import (
    FM,
    FORCE,
    FS,
    KM,
    MODE,
    MU_K,
    MU_S,
    V,
    X,
    flight_piece,
    flight_step,
    free_piece,
    pack_lanes,
    piece_constants,
    starts_in_flight,
)
from microslip.model.coefficients import GRAVITY, MASS

# Columns of the per-set-up constants.
S_OMEGA, S_KT, S_MASS, S_GRAVITY = range(4)


@functools.cache
def _kernel():
    """The spring-lane kernel, compiled for the GPU on its first launch."""

    @cuda.jit
    def spring_kernel(tapes, rows, lane_group, setups, lanes, flying, switches, flagged,
                      stalled):  # fmt: skip
        # One thread per lane: through its set-up's pieces, as spring_lanes._run_group.
        i = cuda.grid(1)
        if i >= lanes.shape[1]:
            return
        g = lane_group[i]
        piece = cuda.local.array(PIECE, float64)
        set_spring(piece, setups[g, S_OMEGA], setups[g, S_KT], setups[g, S_MASS],
                   setups[g, S_GRAVITY])  # fmt: skip
        force, fm, km = lanes[FORCE, i], lanes[FM, i], lanes[KM, i]
        mu_s, mu_k = lanes[MU_S, i], lanes[MU_K, i]
        x, v, f, mode = lanes[X, i], lanes[V, i], lanes[FS, i], lanes[MODE, i]
        in_air = flying[i] != 0
        n_switches = 0
        n_flagged = 0
        for r in range(rows[g]):
            h = tapes[g, r, nt.H]
            a = (
                tapes[g, r, nt.A0], tapes[g, r, nt.A1], tapes[g, r, nt.A2], tapes[g, r, nt.A3],
                tapes[g, r, nt.A4],
            )  # fmt: skip
            if flight_piece(a):
                if not in_air:  # lift-off: the spring relaxes (f = 0, u = x)
                    mode, f = FLIGHT, 0.0
                in_air = True
                x, v = flight_step(x, v, fm, h)
                continue
            in_air = False  # a lane that lands is flagged: lane_piece applies the touchdown
            set_piece(piece, a, h)
            k = piece_constants(a, piece, h * tapes[g, r, nt.INT1], h * h * tapes[g, r, nt.KINT1])
            flag, x1, v1, f1 = free_piece(k, mode, x, v, f, force, fm, km, mu_s, mu_k)
            if not flag:
                x, v, f = x1, v1, f1
                continue
            n_flagged += 1
            x, v, f, mode, n = lane_piece(a, piece, force, fm, km, mu_s, mu_k, x, v, f, mode)
            if n < 0:
                stalled[i] = 1
                break
            n_switches += n
        lanes[X, i], lanes[V, i], lanes[FS, i], lanes[MODE, i] = x, v, f, mode
        flying[i] = 1 if in_air else 0
        switches[i] += n_switches
        flagged[i] += n_flagged

    return spring_kernel


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
    n_groups, n_lanes = normal_coeffs.shape[0], lanes.shape[1]
    if n_lanes == 0:
        none = np.zeros(0, dtype=np.int64)
        return lanes[X], lanes[V], lanes[FS], lanes[MODE], none, none
    setups = np.empty((n_groups, 4))
    flying = np.zeros(n_lanes, dtype=np.int64)
    for g in range(n_groups):
        c = normal_coeffs[g]
        mass = c[MASS]
        setups[g] = math.sqrt(stiffness[g] / mass), stiffness[g], mass, c[GRAVITY]
        if starts_in_flight(c, states0[g, 0], states0[g, 1]):
            lanes[MODE, starts[g] : starts[g + 1]] = FLIGHT
            flying[starts[g] : starts[g + 1]] = 1
    lane_group = np.repeat(np.arange(n_groups), np.diff(starts))
    lanes, switches, flagged = run_lanes(
        _kernel(), "spring-lane kernel (CUDA)", normal_coeffs, states0, lanes, lane_group,
        t_end, dt, tape_rows, before=(setups,), after=(flying,), periods=periods,
    )  # fmt: skip
    return lanes[X], lanes[V], lanes[FS], lanes[MODE], switches, flagged
