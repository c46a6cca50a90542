"""The Mindlin lanes (``MindlinSpring``) on an NVIDIA GPU (optional: numba's CUDA target).

The lanes of :func:`microslip.integrators.mindlin_lanes.run_mindlin_lanes` on the block
pipeline of :mod:`microslip.integrators.shared_lanes_cuda`: the normal tapes on the CPU
cores; on the GPU, per block, first one thread per contact piece writes what that
piece's lanes share (:func:`~microslip.integrators.mindlin_lane_law.set_piece`: the
quartics k_t(τ) and R(τ) and the stick's fundamental series, ~200 numbers) into a
table, then one thread per lane runs through its set-up's pieces
(:func:`~microslip.integrators.spring_lanes_cuda.lanes_kernel`, as the spring lanes):
the CPU kernel's closed form where a piece holds no switch
(:func:`~microslip.integrators.mindlin_pass.free_piece`), else
:func:`~microslip.integrators.mindlin_lane_law.lane_piece`. Both are the CPU kernel's
own functions, compiled for the GPU. The table row also holds the 19 numbers of the
piece's closed form (:func:`~microslip.integrators.mindlin_pass.piece_constants`),
which a lane reads straight into registers; only a flagged lane copies the piece's
scalars and series (to its degree) into its scratch.

Contact exponents: any m2, as on the CPU. At an m2 outside
:func:`~microslip.integrators.mindlin_lanes.supports_exponent` (a Hertz contact, m2 =
1.5) a set-up runs here while it stays in contact; the table kernel marks one with a
row in flight, its lanes stop at their next contact piece, and the run hands it back
(``LEFT_ROUGH_CONTACT``, :class:`~microslip.integrators.shared_lanes.LaneStalledError`
with the other set-ups' results as its ``partial``), as the CPU kernel does. A lane
that stalls (an exact stick/slip tie at a touchdown) is handed back alone, as on the CPU:
NaN, named in the error's ``lanes``, the other lanes of its set-up run to the end.

A lane's result depends only on its parameters and its set-up's tape; on a GPU the
bits differ from the CPU kernel's by rounding (fused multiply-adds), and under numba's
CUDA simulator they are the CPU kernel's (docs/theory/numerics.md, "Lanes on a GPU").
"""

from __future__ import annotations

import functools

import numpy as np
from numba import float64

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import mindlin_lane_law as law
from microslip.integrators import normal_tape as nt
from microslip.integrators.mindlin_lanes import (
    HANDED_BACK,
    LEFT_ROUGH_CONTACT,
    raise_if_too_coarse,
    supports_exponent,
)
from microslip.integrators.mindlin_pass import (
    EMPTY_STICK,
    extend_stick,
    free_piece,
    piece_constants,
    stick_span_constants,
)
from microslip.integrators.shared_lanes import OK
from microslip.integrators.shared_lanes_cuda import (
    TAPE_ROWS,
    THREADS_PER_BLOCK,
    cuda,
    cuda_unavailable,
    run_lanes,
    span_rows,
)
from microslip.integrators.spring_lanes import FS, V, X, pack_lanes
from microslip.integrators.spring_lanes_cuda import (
    COARSE,
    lane_results,
    lanes_kernel,
    start_lanes,
)
from microslip.integrators.spring_pass import stuck_span
from microslip.integrators.tape_row import flight_piece
from microslip.model.coefficients import EXPONENT, GRAVITY, MASS, SIZE

PIECES_BYTES = 512 * 2**20  # at most this much of the pieces' table on the GPU
_SERIES_LENGTH = law.DEGREE + 1
_ONE_ROW = (1, nt.ROW)  # shape of a tape row copied into thread-local memory
_PIECE = law.PIECE  # a module constant: the size of a local array must be a literal
_CONSTANTS = law.PIECE  # where a table row keeps the piece's free_piece constants
_N_CONSTANTS = 19  # of mindlin_pass.piece_constants
TABLE_WIDTH = law.PIECE + _N_CONSTANTS
# Columns of the per-set-up constants: mass [kg], gravity [m/s²], ratio λ [-], 1.0
# once the table kernel has met a row in flight at an m2 outside supports_exponent, and
# 1.0 for such an m2 (its lanes take no spans, as on the CPU).
S_MASS, S_GRAVITY, S_RATIO, S_LEFT, S_ROUGH = range(5)


def piece_table_row(tapes, rows, normal_c, setups, pieces, coarse, rough):
    """Thread j writes row r of set-up g (j = g × rows per block + r) of the pieces'
    table: :func:`~microslip.integrators.mindlin_lane_law.set_piece` on a contact
    piece; h = -1 and ``coarse[g]`` = 1 where θ = h sqrt(k_t/m) > MAX_THETA; on a row in
    flight of a set-up with ``rough[g]`` (its m2 outside supports_exponent),
    setups[g, S_LEFT] = 1. Works on copies in thread-local memory (the law is compiled
    code, which under the simulator cannot take the simulator's arrays)."""
    j = cuda.grid(1)
    n_rows = tapes.shape[1]
    g = j // n_rows
    r = j - g * n_rows
    if g >= tapes.shape[0] or r >= rows[g]:
        return
    a = (
        tapes[g, r, nt.A0], tapes[g, r, nt.A1], tapes[g, r, nt.A2], tapes[g, r, nt.A3],
        tapes[g, r, nt.A4],
    )  # fmt: skip
    if flight_piece(a):
        if rough[g] != 0:
            setups[g, S_LEFT] = 1.0  # every such thread writes the same value
        return
    row = cuda.local.array(_ONE_ROW, float64)
    for q in range(nt.ROW):
        row[0, q] = tapes[g, r, q]
    c = cuda.local.array(SIZE, float64)
    for q in range(SIZE):
        c[q] = normal_c[g, q]
    piece = cuda.local.array(_PIECE, float64)
    law.set_setup(piece, setups[g, S_MASS], setups[g, S_GRAVITY], setups[g, S_RATIO])
    status = law.set_piece(piece, a, row, 0, c)
    for q in range(law.PIECE):
        pieces[g, r, q] = piece[q]
    if status != 0:
        pieces[g, r, law.M_H] = -1.0
        coarse[g] = 1
        return
    h = row[0, nt.H]
    k = piece_constants(a, piece, h * row[0, nt.INT1], h * h * row[0, nt.KINT1])
    for q in range(_N_CONSTANTS):
        pieces[g, r, _CONSTANTS + q] = k[q]


def mindlin_span(tapes, g, r0, r1, setups, pieces, force, mu_s, x, v, f):
    """A stuck Mindlin lane over rows [r0, r1) of set-up g's tape as the span's map of
    its stick (``span_piece`` of
    :func:`~microslip.integrators.spring_lanes_cuda.lanes_kernel`): (stuck, x [m], ẋ
    [m/s], f [N]) of :func:`~microslip.integrators.spring_pass.stuck_span`, the span and
    its stick extended row by row from the pieces' table in row order, as the CPU
    kernel's :func:`~microslip.integrators.mindlin_spans.run_spans` does. Not stuck on a
    set-up whose m2 is outside supports_exponent (its rows go one by one, as on the
    CPU), nor on a span with a row in flight or too coarse."""
    if setups[g, S_ROUGH] != 0.0:
        return False, x, v, f
    span, stick = nt.EMPTY_SPAN, EMPTY_STICK
    for r in range(r0, r1):
        span = nt.extend_span(
            span, tapes[g, r, nt.H], tapes[g, r, nt.INT1], tapes[g, r, nt.KINT1],
            tapes[g, r, nt.PMIN], tapes[g, r, nt.PMAX],
        )  # fmt: skip
        if not span[3] > 0.0 or pieces[g, r, law.M_H] < 0.0:
            return False, x, v, f  # N = 0 on the span (its Φ's unwritten), or too coarse
        k = law.M_K
        stick = extend_stick(
            stick, pieces[g, r, law.M_H], pieces[g, r, law.M_PHI11], pieces[g, r, law.M_PHI12],
            pieces[g, r, law.M_PHI21], pieces[g, r, law.M_PHI22], pieces[g, r, law.M_PSI1],
            pieces[g, r, law.M_PSI2], pieces[g, r, k], pieces[g, r, k + 1],
            pieces[g, r, k + 2], pieces[g, r, k + 3], pieces[g, r, k + 4],
        )  # fmt: skip
    constants = stick_span_constants(stick, setups[g, S_MASS])
    return stuck_span(constants, span[3], 0.0, x, v, f, force, mu_s)


def mindlin_setup(piece, setups, g):
    """Nothing to prepare per lane (``setup_lane`` of
    :func:`~microslip.integrators.spring_lanes_cuda.lanes_kernel`): the set-up's mass,
    gravity and ratio come with each piece's table row."""


def mindlin_piece(tapes, g, r, a, h, setups, pieces, piece, force, fm, km, mu_s, mu_k, x, v,
                  f, mode):  # fmt: skip
    """A Mindlin lane over contact piece r of set-up g (``contact_piece`` of
    :func:`~microslip.integrators.spring_lanes_cuda.lanes_kernel`), from the pieces'
    table into the thread's scratch ``piece``; COARSE on a piece marked too coarse or of
    a set-up marked as left contact on a rough law (handed back: its results are not
    used)."""
    if pieces[g, r, law.M_H] < 0.0 or setups[g, S_LEFT] != 0.0:
        return False, COARSE, x, v, f, mode
    row = pieces[g, r]
    b = _CONSTANTS  # the piece_constants tuple, read straight into registers
    k = (
        row[b], row[b + 1], row[b + 2], row[b + 3], row[b + 4], row[b + 5], row[b + 6],
        row[b + 7], row[b + 8], row[b + 9], row[b + 10], row[b + 11], row[b + 12],
        row[b + 13], row[b + 14], row[b + 15], row[b + 16], row[b + 17], row[b + 18],
    )  # fmt: skip
    flag, x1, v1, f1 = free_piece(k, mode, x, v, f, force, fm, km, mu_s, mu_k)
    if not flag:
        return False, 0, x1, v1, f1, mode
    for q in range(law.M_NODES):  # every scalar of the piece, and the series
        piece[q] = pieces[g, r, q]
    degree = int(piece[law.M_DEG])
    for series in range(6):
        start = law.M_V1 + series * _SERIES_LENGTH
        for n in range(degree + 1):
            piece[start + n] = pieces[g, r, start + n]
    x, v, f, mode, n = law.lane_piece(a, piece, force, fm, km, mu_s, mu_k, x, v, f, mode)
    return True, n, x, v, f, mode


@functools.cache
def _kernels():
    """(pieces' table kernel, lane kernel), compiled for the GPU on their first launch."""
    device = cuda.jit(device=True)
    lanes = lanes_kernel(
        device(mindlin_setup), device(mindlin_piece), device(mindlin_span), law.PIECE
    )
    return cuda.jit(piece_table_row), lanes


def run_mindlin_lanes_cuda(normal_coeffs, normal_states0, ratio, group_of_lane, forces,
                           mu_static, mu_kinetic, t_end, dt, tape_rows=None,
                           periods=None):  # fmt: skip
    """:func:`~microslip.integrators.mindlin_lanes.run_mindlin_lanes` with the lanes on
    the GPU (same arguments, returns and errors, SI units); ``tape_rows`` pieces per
    set-up in a block of tapes (default: TAPE_ROWS, fewer where the pieces' table would
    exceed PIECES_BYTES), ``periods`` as for
    :func:`~microslip.integrators.shared_lanes.run_shared`. Raises RuntimeError when
    no GPU can be used, and LaneStalledError naming the set-ups it hands back, as the CPU
    kernel (module doc)."""
    reason = cuda_unavailable()
    if reason is not None:
        raise RuntimeError(reason)
    normal_coeffs = np.ascontiguousarray(normal_coeffs, dtype=np.float64)
    states0 = np.asarray(normal_states0, dtype=np.float64)
    lanes, starts, ratio = pack_lanes(
        normal_coeffs, ratio, group_of_lane, forces, mu_static, mu_kinetic, what="ratio"
    )
    if lanes.shape[1] == 0:
        none = np.zeros(0, dtype=np.int64)
        return lane_results(lanes, none, none)
    n_groups = normal_coeffs.shape[0]
    if tape_rows is None:
        tape_rows = max(16, min(TAPE_ROWS, PIECES_BYTES // (n_groups * TABLE_WIDTH * 8)))
    tape_rows = span_rows(n_groups, tape_rows)  # whole spans: the CPU kernel's spans
    rough = np.array([not supports_exponent(m2) for m2 in normal_coeffs[:, EXPONENT]], np.int64)
    setups = np.stack(
        [normal_coeffs[:, MASS], normal_coeffs[:, GRAVITY], ratio, np.zeros(n_groups), rough],
        axis=1,
    ).astype(np.float64)
    lane_group, flying = start_lanes(normal_coeffs, states0, lanes, starts)
    table_kernel, lane_kernel = _kernels()
    d_coeffs, d_setups = cuda.to_device(normal_coeffs), cuda.to_device(setups)
    d_pieces = cuda.device_array((n_groups, int(tape_rows), TABLE_WIDTH))
    d_coarse = cuda.to_device(np.zeros(n_groups, dtype=np.int64))
    d_rough = cuda.to_device(rough)
    blocks = (n_groups * int(tape_rows) + THREADS_PER_BLOCK - 1) // THREADS_PER_BLOCK

    def fill_table(d_tapes, d_rows, stream):
        table_kernel[blocks, THREADS_PER_BLOCK, stream](
            d_tapes, d_rows, d_coeffs, d_setups, d_pieces, d_coarse, d_rough
        )

    left = []  # the marks, copied from the GPU once it is done (check, then statuses)

    def left_rough_contact():
        if not left:
            left.append(d_setups.copy_to_host()[:, S_LEFT] != 0.0)
        return left[0]

    def check():  # a set-up handed back is not checked (the CPU kernel stops at its flight)
        raise_if_too_coarse(d_coarse.copy_to_host() * ~left_rough_contact(), dt)

    return run_lanes(
        lane_kernel, "Mindlin-lane kernel (CUDA)", normal_coeffs, states0, lanes, lane_group,
        t_end, dt, tape_rows, before=(d_setups, d_pieces), after=(flying,), periods=periods,
        prepare=fill_table, check=check, results=lane_results, handed_back=HANDED_BACK,
        statuses=lambda: np.where(left_rough_contact(), LEFT_ROUGH_CONTACT, OK),
        alone_rows=(X, V, FS),
    )  # fmt: skip
