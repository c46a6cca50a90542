"""The shared-normal lanes on an NVIDIA GPU (optional: numba's CUDA target).

The same lanes as :func:`microslip.integrators.shared_lanes.run_shared`, with the work
split where it is cheapest: the normal tapes, one per set-up and shared by all its
lanes, are filled on the CPU cores (:func:`~microslip.integrators.normal_tape.fill_tape`
in parallel over the set-ups), a block of ``tape_rows`` pieces at a time; each block
goes to the GPU, where one thread per lane runs through its set-up's pieces with the
lane law of :mod:`~microslip.integrators.rigid_lane_law` itself (:func:`free_piece` for
a piece without a switch, :func:`lane_piece` through the switches), compiled for the
GPU from the same functions. While a block is copied and run, the CPU fills the next.
The lane states stay on the GPU between blocks, so memory is bounded by two blocks of
tapes whatever the duration. A periodic normal motion's tape is one period's pieces,
repeated (:mod:`~microslip.integrators.periodic_tape`): those go to the GPU once, and
its lanes run all their periods in the first launch, a lane that repeats a period
taking the rest at once (:mod:`~microslip.integrators.lane_parking`'s rule), instead
of the repeated rows going through the blocks.

Every lane's arithmetic depends only on its own parameters and its set-up's tape, so a
lane's result does not depend on the other lanes, their number or order. The GPU
compiler contracts multiply-adds (FMA), so the bits differ from the CPU kernel's at the
rounding level (docs/theory/numerics.md, "Lanes on a GPU"). Under numba's CUDA
simulator (``NUMBA_ENABLE_CUDASIM=1``, no GPU needed: the test suite's check) the
kernel runs as Python with the CPU's arithmetic and gives the CPU kernel's bits.

Nothing requires a GPU: :func:`cuda_unavailable` says why none can be used.
"""

from __future__ import annotations

import functools
import threading

import numpy as np

from microslip import _jit_cache  # noqa: F401  (registers the cache before numba's CUDA jit)
from microslip.integrators import normal_tape as nt
from microslip.integrators import periodic_tape
from microslip.integrators.kernel import as_tuple
from microslip.integrators.lane_parking import after_periods, starts_as_before
from microslip.integrators.rigid_lane_law import free_piece, lane_piece
from microslip.integrators.rigid_pass import (
    DIRECTION,
    FM,
    KM,
    LANE_STALLED,
    MODE,
    N_BALANCE,
    N_RELEASE,
    OK,
    SPAN_ROWS,
    V,
    X,
)
from microslip.integrators.shared_lanes import (
    pack_lanes,
    raise_on_failure,
    start_modes,
    unpack_lanes,
)
from microslip.model.normal import normal_force

try:  # the kernel's global ``cuda``: numba's simulator swaps it for its own module
    from numba import cuda
except Exception as error:  # numba without its CUDA target
    cuda = None
    _IMPORT_ERROR = str(error)

THREADS_PER_BLOCK = 128
TAPE_ROWS = 1024  # pieces per set-up in a block of tapes (fewer for many set-ups)
TAPE_BLOCK_BYTES = 256 * 2**20  # at most this much tape per block, host and GPU each

# The last run's two page-locked blocks of tapes and row counts, by shape, for the next
# run of that shape (a sweep's chunks): page-locking them costs about as much as a
# 256-set-up map's lanes (0.055 s for 2 x 42 MiB on the H100 machine). A run takes them
# out, so two runs at once never share them; one shape is kept at most.
_PINNED: dict = {}
_PINNED_LOCK = threading.Lock()


def _take_pinned(shape):
    """(tapes, rows): two page-locked blocks of ``shape`` and two row counts, reused."""
    with _PINNED_LOCK:
        buffers = _PINNED.pop(shape, None)
    if buffers is None:
        tapes = [cuda.pinned_array(shape), cuda.pinned_array(shape)]
        rows = [cuda.pinned_array(shape[0], dtype=np.int64) for _ in range(2)]
        buffers = (tapes, rows)
    return buffers


def _give_back_pinned(shape, buffers):
    """Keep ``buffers`` (from :func:`_take_pinned`, no longer in use) for the next run."""
    with _PINNED_LOCK:
        _PINNED.clear()
        _PINNED[shape] = buffers


def block_rows(n_groups: int, tape_rows: int | None = None) -> int:
    """Pieces per set-up in a block of tapes of ``n_groups`` set-ups: ``tape_rows``
    where given, else TAPE_ROWS, fewer where the block would exceed TAPE_BLOCK_BYTES."""
    if tape_rows is not None:
        return int(tape_rows)
    return max(16, min(TAPE_ROWS, TAPE_BLOCK_BYTES // (n_groups * nt.ROW * 8)))


def span_rows(n_groups: int, tape_rows: int | None = None) -> int:
    """:func:`block_rows` rounded down to whole spans (``rigid_pass.SPAN_ROWS``): the
    lanes then take the CPU kernels' spans of a tape's rows (every SPAN_ROWS from its
    start, nt.TAPE_ROWS a multiple), none across two blocks."""
    return max(SPAN_ROWS, block_rows(n_groups, tape_rows) // SPAN_ROWS * SPAN_ROWS)


def cuda_unavailable() -> str | None:
    """None when a CUDA GPU (or numba's CUDA simulator) can run the lanes, else why not,
    in one line."""
    if cuda is None:
        return f"numba's CUDA target cannot be imported ({_IMPORT_ERROR})"
    try:
        if cuda.is_available():
            return None
    except Exception as error:  # a broken driver reports itself here
        return f"CUDA is not usable here ({error})"
    return "no CUDA GPU is available here (numba.cuda.is_available() is False)"


@functools.cache
def _kernel():
    """The lane kernel, compiled for the GPU on its first launch."""

    @cuda.jit(device=True)
    def lane_row(tape, r, fm, km, n_release, n_balance, direction, x, v, mode):
        # One lane through the piece in row r of ``tape`` (rows x nt.ROW): (x, ẋ, mode,
        # switches (< 0: stalled), 1 if the piece was flagged else 0).
        h = tape[r, nt.H]
        p_min = tape[r, nt.PMIN]
        p_max = tape[r, nt.PMAX]
        flag, x1, v1 = free_piece(
            mode, v, x, fm, km, n_release, n_balance, h, h * tape[r, nt.INT1],
            h * h * tape[r, nt.KINT1], p_min, p_max,
        )  # fmt: skip
        if not flag:
            return x1, v1, mode, 0, 0
        a = (tape[r, nt.A0], tape[r, nt.A1], tape[r, nt.A2], tape[r, nt.A3], tape[r, nt.A4])
        crit = (int(tape[r, nt.NCRIT]), tape[r, nt.CRIT1], tape[r, nt.CRIT2], tape[r, nt.CRIT3])
        x, v, mode, k = lane_piece(a, crit, h, fm, km, n_release, n_balance, direction, x, v, mode)
        return x, v, mode, k, 1

    @cuda.jit(device=True)
    def lane_span(tape, r0, r1, fm, km, n_release, n_balance, direction, x, v, mode):
        # One lane through rows [r0, r1) of ``tape``: as one piece (normal_tape.span)
        # where it holds no switch, else row by row, as the CPU kernel's spans
        # (rigid_pass.lanes_over_rows). (x, ẋ, mode, switches (< 0: stalled), rows
        # flagged.) The loop is nt.span's on this thread's reads of the tape: under
        # numba's CUDA simulator a compiled function cannot take the kernel's arrays.
        span = nt.EMPTY_SPAN
        for r in range(r0, r1):
            span = nt.extend_span(
                span, tape[r, nt.H], tape[r, nt.INT1], tape[r, nt.KINT1], tape[r, nt.PMIN],
                tape[r, nt.PMAX],
            )  # fmt: skip
        length, h_int, h2_kint, p_min, p_max = span
        flag, x1, v1 = free_piece(
            mode, v, x, fm, km, n_release, n_balance, length, h_int, h2_kint, p_min, p_max
        )
        if not flag:
            return x1, v1, mode, 0, 0
        switches = 0
        flags = 0
        for r in range(r0, r1):
            x, v, mode, k, f = lane_row(
                tape, r, fm, km, n_release, n_balance, direction, x, v, mode
            )
            flags += f
            if k < 0:
                return x, v, mode, k, flags
            switches += k
        return x, v, mode, switches, flags

    @cuda.jit
    def lanes_kernel(tapes, rows, lane_group, cycles, offsets, cycle_shape, lanes, done,
                     switches, flagged, stalled):  # fmt: skip
        # One thread per lane (a column of ``lanes``). A set-up with a cycle (period rows
        # > 0 in cycle_shape: period rows, tail rows, repeats) has no rows in the blocks:
        # its lanes run all its periods from ``cycles`` in the first launch, and one that
        # starts a period as it started the last one takes its remaining periods at once,
        # as in the CPU kernel (shared_lanes._run_cycle). Any other set-up's lanes run
        # through the block of tapes of each launch.
        i = cuda.grid(1)
        if i >= lanes.shape[1] or done[i] != 0:
            return
        g = lane_group[i]
        fm, km = lanes[FM, i], lanes[KM, i]
        n_release, n_balance = lanes[N_RELEASE, i], lanes[N_BALANCE, i]
        direction = lanes[DIRECTION, i]
        x, v, mode = lanes[X, i], lanes[V, i], lanes[MODE, i]
        n_switches = switches[i]
        n_flagged = flagged[i]
        period, tail, repeats = cycle_shape[g, 0], cycle_shape[g, 1], cycle_shape[g, 2]
        ok = True
        if period > 0:
            done[i] = 1
            cycle = cycles[offsets[g] : offsets[g + 1]]
            x_mark, v_mark, mode_mark = x, v, mode
            switches_mark, flagged_mark = n_switches, n_flagged
            p = 0  # the period about to start; p == repeats: the tail
            while True:
                if 0 < p < repeats and starts_as_before(v, mode, v_mark, mode_mark):
                    # It repeats the last period, bit for bit: the rest at once.
                    x, n_switches, n_flagged = after_periods(
                        repeats - p, x, n_switches, n_flagged, x - x_mark,
                        n_switches - switches_mark, n_flagged - flagged_mark,
                    )  # fmt: skip
                    p = repeats
                x_mark, v_mark, mode_mark = x, v, mode
                switches_mark, flagged_mark = n_switches, n_flagged
                lo, hi = (period, period + tail) if p == repeats else (0, period)
                for r in range(lo, hi, SPAN_ROWS):
                    x, v, mode, k, f = lane_span(
                        cycle, r, min(r + SPAN_ROWS, hi), fm, km, n_release, n_balance,
                        direction, x, v, mode,
                    )  # fmt: skip
                    n_flagged += f
                    if k < 0:
                        ok = False
                        break
                    n_switches += k
                if not ok or p == repeats:
                    break
                p += 1
        else:
            tape = tapes[g]
            for r in range(0, rows[g], SPAN_ROWS):
                x, v, mode, k, f = lane_span(
                    tape, r, min(r + SPAN_ROWS, rows[g]), fm, km, n_release, n_balance,
                    direction, x, v, mode,
                )  # fmt: skip
                n_flagged += f
                if k < 0:
                    ok = False
                    break
                n_switches += k
        if not ok:
            stalled[i] = 1
        lanes[X, i], lanes[V, i], lanes[MODE, i] = x, v, mode
        switches[i] = n_switches
        flagged[i] = n_flagged

    return lanes_kernel


def run_blocks(kernel, normal_coeffs, normal_states0, n_lanes, t_end, dt, tape_rows, stream,
               lane_args, periods=None, prepare=None, cycles=None,
               cycles_on_gpu=False):  # fmt: skip
    """Fill every set-up's tape block by block on the CPU cores and run
    ``kernel[blocks, THREADS_PER_BLOCK, stream](tapes, rows, *lane_args)`` on each block
    (one thread per lane; ``lane_args`` on the GPU, in ``stream``), after
    ``prepare(tapes, rows, stream)`` where given (work per block that the lanes share,
    queued on the same stream). Returns the status per set-up (0, or a normal
    integration's failure) once the GPU is done. ``periods``: the set-ups' periodic
    normal motions, as for :func:`~microslip.integrators.shared_lanes.run_shared`, or
    their ``cycles`` (:func:`~microslip.integrators.periodic_tape.cycles`) where the
    caller has them; with ``cycles_on_gpu`` the kernel reads a periodic set-up's cycle
    itself and the blocks hold no rows of it, else they hold its repeated rows."""
    n_groups = normal_coeffs.shape[0]
    t_end, dt = float(t_end), float(dt)
    if cycles is None:
        cycles = periodic_tape.cycles(normal_coeffs, normal_states0, periods, t_end, dt)
    carries = np.empty((n_groups, nt.CARRY))
    for g in range(n_groups):
        carries[g] = nt.start_tape(normal_states0[g, 0], normal_states0[g, 1])
    tape_rows = block_rows(n_groups, tape_rows)
    works = np.zeros((n_groups, nt.WORK_SCRATCH, nt.N_STATE))
    status = np.ones(n_groups, dtype=np.int64)
    if cycles_on_gpu:
        status[cycles[2][:, 0] > 0] = 0  # nothing to fill: 0 rows in every block
    # Two blocks of tapes in flight: page-locked on the host (asynchronous copies), one
    # filled by the CPU while the other is copied and run. One stream keeps each
    # block's copy before its kernel and the kernels in order.
    shape = (n_groups, int(tape_rows), nt.ROW)
    tapes, rows = _take_pinned(shape)
    d_tapes = [cuda.device_array(shape, stream=stream) for _ in range(2)]
    d_rows = [cuda.device_array(n_groups, dtype=np.int64, stream=stream) for _ in range(2)]
    copied = [cuda.event(), cuda.event()]
    blocks = (n_lanes + THREADS_PER_BLOCK - 1) // THREADS_PER_BLOCK
    b = 0
    periodic_tape.fill_blocks(normal_coeffs, carries, works, tapes[b], rows[b], status, t_end, dt,
                              *cycles)  # fmt: skip
    while np.all(status <= 1):
        d_tapes[b].copy_to_device(tapes[b], stream=stream)
        d_rows[b].copy_to_device(rows[b], stream=stream)
        copied[b].record(stream)
        if prepare is not None:
            prepare(d_tapes[b], d_rows[b], stream)
        kernel[blocks, THREADS_PER_BLOCK, stream](d_tapes[b], d_rows[b], *lane_args)
        if not np.any(status == 1):
            break
        b = 1 - b
        copied[b].synchronize()  # the host buffer's last copy (two blocks ago) is done
        periodic_tape.fill_blocks(normal_coeffs, carries, works, tapes[b], rows[b], status,
                                  t_end, dt, *cycles)  # fmt: skip
    stream.synchronize()  # the blocks' copies are done: the buffers may serve another run
    _give_back_pinned(shape, (tapes, rows))
    return np.where(status > 1, status, OK)


def run_lanes(kernel, name, normal_coeffs, normal_states0, lanes, lane_group, t_end, dt,
              tape_rows, before=(), after=(), periods=None, prepare=None,
              check=None, cycles=None, cycles_on_gpu=False, results=None,
              statuses=None, handed_back=None, alone_rows=None):  # fmt: skip
    """Run ``kernel`` over every block of tapes (:func:`run_blocks`, with ``prepare``) on
    ``lanes`` (rows x lanes, a column per lane, ``lane_group`` its set-up) and return
    ``results(lanes, switches, flagged)`` (default: that tuple) from the GPU. The kernel
    takes (tapes, rows, lane_group, *before, lanes, *after, switches, flagged, stalled),
    ``before`` and ``after`` host arrays that go to the GPU with it (or arrays on the GPU
    already). ``check()``, where given, runs once the GPU is done and may raise first;
    then RuntimeError naming ``name`` and the set-up if a normal integration failed, else
    :class:`~microslip.integrators.shared_lanes.LaneStalledError` for the set-ups handed
    back (a lane stalled, or a status of ``handed_back`` that ``statuses()`` gives the
    set-up: :func:`~microslip.integrators.shared_lanes.raise_on_failure`), with the
    results as its ``partial``: complete for every other set-up, since a thread's lane
    depends on nothing but its own set-up. With ``alone_rows`` (rows of the lane array) a
    lane that stalled is handed back alone, as the CPU Mindlin lanes do: those rows of it
    are NaN, the error's ``lanes`` names it, and the other lanes of its set-up, which
    ran to the end, keep their results. ``periods``, ``cycles`` and ``cycles_on_gpu``
    as for :func:`run_blocks`."""
    n_groups, n_lanes = normal_coeffs.shape[0], lanes.shape[1]
    stream = cuda.stream()

    def on_device(a):
        return cuda.to_device(a, stream=stream) if isinstance(a, np.ndarray) else a

    d_lanes = cuda.to_device(lanes, stream=stream)
    counts = [cuda.to_device(np.zeros(n_lanes, dtype=np.int64), stream=stream) for _ in range(3)]
    status = run_blocks(
        kernel, normal_coeffs, normal_states0, n_lanes, t_end, dt, tape_rows, stream,
        (
            cuda.to_device(lane_group, stream=stream),
            *(on_device(a) for a in before), d_lanes, *(on_device(a) for a in after), *counts,
        ),
        periods, prepare, cycles, cycles_on_gpu,
    )  # fmt: skip
    lanes = d_lanes.copy_to_host(stream=stream)
    switches, flagged, stalled = (d.copy_to_host(stream=stream) for d in counts)
    stream.synchronize()
    if check is not None:
        check()
    raise_on_failure(status, name)
    group_status = np.full(n_groups, OK, dtype=np.int64)
    if alone_rows is None:
        group_status[lane_group[stalled != 0]] = LANE_STALLED
    if statuses is not None:  # the kernel's own marks come first (they end the lanes)
        marked = statuses()
        group_status = np.where(marked != OK, marked, group_status)
    alone = np.zeros(0, dtype=np.int64)
    if alone_rows is not None:  # a lane of a set-up handed back whole goes with it
        alone = np.flatnonzero((stalled != 0) & (group_status[lane_group] == OK))
        for row in alone_rows:
            lanes[row, alone] = np.nan
    out = (lanes, switches, flagged) if results is None else results(lanes, switches, flagged)
    raise_on_failure(group_status, name, handed_back, alone, out)
    return out


def run_shared_cuda(normal_coeffs, normal_states0, group_of_lane, forces, mu_static,
                    mu_kinetic, t_end, dt, x0=None, v0=None, tape_rows=None,
                    periods=None):  # fmt: skip
    """:func:`~microslip.integrators.shared_lanes.run_shared` with the lanes on the GPU
    (same arguments and returns, SI units); ``tape_rows`` sets the pieces per set-up
    in a block of tapes (default: TAPE_ROWS, fewer where the block would exceed
    TAPE_BLOCK_BYTES), rounded down to whole spans (``rigid_pass.SPAN_ROWS``). Raises
    RuntimeError when no GPU can be used (:func:`cuda_unavailable`) or a normal
    integration or a lane fails."""
    reason = cuda_unavailable()
    if reason is not None:
        raise RuntimeError(reason)
    normal_coeffs = np.ascontiguousarray(normal_coeffs, dtype=np.float64)
    normal_states0 = np.asarray(normal_states0, dtype=np.float64)
    n_groups = normal_coeffs.shape[0]
    lanes, order, starts = pack_lanes(
        normal_coeffs, group_of_lane, forces, mu_static, mu_kinetic, x0, v0
    )
    if order.size == 0:
        none = np.zeros(0, dtype=np.int64)
        return unpack_lanes(lanes, order, none, none)
    for g in range(n_groups):
        y0, ydot0 = normal_states0[g, 0], normal_states0[g, 1]
        n0 = normal_force(0.0, y0, ydot0, as_tuple(normal_coeffs[g]))  # the tuple form
        start_modes(lanes, starts[g], starts[g + 1], n0)
    lane_group = np.repeat(np.arange(n_groups), np.diff(starts))
    tape_rows = span_rows(n_groups, tape_rows)
    cycles = periodic_tape.cycles(normal_coeffs, normal_states0, periods, float(t_end), float(dt))
    cycle_shape = cycles[2][:, :3].astype(np.int64)  # period rows, tail rows, repeats
    cycle_rows = cycles[0] if cycles[0].shape[0] > 0 else np.zeros((1, nt.ROW))  # none: 1 row
    return run_lanes(
        _kernel(), "shared-normal kernel (CUDA)", normal_coeffs, normal_states0, lanes,
        lane_group, t_end, dt, tape_rows, before=(cycle_rows, cycles[1], cycle_shape),
        after=(np.zeros(order.size, dtype=np.int8),), cycles=cycles, cycles_on_gpu=True,
        results=lambda lanes, switches, flagged: unpack_lanes(lanes, order, switches, flagged),
    )  # fmt: skip
