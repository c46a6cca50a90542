"""integrators.threads.run_ranges: every item once, in ranges of the asked size, on the
asked number of threads; an error in any range stops the handing out and is raised."""

from __future__ import annotations

import os
import signal
import threading
import time

import numba
import numpy as np
import pytest

from microslip.integrators import threads


@pytest.fixture
def two_threads():
    before = numba.get_num_threads()
    numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
    yield numba.get_num_threads()
    numba.set_num_threads(before)


def test_every_item_once_in_ranges_of_the_asked_size(two_threads):
    seen = np.zeros(37, dtype=np.int64)
    sizes = []
    lock = threading.Lock()

    def kernel(lo, hi, out):
        with lock:
            sizes.append(hi - lo)
        out[lo:hi] += 1

    threads.run_ranges(kernel, 37, seen, per_task=5)
    assert seen.tolist() == [1] * 37
    assert sorted(sizes) == [2] + [5] * 7


def test_default_ranges_per_thread(two_threads):
    sizes = []
    threads.run_ranges(lambda lo, hi: sizes.append(hi - lo), 1000)
    per_task = -(-1000 // (two_threads * threads.RANGES_PER_THREAD))
    assert max(sizes) == per_task and sum(sizes) == 1000


def test_one_thread_runs_in_the_caller_off_the_main_thread_or_when_short():
    """Off the main thread (a Dask worker), or for short calls (``interruptible=False``),
    one thread is the caller itself: no hand-off to a helper."""
    idents, caller = set(), []

    def call(interruptible):
        caller.append(threading.get_ident())
        numba.set_num_threads(1)  # per thread
        threads.run_ranges(
            lambda lo, hi: idents.add(threading.get_ident()), 10, per_task=1,
            interruptible=interruptible,
        )  # fmt: skip

    worker = threading.Thread(target=call, args=(True,))
    worker.start()
    worker.join()
    before = numba.get_num_threads()
    try:
        call(False)
    finally:
        numba.set_num_threads(before)
    assert idents == set(caller) and len(caller) == 2


@numba.njit(nogil=True)
def _spin(lo, hi, iterations, done):
    """Compiled code that holds off signals: a chain of dependent multiply-adds that
    cannot be folded or vectorised (no fastmath), ~1 s per 3e8 iterations."""
    x = 0.0
    for _ in range(iterations):
        x = x * 1.0000001 + 1e-9
    done[lo] = 1.0 + 0.0 * x


@pytest.mark.parametrize("n_threads", [1, 2])
def test_ctrl_c_in_compiled_ranges_is_raised_at_once(n_threads):
    """On the main thread the ranges run on helpers and this thread waits where a
    signal reaches it: a Ctrl-C while a compiled range runs is raised before that range
    ends (before, the caller ran a range itself, and its Ctrl-C came when the range
    ended). The range goes on to its end in the background."""
    before = numba.get_num_threads()
    numba.set_num_threads(min(n_threads, numba.config.NUMBA_NUM_THREADS))
    done = np.zeros(2)
    _spin(0, 1, 0, done)  # compiled before the clock starts
    done[:] = 0.0
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    try:
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            threads.run_ranges(_spin, 2, 10**9, done, per_task=1)  # seconds
        assert done[0] == 0.0  # the range was still running
    finally:
        timer.cancel()
        numba.set_num_threads(before)


@pytest.mark.skipif(numba.config.NUMBA_NUM_THREADS < 2, reason="needs two CPUs")
def test_ranges_run_on_two_threads_at_once(two_threads):
    # Each range waits until the other thread is inside a range too: on one thread this
    # would time out.
    barrier = threading.Barrier(2, timeout=10.0)
    idents = set()

    def kernel(lo, hi):
        idents.add(threading.get_ident())
        barrier.wait()

    threads.run_ranges(kernel, 4, per_task=1)
    assert len(idents) == 2


@pytest.mark.parametrize("failing", [0, 5])
def test_an_error_stops_the_ranges_and_is_raised(two_threads, failing):
    started = []

    def kernel(lo, hi):
        started.append(lo)
        time.sleep(0.01)
        if lo == failing:
            raise KeyboardInterrupt if failing == 0 else ValueError(f"range {lo}")

    error = KeyboardInterrupt if failing == 0 else ValueError
    with pytest.raises(error):
        threads.run_ranges(kernel, 200, per_task=1)
    # The ranges handed out after the failure are the few already asked for, not all.
    assert len(started) < 20


def test_a_compiled_kernel_that_releases_the_gil(two_threads):
    @numba.njit(nogil=True)
    def square(lo, hi, x, out):
        for i in range(lo, hi):
            out[i] = x[i] * x[i]

    x = np.arange(1000.0)
    out = np.zeros_like(x)
    threads.run_ranges(square, x.size, x, out)
    assert np.array_equal(out, x * x)


def _ranges_in_a_child(queue):
    seen = np.zeros(16)
    threads.run_ranges(lambda lo, hi: seen.__setitem__(slice(lo, hi), 1.0), 16, per_task=2)
    queue.put(seen.sum())


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork")
def test_a_forked_child_runs_its_ranges(two_threads):
    """A child forked after the parent used the pool has none of its threads: its ranges
    must still run (a pool that counted the parent's idle threads waited for ever)."""
    import multiprocessing

    threads.run_ranges(lambda lo, hi: None, 16, per_task=2)  # the parent's threads exist
    context = multiprocessing.get_context("fork")
    queue = context.Queue()
    child = context.Process(target=_ranges_in_a_child, args=(queue,))
    child.start()
    child.join(60)
    if child.is_alive():
        child.kill()
        pytest.fail("the forked child's ranges never ran")
    assert child.exitcode == 0 and queue.get(timeout=5) == 16.0
