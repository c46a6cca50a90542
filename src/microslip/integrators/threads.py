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
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from typing import Any

import numba

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)

__all__ = ["run_ranges", "thread_count"]

_pool_lock = threading.Lock()
_pool: ThreadPoolExecutor | None = None
_pool_size = 0


def thread_count() -> int:
    """Threads the kernels run on: numba's thread count (``numba.set_num_threads``,
    ``NUMBA_NUM_THREADS``, else the CPUs)."""
    return int(numba.get_num_threads())


def _helpers(count: int) -> ThreadPoolExecutor:
    """A pool of at least ``count`` threads, kept between calls (a call takes
    milliseconds on the smallest maps: starting threads each time would show)."""
    global _pool, _pool_size
    with _pool_lock:
        if _pool is None or _pool_size < count:
            if _pool is not None:
                _pool.shutdown(wait=False)
            _pool = ThreadPoolExecutor(count, thread_name_prefix="microslip")
            _pool_size = count
        return _pool


# Ranges per thread when the items are cheap and many: enough for the threads to even out
# their load, few enough that calling the kernel (~10 µs from Python) stays small.
RANGES_PER_THREAD = 8


def run_ranges(
    kernel: Callable[..., Any], n_items: int, *args: Any, per_task: int | None = None
) -> None:
    """``kernel(lo, hi, *args)`` on consecutive ranges of at most ``per_task`` items that
    cover [0, n_items) (default: about RANGES_PER_THREAD ranges per thread; 1 where
    each item is a long job of its own), on :func:`thread_count` threads: this one and
    helpers. The kernel must release the GIL (``nogil=True``) and write its results into
    ``args``. An exception in a range (Ctrl-C included) stops the handing out of ranges,
    and is raised here once the ranges already running have ended."""
    count = thread_count()
    if per_task is None:
        per_task = -(-n_items // (count * RANGES_PER_THREAD))
    per_task = max(1, int(per_task))
    ranges = [(lo, min(lo + per_task, n_items)) for lo in range(0, n_items, per_task)]
    threads = min(count, len(ranges))
    if threads <= 1:
        for lo, hi in ranges:
            kernel(lo, hi, *args)
        return
    lock = threading.Lock()
    queue = iter(ranges)
    stop = threading.Event()

    def work() -> None:
        while not stop.is_set():
            with lock:
                item = next(queue, None)
            if item is None:
                return
            try:
                kernel(item[0], item[1], *args)
            except BaseException:
                stop.set()
                raise

    helpers: list[Future] = [_helpers(threads - 1).submit(work) for _ in range(threads - 1)]
    try:
        work()
    finally:
        stop.set()
        # A helper still queued behind another call's work has nothing left to do.
        for future in helpers:
            future.cancel()
        for future in helpers:
            if not future.cancelled():
                future.exception()  # waits for it to end
    for future in helpers:
        if not future.cancelled() and future.exception() is not None:
            raise future.exception()
