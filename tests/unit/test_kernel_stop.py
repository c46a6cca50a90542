"""An interrupted map stops its compiled work (integrators.threads.stop_flag).

Called from the main thread, run_ranges raises Ctrl-C at once, but compiled code cannot
be stopped from outside: each long-running kernel (the rigid, spring and Mindlin lanes,
the batched RK4 kernel) reads its stop flag between blocks of work, and run_ranges sets
it before it raises. Without that, an interrupted map in a notebook kept the cores busy
until its ranges ended: for the runs here, minutes."""

from __future__ import annotations

import os
import signal
import threading
import time

import numba
import numpy as np
import pytest

import microslip as ms
from microslip.integrators.batched import simulate_batch
from microslip.integrators.mindlin_lanes import run_mindlin_lanes
from microslip.integrators.normal_tape import normal_coefficients
from microslip.integrators.shared_lanes import run_shared
from microslip.integrators.spring_lanes import run_spring_lanes
from microslip.simulation import initial_state_from_amplitude

P = ms.Parameters()
DT = P.natural_period / 200


def lanes(kind: str, t_end: float):
    """A call of ``kind``'s kernel: two set-ups (two ranges, one per thread), each of
    eight lanes pushed beyond μ m g (they slide for ever and never park), over
    ``t_end`` [s] on the stepped tape."""
    c = normal_coefficients(ms.Model(P).pack(0.0))
    coeffs = np.array([c, c])
    normal0 = np.array([initial_state_from_amplitude(P, a)[:2] for a in (1e-7, 2e-7)])
    forces = np.tile(np.linspace(1.1, 1.5, 8) * P.mu * P.mass * P.g, 2)
    groups = np.repeat([0, 1], 8)
    mu = np.full(16, P.mu)
    if kind == "rigid":
        return lambda: run_shared(coeffs, normal0, groups, forces, mu, mu, t_end, DT)
    if kind == "spring":
        k_t = [P.contact_stiffness] * 2
        return lambda: run_spring_lanes(coeffs, normal0, k_t, groups, forces, mu, mu, t_end, DT)
    if kind == "mindlin":
        ratio = [0.8, 0.8]
        return lambda: run_mindlin_lanes(coeffs, normal0, ratio, groups, forces, mu, mu, t_end,
                                         DT)  # fmt: skip
    batch = np.repeat([ms.Model(P).pack(force) for force in forces[:8]], 2, axis=0)
    states0 = np.zeros((16, 4))
    states0[:, :2] = np.repeat(normal0, 8, axis=0)
    return lambda: simulate_batch(batch, states0, t_end, DT, block=8)


def cpu_seconds_over(seconds: float) -> float:
    """CPU time [s] this process (every thread) spends in the next ``seconds`` [s]."""
    started = time.process_time()
    time.sleep(seconds)
    return time.process_time() - started


@pytest.mark.parametrize("kind", ["rigid", "spring", "mindlin", "batched"])
def test_an_interrupted_kernel_stops_its_ranges(kind):
    before = numba.get_num_threads()
    numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
    lanes(kind, 20 * DT)()  # compiled before the clock starts
    # Hours on the lanes; the batched kernel's ~1e-6 s per lane-step makes 1e7 steps a
    # minute (and its time grid, an array of the steps, stays small).
    run = lanes(kind, (1e7 if kind == "batched" else 1e9) * DT)
    timer = threading.Timer(1.0, os.kill, (os.getpid(), signal.SIGINT))
    try:
        timer.start()
        started = time.perf_counter()
        with pytest.raises(KeyboardInterrupt):
            run()
        assert time.perf_counter() - started < 5.0
        time.sleep(0.5)  # the ranges' next check of their flag: a block of tape, a step
        # Both ranges stopped: the process is idle (they would keep two cores busy).
        assert cpu_seconds_over(1.0) < 0.3
    finally:
        timer.cancel()
        numba.set_num_threads(before)
