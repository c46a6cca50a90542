"""Benchmark of one trajectory: microslip's event and RK4 methods against scipy.

Job: F = 0.5 N, 0.05 s of physical time (≈ 70 normal periods) from rest at the top, for
the paper's amplitudes A = y0/3, 2y0/3, y0 and a loss-of-contact case 1.3 y0. Accuracy
is |x(T) - x_ref(T)| / x_ref(T), the reference being an independent event-driven scipy
DOP853 integration at rtol 1e-12 (tests/validation/scipy_reference.py). JIT warm-up is
timed separately. Run: python benchmarks/bench_simulate.py
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

# The independent scipy reference lives with the validation tests, which check it.
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "validation"))

import scipy_reference as scipy_ref

import microslip as ms

DURATION = 0.05
FORCE = 0.5


def best_time(function, repeats: int = 5) -> tuple[float, object]:
    best, value = np.inf, None
    for _ in range(repeats):
        started = time.perf_counter()
        value = function()
        best = min(best, time.perf_counter() - started)
    return best, value


def main() -> None:
    p = ms.Parameters()
    y0 = p.static_deflection
    started = time.perf_counter()
    ms.simulate(p, force=FORCE, amplitude=y0 / 3, duration=1e-3)
    ms.simulate(p, force=FORCE, amplitude=y0 / 3, duration=1e-3, method="rk4")
    warm_up = time.perf_counter() - started
    print(f"JIT warm-up (first calls, includes loading the numba cache): {warm_up:.2f} s\n")
    header = f"{'A/y0':>5} {'method':<28} {'time [ms]':>10} {'x(T) rel. error':>16} {'speed-up':>9}"
    print(header)
    print("-" * len(header))
    for fraction in (1 / 3, 2 / 3, 1.0, 1.3):
        amplitude = fraction * y0
        reference = (
            scipy_ref.finite_time_mean_velocity(p, FORCE, amplitude, DURATION, rtol=1e-12)
            * DURATION
        )
        rows = []
        t_scipy, x_scipy = best_time(
            lambda a=amplitude: (
                DURATION * scipy_ref.finite_time_mean_velocity(p, FORCE, a, DURATION, rtol=1e-9)
            ),
            repeats=1,
        )
        rows.append(("scipy DOP853 events, rtol 1e-9", t_scipy, x_scipy))
        t_event, r_event = best_time(
            lambda a=amplitude: ms.simulate(p, force=FORCE, amplitude=a, duration=DURATION)
        )
        rows.append(("microslip event (defaults)", t_event, r_event.x[-1]))
        t_rk4, r_rk4 = best_time(
            lambda a=amplitude: ms.simulate(
                p, force=FORCE, amplitude=a, duration=DURATION, method="rk4"
            )
        )
        rows.append(("microslip rk4, dt = T0/200", t_rk4, r_rk4.x[-1]))
        for name, seconds, x_end in rows:
            error = abs(x_end - reference) / abs(reference)
            print(
                f"{fraction:5.3f} {name:<28} {seconds * 1e3:10.2f} {error:16.2e} "
                f"{t_scipy / seconds:8.0f}x"
            )
    print("\nspeed-up = scipy time / method time, same job, same machine, one run.")


if __name__ == "__main__":
    main()
