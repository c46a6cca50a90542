"""Independent work items over the cores: a compiled kernel that releases the GIL, called
on consecutive ranges of items from several Python threads.

The map kernels (the shared-normal lanes, the batched RK4 kernel, the steady map, the
forced tables, the contact-point walks) split their work into items that share nothing:
a normal set-up and its lanes, a block of trajectories, an amplitude, a drive speed.
numba's ``parallel=True`` would run such a loop with ``prange``, but compiling a parallel
region costs seconds per kernel at a cold start: the parfor passes, and the loop body
compiled once more as a gufunc (docs/design.md, "Threads"). A kernel compiled with
``nogil=True`` that takes a range [lo, hi) of items runs the same loop, and
:func:`run_ranges` calls it on the ranges from as many threads as numba would use
(:func:`thread_count`: ``numba.set_num_threads`` and ``NUMBA_NUM_THREADS`` apply).

The ranges are handed out in order, each to the next thread that is free, so a costly
item does not hold up a fixed share of the others. Every item's arithmetic is its own:
the results do not depend on the number of threads or on which thread ran which range.

Compiled code holds a signal off until it returns, and a map's chunk may run for
minutes: called from the main thread, :func:`run_ranges` runs every range on a helper
and waits where Ctrl-C reaches it, and raises it at once. The ranges already running
cannot be stopped from outside; a kernel that may run long takes a stop flag
(:func:`stop_flag`), which :func:`run_ranges` raises on an interrupt, and reads it
between its blocks of work, so that an interrupted map in a library session (a
notebook) does not keep the cores busy to its end. The same array holds a progress slot
per item (:func:`report`), which the waiting thread reads every POLL_S: a caller's
progress then moves inside a long item too.
"""

from __future__ import annotations

import os
import queue
import threading
from collections.abc import Callable
from concurrent import futures
from concurrent.futures import Future
from typing import Any

import numba
import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)

__all__ = [
    "HANDED_BACK",
    "PROGRESS_SCALE",
    "hand_back",
    "report",
    "run_ranges",
    "stop_flag",
    "thread_count",
]


def thread_count() -> int:
    """Threads the kernels run on: numba's thread count (``numba.set_num_threads``,
    ``NUMBA_NUM_THREADS``, else the CPUs)."""
    return int(numba.get_num_threads())


class _Pool:
    """Daemon threads kept between calls (a call takes milliseconds on the smallest maps:
    starting threads each time would show), at least as many idle as a call asks for.

    Not :class:`concurrent.futures.ThreadPoolExecutor`: its threads are joined when the
    interpreter exits, so a range abandoned by an interrupt (:func:`run_ranges`) would
    hold the exit until its compiled code ends, and the ranges of the next call would
    queue behind it. Here a busy thread is not counted as idle: the next call gets new
    threads, and the exit does not wait."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._tasks: queue.SimpleQueue = queue.SimpleQueue()
        self._idle = 0

    def submit(self, function: Callable[[], Any], count: int) -> list[Future]:
        """``count`` futures of ``function()``, each on a thread of its own if free."""
        futures = [Future() for _ in range(count)]
        with self._lock:
            for _ in range(count - self._idle):
                threading.Thread(target=self._serve, name="microslip", daemon=True).start()
                self._idle += 1
            self._idle -= count
        for future in futures:
            self._tasks.put((function, future))
        return futures

    def _serve(self) -> None:
        while True:
            function, future = self._tasks.get()
            if future.set_running_or_notify_cancel():
                try:
                    future.set_result(function())
                except BaseException as error:  # Ctrl-C included: the caller raises it
                    future.set_exception(error)
            with self._lock:
                self._idle += 1


_POOL = _Pool()


def _new_pool_after_fork() -> None:
    """A forked child has none of the parent's threads: a new, empty pool (the parent's
    idle count would send its ranges to threads that do not exist, and wait for ever)."""
    global _POOL
    _POOL = _Pool()


os.register_at_fork(after_in_child=_new_pool_after_fork)


def stop_flag(n_items: int = 0) -> np.ndarray:
    """A kernel's stop flag for :func:`run_ranges`' ``stop``: an int64, 0 until an
    interrupt abandons the ranges, then 1. A kernel reads ``stop[0]`` between its blocks
    of work (a tape block, a period) and returns at once where it is not 0; its results
    are then not read.

    With ``n_items``, one progress slot per item follows: a long item g may write the
    fraction of it done as ``stop[1 + g]`` = fraction x PROGRESS_SCALE (:func:`report`),
    and :func:`run_ranges` tells its ``on_done`` of those fractions as they grow. An
    item its kernel gives up on is marked there (:func:`hand_back`)."""
    return np.zeros(1 + n_items, dtype=np.int64)


PROGRESS_SCALE = 1 << 20  # a progress slot's value for a whole item
HANDED_BACK = -1  # a progress slot's mark: the kernel gave the item up (hand_back)
POLL_S = 0.5  # how often run_ranges reads the progress slots [s]


@njit(cache=True, nogil=True)
def report(stop, item, fraction):
    """Write ``fraction`` [1] of ``item`` done into its progress slot of ``stop``
    (:func:`stop_flag`), where it has one."""
    if 1 + item < stop.size:
        stop[1 + item] = int(min(max(fraction, 0.0), 1.0) * PROGRESS_SCALE)


@njit(cache=True, nogil=True)
def hand_back(stop, item):
    """Mark ``item`` of ``stop`` (:func:`stop_flag`) as handed back, where it has a slot:
    its kernel gave it up, and its caller runs it again on another kernel, which then
    tells of that work. The end of its range does not count it done (the progress it
    reported before stays told)."""
    if 1 + item < stop.size:
        stop[1 + item] = HANDED_BACK


def _done_in(stop: np.ndarray | None, n_items: int, lo: int, hi: int) -> int:
    """Items of the ended range [lo, hi) that count as done: all but those handed back."""
    if stop is None or stop.size <= n_items:
        return hi - lo
    return hi - lo - int(np.count_nonzero(stop[1 + lo : 1 + hi] == HANDED_BACK))


# Ranges per thread when the items are cheap and many: enough for the threads to even out
# their load, few enough that calling the kernel (~10 µs from Python) stays small.
RANGES_PER_THREAD = 8


def run_ranges(
    kernel: Callable[..., Any],
    n_items: int,
    *args: Any,
    per_task: int | None = None,
    interruptible: bool = True,
    stop: np.ndarray | None = None,
    on_done: Callable[[float], None] | None = None,
) -> None:
    """``kernel(lo, hi, *args)`` on consecutive ranges of at most ``per_task`` items that
    cover [0, n_items) (default: about RANGES_PER_THREAD ranges per thread; 1 where
    each item is a long job of its own), on :func:`thread_count` threads: this one and
    helpers. The kernel must release the GIL (``nogil=True``) and write its results into
    ``args``. An exception in a range stops the handing out of ranges, and is raised
    here once the ranges already running have ended.

    Called from the main thread, every range runs on a helper while this thread waits,
    so that Ctrl-C and SIGTERM reach it at once: compiled code holds a signal off until
    it returns. The interrupt is raised here without waiting for the ranges already
    running: their results, written into ``args``, are not to be read. Compiled code
    cannot be stopped from outside: a kernel that may run long takes a ``stop`` flag
    (:func:`stop_flag`, also among its ``args``), set here before the interrupt is raised,
    and returns at its next check of it; any other range runs to its end in the
    background. ``on_done(k)``, where given, is told of the k items done since its last
    call: a caller's progress. Called from the main thread, with ``stop`` holding a
    progress slot per item (:func:`stop_flag`), this thread tells it every POLL_S of the
    slots' growth and of the ranges ended, k then a fraction; otherwise it is called after
    each range that ends without error, with its items, from the thread that ran it (so
    it must be thread-safe). Either way an item handed back (:func:`hand_back`) does not
    count as done. That hand-off costs ~0.1 ms a call: a caller
    whose calls are short and many (an analysis's per-orbit work, milliseconds each)
    passes ``interruptible=False``, and this thread then takes its share of the ranges,
    as it does from another thread (a Dask worker), and runs them all itself on one
    thread."""
    count = thread_count()
    if per_task is None:
        per_task = -(-n_items // (count * RANGES_PER_THREAD))
    per_task = max(1, int(per_task))
    ranges = [(lo, min(lo + per_task, n_items)) for lo in range(0, n_items, per_task)]
    threads = min(count, len(ranges))
    on_main = interruptible and threading.current_thread() is threading.main_thread()
    if threads <= 1 and not on_main:
        for lo, hi in ranges:
            kernel(lo, hi, *args)
            if on_done is not None:
                on_done(_done_in(stop, n_items, lo, hi))
        return
    lock = threading.Lock()
    pending = iter(ranges)
    halted = threading.Event()

    # Called from the main thread, the kernels' progress slots (if any) are read while
    # it waits, and every report goes through it; else each range reports as it ends.
    watched = on_done is not None and on_main and stop is not None and stop.size > n_items
    ended: list[tuple[int, int]] = []

    def work() -> None:
        while not halted.is_set():
            with lock:
                item = next(pending, None)
            if item is None:
                return
            try:
                kernel(item[0], item[1], *args)
            except BaseException:
                halted.set()
                raise
            if watched:
                with lock:
                    ended.append(item)
            elif on_done is not None:
                on_done(_done_in(stop, n_items, *item))

    if not on_main:
        # A worker's call (Dask), where no signal comes, or short calls: the caller
        # takes its share.
        helpers = _POOL.submit(work, threads - 1)
        try:
            work()
        finally:
            _halt(helpers, halted)
            for future in helpers:
                if not future.cancelled():
                    future.exception()  # waits for it to end
    else:
        # Every range on a helper, this thread waiting where a signal can reach it:
        # compiled code holds off Ctrl-C until it returns, which may be minutes.
        helpers = _POOL.submit(work, threads)
        try:
            if watched:
                _watch(helpers, stop, n_items, ended, lock, on_done)
            for future in helpers:
                future.exception()
        except BaseException:
            # Ctrl-C or SIGTERM: raised at once. The ranges already running end at their
            # kernel's next check of ``stop`` (or their own end), their results unread.
            if stop is not None:
                stop[0] = 1
            _halt(helpers, halted)
            raise
    for future in helpers:
        if not future.cancelled() and future.exception() is not None:
            raise future.exception()


def _watch(helpers, stop, n_items, ended, lock, on_done) -> None:
    """Until the helpers end, tell ``on_done`` every POLL_S of the items' progress since
    the last call: the fractions in their slots of ``stop`` (:func:`report`), 1 for each
    item of a range in ``ended`` but one handed back (:func:`hand_back`), which keeps the
    fraction it reached."""
    level = np.zeros(n_items)
    told = 0.0
    while True:
        running = futures.wait(helpers, timeout=POLL_S).not_done
        with lock:
            finished, ended[:] = list(ended), []
        slots = stop[1 : 1 + n_items]
        np.maximum(level, slots / PROGRESS_SCALE, out=level)
        for lo, hi in finished:
            level[lo:hi] = np.where(slots[lo:hi] == HANDED_BACK, level[lo:hi], 1.0)
        total = float(level.sum())
        if total > told:
            on_done(total - told)
            told = total
        if not running:
            return


def _halt(helpers: list[Future], halted: threading.Event) -> None:
    """Stop handing out ranges; a helper still queued (behind another call's work) has
    none left to run."""
    halted.set()
    for future in helpers:
        future.cancel()
