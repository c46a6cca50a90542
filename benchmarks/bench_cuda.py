"""The shared-normal time map on a GPU against the same map on the CPU cores, one run.

    python benchmarks/bench_cuda.py [--quick] [--out DIR]

Runs only where numba's CUDA target finds a GPU (otherwise it says why and exits 0).
Each job runs the same lanes through :func:`~microslip.integrators.shared_lanes.run_shared`
(every CPU core) and :func:`~microslip.integrators.shared_lanes_cuda.run_shared_cuda`
(tapes on the CPU cores, lanes on the GPU) on the same machine (for a TangentialSpring
or a MindlinSpring their spring- or Mindlin-lane counterparts), with the periods the
sweep passes (a free vibration's tape is one period repeated, and repeating lanes park;
``--stepped`` adds the paper map on the stepped tape), warm (compile times
reported apart), best of three; and reports the GPU path's run time with the lanes
skipped (the tapes alone: the CPU's share), the two paths' largest difference and,
for the 256-force paper and Mindlin maps, the error against the event method at rtol
1e-12 on sample points.
Prints one table and writes cuda_results.json to DIR (default benchmarks/out).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

import microslip as ms
from microslip.analysis.free_vibration import free_period
from microslip.integrators import shared_lanes_cuda as slc
from microslip.integrators.mindlin_lanes import run_mindlin_lanes
from microslip.integrators.mindlin_lanes_cuda import run_mindlin_lanes_cuda
from microslip.integrators.normal_tape import normal_coefficients
from microslip.integrators.shared_lanes import run_shared
from microslip.integrators.spring_lanes import run_spring_lanes
from microslip.integrators.spring_lanes_cuda import run_spring_lanes_cuda
from microslip.simulation import initial_state_from_amplitude

PARAMS = ms.Parameters()
T0 = PARAMS.natural_period
DURATION = 0.05  # s


def best_time(function, *args, repeats=3):
    best, result = np.inf, None
    for _ in range(repeats):
        started = time.perf_counter()
        result = function(*args)
        best = min(best, time.perf_counter() - started)
    return result, best


def free_lanes(n_forces, n_amplitudes):
    """The paper map's lanes: F in [0.05, 0.95] N x A in [0, 3e-7] m, from rest at the top,
    with each set-up's period T(A) [s] (T0 at A = 0, rest, as the sweep passes them)."""
    forces = np.linspace(0.05, 0.95, n_forces)
    amplitudes = np.linspace(0.0, 3e-7, n_amplitudes)
    c = normal_coefficients(ms.Model(PARAMS).pack(0.0))
    coeffs = np.repeat(c[None], n_amplitudes, axis=0)
    normal0 = np.array([initial_state_from_amplitude(PARAMS, a)[:2] for a in amplitudes])
    periods = np.array([free_period(PARAMS, a) for a in amplitudes])
    return coeffs, normal0, forces, amplitudes, T0 / 200, periods


def stepped_lanes(n_forces, n_amplitudes):
    """:func:`free_lanes` on the stepped tape (no periods: every step integrated)."""
    *lanes, periods = free_lanes(n_forces, n_amplitudes)
    return (*lanes, np.zeros_like(periods))


def forced_lanes(n_forces, n_amplitudes):
    """Viscous(0.05) + HarmonicForce(A, 1400 Hz), A in [0.5, 5] N, from rest at y0."""
    forces = np.linspace(0.05, 0.95, n_forces)
    amplitudes = np.linspace(0.5, 5.0, n_amplitudes)
    model = ms.Model(PARAMS, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(2.0, 1400.0))
    coeffs = np.array(
        [
            normal_coefficients(model.replace(**{"excitation.amplitude": float(a)}).pack(0.0))
            for a in amplitudes
        ]
    )
    normal0 = np.tile([PARAMS.static_deflection, 0.0], (n_amplitudes, 1))
    dt = min(T0, 1.0 / 1400.0) / 200
    return coeffs, normal0, forces, amplitudes, dt, np.zeros(n_amplitudes)


def spring_lanes(n_forces, n_amplitudes):
    """The paper map's set-ups on TangentialSpring(K_n), dt = 1/200 of the shorter of T0
    and the body's tangential period (the sweep's default)."""
    coeffs, normal0, forces, amplitudes, _, periods = free_lanes(n_forces, n_amplitudes)
    k_t = PARAMS.contact_stiffness
    dt = min(T0, 2.0 * np.pi * np.sqrt(PARAMS.mass / k_t)) / 200
    return coeffs, normal0, forces, amplitudes, dt, periods, np.full(n_amplitudes, k_t)


def mindlin_lanes(n_forces, n_amplitudes):
    """The paper map's set-ups on MindlinSpring(0.8235), dt = 1/200 of the shorter of T0
    and the body's tangential period at rest (k_t = λ K_n, the sweep's default)."""
    coeffs, normal0, forces, amplitudes, _, periods = free_lanes(n_forces, n_amplitudes)
    k_t = MINDLIN_RATIO * PARAMS.contact_stiffness
    dt = min(T0, 2.0 * np.pi * np.sqrt(PARAMS.mass / k_t)) / 200
    return coeffs, normal0, forces, amplitudes, dt, periods, np.full(n_amplitudes, MINDLIN_RATIO)


# The kernels a job runs on the CPU and the GPU, and the switch counts' column.
KERNELS = {
    "rigid": (run_shared, slc.run_shared_cuda, 3),
    "spring": (run_spring_lanes, run_spring_lanes_cuda, 4),
    "mindlin": (run_mindlin_lanes, run_mindlin_lanes_cuda, 4),
}
MINDLIN_RATIO = 0.8235


def lane_arrays(coeffs, forces):
    n_groups = coeffs.shape[0]
    groups = np.repeat(np.arange(n_groups), forces.size)
    lane_forces = np.tile(forces, n_groups)
    mu = np.full(lane_forces.size, PARAMS.mu)
    return groups, lane_forces, mu


def job(name, setup, n_forces, n_amplitudes, rows, kind="rigid", event_model=None):
    """One row: ``setup``'s lanes on the ``kind`` kernels (KERNELS); with ``event_model``
    (the model of the lanes), the GPU's error against the event method at five points."""
    coeffs, normal0, forces, amplitudes, dt, periods, *spring = setup(n_forces, n_amplitudes)
    groups, lane_forces, mu = lane_arrays(coeffs, forces)
    args = (coeffs, normal0, *spring, groups, lane_forces, mu, mu, DURATION, dt)
    on_cpu, on_gpu, n_switches = KERNELS[kind]
    cpu, cpu_s = best_time(lambda *a: on_cpu(*a, periods=periods), *args)
    gpu, gpu_s = best_time(lambda *a: on_gpu(*a, periods=periods), *args)
    tapes_s = best_time(_tapes_only, coeffs, normal0, DURATION, dt, periods)[1]
    steps = DURATION / dt
    lane_steps = lane_forces.size * steps
    v_cpu, v_gpu = cpu[0] / DURATION, gpu[0] / DURATION
    scale = np.abs(v_cpu).max()
    diff = float(np.abs(v_gpu - v_cpu).max() / scale)
    row = {
        "job": f"{name}, {n_forces}x{n_amplitudes}, {DURATION} s",
        "cpu_s": cpu_s,
        "gpu_s": gpu_s,
        "tapes_s": tapes_s,
        "cpu_throughput": lane_steps / cpu_s,
        "gpu_throughput": lane_steps / gpu_s,
        "speedup": cpu_s / gpu_s,
        "gpu_vs_cpu": diff,
        "switches": int(gpu[n_switches].sum()),
        "switches_cpu": int(cpu[n_switches].sum()),
    }
    if event_model is not None:
        rng = np.random.default_rng(1)
        errors, reference = [], []
        for _ in range(5):
            i, j = rng.integers(n_forces), rng.integers(n_amplitudes)
            run = ms.simulate(
                event_model, force=forces[i], amplitude=amplitudes[j], duration=DURATION,
                rtol=1e-12,
            )  # fmt: skip
            reference.append(run.x[-1] / DURATION)
            errors.append(abs(v_gpu.reshape(n_amplitudes, n_forces)[j, i] - reference[-1]))
        row["gpu_vs_event"] = float(max(errors) / max(np.abs(reference).max(), scale))
    rows.append(row)
    print(json.dumps(row), flush=True)


def _tapes_only(coeffs, normal0, t_end, dt, periods):
    """The GPU path's CPU share: every block of tapes with one lane per set-up, F = 0
    (it never moves)."""
    n = coeffs.shape[0]
    zeros, mu = np.zeros(n), np.full(n, PARAMS.mu)
    return slc.run_shared_cuda(coeffs, normal0, np.arange(n), zeros, mu, mu, t_end, dt,
                               periods=periods)  # fmt: skip


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small grids (a smoke run)")
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "out")
    parser.add_argument(
        "--stepped",
        action="store_true",
        help="also the paper map on the stepped tape (no periods, no parking)",
    )
    args = parser.parse_args(argv)
    reason = slc.cuda_unavailable()
    if reason is not None:
        print(f"bench_cuda: skipped: {reason}")
        return 0
    from numba import cuda

    device = cuda.get_current_device()
    info = {
        "gpu": device.name.decode() if isinstance(device.name, bytes) else str(device.name),
        "cpu_cores": os.cpu_count(),
        "numba": __import__("numba").__version__,
        "python": sys.version.split()[0],
    }
    print(json.dumps(info), flush=True)
    compile_started = time.perf_counter()
    tiny = free_lanes(2, 2)
    groups, lane_forces, mu = lane_arrays(tiny[0], tiny[2])
    spring = {
        "rigid": (),
        "spring": (np.full(2, PARAMS.contact_stiffness),),
        "mindlin": (np.full(2, MINDLIN_RATIO),),
    }
    for side in (0, 1):  # the CPU kernels, then the GPU path (its kernels and tapes)
        compile_started = time.perf_counter()
        for kind, kernels in KERNELS.items():
            kernels[side](tiny[0], tiny[1], *spring[kind], groups, lane_forces, mu, mu,
                          20 * tiny[4], tiny[4])  # fmt: skip
        info[("compile_cpu_s", "compile_gpu_path_s")[side]] = time.perf_counter() - compile_started
    print(json.dumps(info), flush=True)
    rows = []
    sizes = [(64, 64)] if args.quick else [(256, 256), (1024, 256)]
    for n_forces, n_amplitudes in sizes:
        event_model = ms.Model(PARAMS) if n_forces == 256 else None
        job("paper", free_lanes, n_forces, n_amplitudes, rows, event_model=event_model)
        if args.stepped:
            job("paper, stepped tape", stepped_lanes, n_forces, n_amplitudes, rows)
    job("Viscous(0.05)+HarmonicForce", forced_lanes, 256, 16 if args.quick else 64, rows)
    mindlin = ms.Model(PARAMS, tangential=ms.MindlinSpring(MINDLIN_RATIO))
    for n_forces, n_amplitudes in [(64, 16)] if args.quick else [(256, 64), (1024, 256)]:
        job("TangentialSpring(K_n)", spring_lanes, n_forces, n_amplitudes, rows, "spring")
        job(f"MindlinSpring({MINDLIN_RATIO})", mindlin_lanes, n_forces, n_amplitudes, rows,
            "mindlin", event_model=mindlin if n_forces == 256 else None)  # fmt: skip
    print(f"\n{'job':46} {'CPU s':>8} {'GPU s':>8} {'tapes s':>8} {'GPU steps*traj/s':>17} "
          f"{'x CPU':>6} {'|GPU-CPU|':>9}")  # fmt: skip
    for row in rows:
        print(
            f"{row['job']:46} {row['cpu_s']:8.3f} {row['gpu_s']:8.3f} {row['tapes_s']:8.3f} "
            f"{row['gpu_throughput']:17.2e} {row['speedup']:6.1f} {row['gpu_vs_cpu']:9.1e}"
        )
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "cuda_results.json").write_text(json.dumps({"info": info, "rows": rows}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
