"""integrators.threads.run_ranges: every item once, in ranges of the asked size, on the
asked number of threads; an error in any range stops the handing out and is raised."""

from __future__ import annotations

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


def test_one_thread_runs_in_the_caller():
    before = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        idents = set()
        threads.run_ranges(lambda lo, hi: idents.add(threading.get_ident()), 10, per_task=1)
    finally:
        numba.set_num_threads(before)
    assert idents == {threading.get_ident()}


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
