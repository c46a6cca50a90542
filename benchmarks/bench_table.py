"""The #10 benchmark table: one run, warm, each job side by side with its peer.

    python benchmarks/bench_table.py [--quick] [--out DIR]

Prints one table (job, microslip, peer, ratio, accuracy, target) to stdout, progress to
stderr, and writes results.json and scaling.png (time against size, log-log) to DIR
(default benchmarks/out, not tracked). JIT compilation is excluded from every timing
(each job runs once on a tiny input first) and measured on its own in subprocesses:
cold (an empty kernel cache) and warm (import to first result). Times under 1 s are the
best of three. See benchmarks/README.md for the machine and how to read the table.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests" / "validation"))

import bench_velocity_map as bvm  # noqa: E402  (the NumPy RK4 peer)
import microslip as ms  # noqa: E402

PARAMS = ms.Parameters()
T0 = PARAMS.natural_period
DURATION = 0.05  # s, the time-domain job


def log(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def best_time(function, *args, **kwargs):
    """(result, seconds): best of three when a run takes under 1 s."""
    best, result = np.inf, None
    for _ in range(3):
        started = time.perf_counter()
        result = function(*args, **kwargs)
        elapsed = time.perf_counter() - started
        best = min(best, elapsed)
        if elapsed > 1.0:
            break
    return result, best


def time_map(forces, amplitudes, duration=DURATION, dt=None):
    return np.asarray(
        ms.velocity_map(
            PARAMS, forces=forces, amplitudes=amplitudes, method="time", duration=duration, dt=dt
        ).values
    )


def _stepped_paper_map(forces, amplitudes):
    """x(DURATION) [m] of the paper model's (A, F) lanes as velocity_map runs them (one
    period's tape repeated), but every lane stepped through every period."""
    from microslip.integrators.normal_tape import normal_coefficients
    from microslip.integrators.shared_lanes import run_shared
    from microslip.simulation import initial_state_from_amplitude

    normal0 = np.array([initial_state_from_amplitude(PARAMS, a)[:2] for a in amplitudes])
    coeffs = np.repeat(normal_coefficients(ms.Model(PARAMS).pack(0.0))[None], len(amplitudes), 0)
    periods = [ms.free_period(PARAMS, a) if a > 0.0 else 0.0 for a in amplitudes]
    groups = np.repeat(np.arange(len(amplitudes)), len(forces))
    lane_forces = np.tile(forces, len(amplitudes))  # [N]
    mu = np.full(lane_forces.size, PARAMS.mu)
    return run_shared(coeffs, normal0, groups, lane_forces, mu, mu, DURATION, T0 / 200,
                      periods=periods, park=False)[0]  # fmt: skip


def job_time_map(n, peer_n, rows, scaling):
    """Paper model, n x n (F x A), 0.05 s, dt = T0/200: shared-normal kernel vs NumPy."""
    forces = np.linspace(0.05, 0.95, n)
    amplitudes = np.linspace(0.0, 3e-7, n)
    time_map(forces[:2], amplitudes[:2], 0.001)  # compile
    v, seconds = best_time(time_map, forces, amplitudes)
    steps = round(DURATION / (T0 / 200))
    throughput = n * n * steps / seconds
    peer_f = np.linspace(0.05, 0.95, peer_n)
    peer_a = np.linspace(0.0, 3e-7, peer_n)
    _, peer_seconds = best_time(bvm.numpy_rk4_naive, PARAMS, peer_f, peer_a, T0 / 200)
    peer_throughput = peer_n * peer_n * steps / peer_seconds
    # Accuracy: against the event method at rtol 1e-12 on sample points of the grid.
    rng = np.random.default_rng(1)
    picks = [(rng.integers(n), rng.integers(n)) for _ in range(10)]
    errors, reference = [], []
    for i, j in picks:
        run = ms.simulate(
            PARAMS, force=forces[i], amplitude=amplitudes[j], duration=DURATION, rtol=1e-12
        )
        reference.append(run.x[-1] / DURATION)
        errors.append(abs(v[i, j] - reference[-1]))
    error = max(errors) / max(abs(np.array(reference)).max(), np.abs(v).max())
    rows.append(
        {
            "job": f"time map, paper, {n}x{n}, 0.05 s, dt=T0/200",
            "microslip": f"{seconds:.3f} s = {throughput:.2e} steps*traj/s",
            "peer": f"NumPy RK4 {peer_n}x{peer_n}: {peer_throughput:.2e} steps*traj/s",
            "ratio": throughput / peer_throughput,
            "accuracy": f"{error:.1e} max v (vs event, 10 pts)",
            "target": ">= 2e9 steps*traj/s, >= 60x, <= 1e-6",
            "pass": bool(
                throughput >= 2e9 and throughput / peer_throughput >= 60 and error <= 1e-6
            ),
        }
    )
    # The same map with every lane stepped through every period (park=False): what the
    # kernel does per piece, without the shortcut of lanes that repeat a period.
    stepped_seconds = best_time(_stepped_paper_map, forces, amplitudes)[1]
    rows.append(
        {
            "job": "  same, every lane stepped through every period (park=False)",
            "microslip": f"{stepped_seconds:.3f} s = {n * n * steps / stepped_seconds:.2e} "
            "steps*traj/s",
            "peer": "-",
            "ratio": stepped_seconds / seconds,
            "accuracy": "ratio: park=False / park=True time",
            "target": "- (for reading the row above)",
            "pass": True,
        }
    )
    for size in sorted({size for size in (32, 64, 128, n) if size <= n}):
        f = np.linspace(0.05, 0.95, size)
        a = np.linspace(0.0, 3e-7, size)
        scaling.setdefault("time map (points)", []).append(
            (size * size, best_time(time_map, f, a)[1])
        )
    # Up to 50 s (74,000 periods): once every lane of a set-up repeats a period the
    # periods left cost nothing, so past the first few periods the time does not grow.
    for duration in (0.0125, 0.05, 0.5, 5.0, 50.0):
        scaling.setdefault("time map 64x64 (duration s x 1e4)", []).append(
            (
                duration * 1e4,
                best_time(time_map, forces[::4][:64], amplitudes[::4][:64], duration)[1],
            )
        )
    for steps_per_period in (100, 200, 400, 800):
        scaling.setdefault("time map 64x64 (steps per T0)", []).append(
            (
                steps_per_period,
                best_time(
                    time_map, forces[::4][:64], amplitudes[::4][:64], DURATION,
                    T0 / steps_per_period,
                )[1],
            )
        )  # fmt: skip


def job_forced_time_map(n_forces, n_amplitudes, rows):
    """Damping + harmonic excitation: forces x excitation amplitude, vs the event path."""
    model = ms.Model(PARAMS, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(2.0, 1400.0))
    forces = np.linspace(0.05, 0.95, n_forces)
    amps = np.linspace(0.5, 5.0, n_amplitudes)

    def run(f, a, duration=DURATION):
        return ms.sweep(
            model, {"excitation.amplitude": a}, force=f, method="time", duration=duration
        )

    run(forces[:2], amps[:1], 0.001)
    result, seconds = best_time(run, forces, amps)
    dt = (1.0 / 1400.0) / 200 if 1.0 / 1400.0 < T0 else T0 / 200
    steps = DURATION / dt
    throughput = n_forces * n_amplitudes * steps / seconds
    samples = [(0, 0), (n_amplitudes - 1, n_forces // 2), (n_amplitudes // 2, n_forces - 1)]
    values = np.asarray(result.values)
    peer_seconds, errors, reference = 0.0, [], []
    for j, i in samples:
        m = model.replace(**{"excitation.amplitude": float(amps[j])})
        started = time.perf_counter()
        x = ms.simulate(m, force=float(forces[i]), duration=DURATION).x[-1]
        peer_seconds += time.perf_counter() - started
        ref = ms.simulate(m, force=float(forces[i]), duration=DURATION, rtol=1e-12).x[-1]
        reference.append(ref / DURATION)
        errors.append(abs(values.reshape(n_amplitudes, n_forces)[j, i] - ref / DURATION))
        del x
    per_traj_peer = peer_seconds / len(samples)
    per_traj = seconds / (n_forces * n_amplitudes)
    error = max(errors) / max(np.abs(values).max(), 1e-300)
    rows.append(
        {
            "job": f"time map, Viscous(0.05)+HarmonicForce, {n_forces}x{n_amplitudes}",
            "microslip": f"{seconds:.3f} s = {throughput:.2e} steps*traj/s",
            "peer": f"scalar event path: {per_traj_peer * 1e3:.2f} ms/traj",
            "ratio": per_traj_peer / per_traj,
            "accuracy": f"{error:.1e} max v (vs event rtol 1e-12)",
            "target": ">= 1e9 steps*traj/s",
            "pass": bool(throughput >= 1e9),
        }
    )


def job_compliant_time_map(tangential, kernel, n_forces, n_amplitudes, rows, scaling=None,
                           params=PARAMS, top=3e-7):  # fmt: skip
    """A compliant tangential contact, forces x amplitudes (0 to ``top`` [m]), 0.05 s, vs
    the scalar event path: a TangentialSpring on the spring-lane kernel (one normal tape
    per amplitude, integrators/spring_lanes.py), a MindlinSpring on the Mindlin-lane
    kernel (the same tape, the stiffness following it: integrators/mindlin_lanes.py; on
    a Hertz contact past A = y0 each flight crossed on the scalar step:
    integrators/mindlin_windows.py)."""
    model = ms.Model(params, tangential=tangential)
    forces = np.linspace(0.05, 0.95, n_forces)
    amps = np.linspace(0.0, top, n_amplitudes)

    def run(f, a, duration=DURATION):
        return ms.sweep(model, None, force=f, amplitude=a, method="time", duration=duration)

    run(forces[:2], amps[:2], 0.001)
    result, seconds = best_time(run, forces, amps)
    if scaling is not None:  # points: forces x amplitudes at the job's aspect ratio
        for k in (8, 4, 2, 1):
            n_f, n_a = max(n_forces // k, 2), max(n_amplitudes // k, 2)
            f, a = np.linspace(0.05, 0.95, n_f), np.linspace(0.0, top, n_a)
            elapsed = seconds if k == 1 else best_time(run, f, a)[1]
            scaling.setdefault(f"{type(tangential).__name__} time map (points)", []).append(
                (n_f * n_a, elapsed)
            )
    steps = math.ceil(DURATION * 200 / ms.budget.shortest_period(model))
    throughput = n_forces * n_amplitudes * steps / seconds
    values = np.asarray(result.values)
    samples = [(n_forces // 2, n_amplitudes - 1), (n_forces - 1, n_amplitudes // 2), (1, 1)]
    peer_seconds, errors = 0.0, []
    for i, j in samples:
        started = time.perf_counter()
        ms.simulate(model, force=float(forces[i]), amplitude=float(amps[j]), duration=DURATION)
        peer_seconds += time.perf_counter() - started
        ref = ms.simulate(
            model, force=float(forces[i]), amplitude=float(amps[j]), duration=DURATION, rtol=1e-12
        ).x[-1]
        errors.append(abs(values[i, j] - ref / DURATION))
    per_traj_peer = peer_seconds / len(samples)
    per_traj = seconds / (n_forces * n_amplitudes)
    name = type(tangential).__name__
    if params.m2 != PARAMS.m2:
        name += f", m2 = {params.m2}, A to {top / params.static_deflection:.1f} y0"
    rows.append(
        {
            "job": f"time map, {name}, {n_forces}x{n_amplitudes} ({kernel})",
            "microslip": f"{seconds:.3f} s = {throughput:.2e} steps*traj/s",
            "peer": f"scalar event path: {per_traj_peer * 1e3:.2f} ms/traj",
            "ratio": per_traj_peer / per_traj,
            "accuracy": f"{max(errors) / np.abs(values).max():.1e} max v (vs event rtol 1e-12)",
            "target": ">= 1e9 steps*traj/s",
            "pass": bool(throughput >= 1e9),
        }
    )


def steady_map(n):
    f = np.linspace(0.05, 0.95, n)
    a = np.linspace(0.0, 3e-7, n)
    return np.asarray(ms.velocity_map(PARAMS, forces=f, amplitudes=a).values)


def job_steady_map(n, peer_seconds_64, rows, scaling):
    steady_map(4)
    _, seconds = best_time(steady_map, n)
    import scipy_reference

    forces = np.linspace(0.05, 0.95, n)
    amplitudes = np.linspace(0.0, 3e-7, n)
    v = ms.velocity_map(PARAMS, forces=forces[:: n // 4], amplitudes=amplitudes[:: n // 4])
    v = np.asarray(v.values)
    errors, refs = [], []
    for i, fi in enumerate(forces[:: n // 4]):
        for j, aj in enumerate(amplitudes[:: n // 4]):
            if aj == 0.0:
                continue
            ref = scipy_reference.steady_mean_velocity(PARAMS, fi, aj)
            if np.isfinite(ref):
                refs.append(abs(ref))
                errors.append(abs(v[i, j] - ref))
    error = max(errors) / max(refs)
    rows.append(
        {
            "job": f"exact steady map {n}x{n}",
            "microslip": f"{seconds:.3f} s ({seconds / n / n * 1e9:.0f} ns/point)",
            "peer": f"NumPy RK4 64x64 time job: {peer_seconds_64:.3f} s",
            "ratio": peer_seconds_64 / seconds,
            "accuracy": f"{error:.1e} max v (vs scipy steady cycle)",
            "target": "<= 0.6 x peer time",
            "pass": bool(seconds <= 0.6 * peer_seconds_64),
        }
    )
    for size in sorted({size for size in (256, 512, 1024, n) if size <= n}):
        scaling.setdefault("steady map (points)", []).append(
            (size * size, best_time(steady_map, size)[1])
        )


def job_forced_response(rows, scaling):
    """400 points with Floquet stability vs scipy integrating each frequency to steady state."""
    from forced_reference import NormalReference

    model = ms.Model(PARAMS, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(2.0, 1000.0))
    f0 = 1.0 / T0
    ms.forced_response(model, frequencies=(0.5 * f0, 0.6 * f0), max_points=10)
    result, seconds = best_time(
        ms.forced_response, model, frequencies=(0.3 * f0, 2.0 * f0), max_points=400
    )
    points = result.sizes[next(iter(result.sizes))]
    for size in (50, 100, 200, 400):
        scaling.setdefault("forced response (points)", []).append(
            (
                size,
                best_time(
                    ms.forced_response, model, frequencies=(0.3 * f0, 2.0 * f0), max_points=size
                )[1],
            )
        )
    # Peer: scipy DOP853 (rtol 1e-12) from rest over 150 excitation periods per frequency,
    # the steady amplitude read off one more period; microslip's orbit at the same
    # frequency (the shooting and Floquet test that each point of the curve runs) is the
    # accuracy check.
    peer_seconds, errors = [], []
    for ratio in (0.5, 1.5, 2.0):
        point = model.replace(**{"excitation.frequency": ratio * f0})
        reference = NormalReference(point)
        started = time.perf_counter()
        state = reference.settle(np.array([1.0, 0.0]), 150)
        amplitude = reference.period_summary(state)["amplitude"]
        peer_seconds.append(time.perf_counter() - started)
        orbit = ms.periodic_orbit(point)
        errors.append(abs(0.5 * (orbit.y_max - orbit.y_min) - amplitude) / amplitude)
    per_point = seconds / points
    per_point_peer = float(np.mean(peer_seconds))
    rows.append(
        {
            "job": "forced-response curve with stability",
            "microslip": f"{seconds:.3f} s for {points} points ({per_point * 1e3:.2f} ms/point)",
            "peer": f"scipy DOP853 150 periods to steady state: {per_point_peer:.2f} s/point",
            "ratio": per_point_peer / per_point,
            "accuracy": f"{max(errors):.1e} rel. amplitude (vs scipy, 3 frequencies)",
            "target": "<= 1 s for 400 points, >= 100x per point",
            "pass": bool(seconds <= 1.0 and points >= 400 and per_point_peer / per_point >= 100),
        }
    )


def job_effective_friction(n, rows, scaling):
    """mu_eff over drive speed x free normal amplitude (exact contact-point walk)."""
    model = ms.Model(PARAMS, tangential=ms.TangentialSpring(7e7), drive=ms.PrescribedVelocity(1e-4))
    speeds = np.geomspace(1e-6, 1e-2, n)
    amps = np.linspace(2e-8, 3e-7, n)
    ms.effective_friction_map(model, speeds[:2], "amplitude", amps[:1])  # compile
    result, seconds = best_time(ms.effective_friction_map, model, speeds, "amplitude", amps)
    mu = np.asarray(result["mu_eff"].values)
    for size in sorted({size for size in (32, 64, 128, n) if size <= n}):
        scaling.setdefault("mu_eff map (points)", []).append(
            (
                size * size,
                best_time(
                    ms.effective_friction_map, model, speeds[:: n // size], "amplitude",
                    amps[:: n // size],
                )[1],
            )
        )  # fmt: skip
    # Accuracy: against the event-method time average (a separate integration of the
    # same model) at three sample points.
    errors = []
    for j, i in [(n // 4, n // 4), (n // 2, n // 2), (n - 1, n // 2)]:
        point = model.replace(**{"drive.velocity": float(speeds[i])})
        reference = ms.effective_friction(
            point, amplitude=float(amps[j]), method="time_average", rtol=1e-12
        )
        errors.append(abs(mu[j, i] - reference.mu_eff))
    rows.append(
        {
            "job": f"mu_eff map {n}x{n} (speed x free amplitude), TangentialSpring",
            "microslip": f"{seconds:.3f} s ({seconds / n / n * 1e6:.1f} us/point)",
            "peer": "-",
            "ratio": float("nan"),
            "accuracy": f"{max(errors):.1e} abs mu_eff (vs event time average, 3 pts)",
            "target": "256x256 <= 1 s",
            "pass": bool(seconds * 65536 / (n * n) <= 1.0),
        }
    )


def job_forced_effective_friction(n_speeds, n_amplitudes, rows):
    """mu_eff over speed x excitation amplitude: one forced periodic orbit per amplitude."""
    model = ms.Model(
        PARAMS,
        damping=ms.Viscous(0.05),
        excitation=ms.HarmonicForce(2.0, 1400.0),
        tangential=ms.TangentialSpring(7e7),
        drive=ms.PrescribedVelocity(1e-4),
    )
    speeds = np.geomspace(1e-6, 1e-2, n_speeds)
    amps = np.linspace(0.5, 5.0, n_amplitudes)
    ms.effective_friction_map(model, speeds[:2], "excitation.amplitude", amps[:1])
    _, seconds = best_time(ms.effective_friction_map, model, speeds, "excitation.amplitude", amps)
    per_amplitude = seconds / n_amplitudes
    rows.append(
        {
            "job": f"mu_eff map {n_speeds}x{n_amplitudes} (speed x excitation amplitude), "
            "Viscous+HarmonicForce",
            "microslip": f"{seconds:.3f} s ({per_amplitude * 1e3:.1f} ms/amplitude; "
            f"256x256: {per_amplitude * 256:.1f} s)",
            "peer": "-",
            "ratio": float("nan"),
            "accuracy": "-",
            "target": "256x256 <= 1 s",
            "pass": bool(per_amplitude * 256 <= 1.0),
        }
    )


SUBPROCESS_FIRST_RESULT = """
import time, sys
started = time.perf_counter()
import numpy as np, microslip as ms
ms.velocity_map(ms.Parameters(), forces=np.linspace(0.1, 0.9, 4), amplitudes=[1e-7, 2e-7])
ms.velocity_map(ms.Parameters(), forces=np.linspace(0.1, 0.9, 4), amplitudes=[1e-7, 2e-7],
                method="time", duration=0.001)
ms.simulate(ms.Parameters(), force=0.5, amplitude=1e-7, duration=0.001)
print(time.perf_counter() - started)
"""


# The time map alone from an empty cache: the common first run of a sweep, which compiles
# only the time kernel's tree (docs/design.md, "Compile time").
SUBPROCESS_TIME_MAP_ONLY = """
import time
started = time.perf_counter()
import numpy as np, microslip as ms
ms.velocity_map(ms.Parameters(), forces=np.linspace(0.1, 0.9, 4), amplitudes=[1e-7, 2e-7],
                method="time", duration=0.001)
print(time.perf_counter() - started)
"""


def cpu_model() -> str:
    """The CPU's model name (Linux /proc/cpuinfo; the platform's processor elsewhere):
    the development machine is lent on more than one kind of host, and absolute times
    differ between them."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as info:
            for line in info:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    import platform

    return platform.processor() or "unknown CPU"


def _seconds_printed(code, env):
    """The last number a fresh interpreter running ``code`` prints."""
    run = [sys.executable, "-c", code]
    out = subprocess.run(run, env=env, capture_output=True, text=True, check=True).stdout
    return float(out.split()[-1])


def job_jit(rows):
    """Import to the first results in a fresh interpreter: once from an empty kernel
    cache (cold), and then from the cache it filled, the least of three starts (warm:
    like the other rows' best of runs; one start varies by ~0.1 s with the page cache
    and the machine's load, 0.90-1.04 s on the AMD host of 2026-11-29)."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, MICROSLIP_CACHE_DIR=cache)
        cold = _seconds_printed(SUBPROCESS_FIRST_RESULT, env)
        warm = min(_seconds_printed(SUBPROCESS_FIRST_RESULT, env) for _ in range(3))
    with tempfile.TemporaryDirectory() as cache:
        time_map_cold = _seconds_printed(
            SUBPROCESS_TIME_MAP_ONLY, dict(os.environ, MICROSLIP_CACHE_DIR=cache)
        )
    rows.append(
        {
            "job": "JIT: import to first results (steady map, time map, simulate)",
            "microslip": f"cold {cold:.1f} s (a time map alone {time_map_cold:.1f} s), "
            f"warm {warm:.2f} s",
            "peer": "-",
            "ratio": float("nan"),
            "accuracy": "-",
            "target": "cold <= 20 s (these kernels), warm <= 1 s",
            "pass": bool(cold <= 20.0 and warm <= 1.0),
        }
    )


# The peak RSS [bytes] of the map's own process: Linux's VmHWM, the high-water mark of
# the process's memory since its exec. Not getrusage's ru_maxrss, which on Linux keeps
# the parent's peak across fork and exec: a child that used 9 MB reported the 1.46 GB
# its parent held, and this row printed the bench process's own peak (1030-1040 MiB
# against 830-850 MiB for the map alone, 2026-11-29). Elsewhere ru_maxrss is all there is.
SUBPROCESS_STORE = """
import resource, sys, numpy as np, microslip as ms
n = int(sys.argv[1])
ms.velocity_map(ms.Parameters(), forces=np.linspace(0.05, 0.95, n),
                amplitudes=np.linspace(0.0, 3e-7, n), store=sys.argv[2], allow_large=True)
try:
    with open("/proc/self/status") as status:
        print(next(int(l.split()[1]) * 1024 for l in status if l.startswith("VmHWM:")))
except (OSError, StopIteration):
    print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024)
"""


def job_memory(n, rows):
    """Peak RSS of a steady map streamed through the chunk store, its kernels loaded from
    the cache: a small map first loads or compiles what the store's path needs, so the
    row measures the streaming and not LLVM's memory while compiling, which is the JIT
    row's (8192²: 831 MiB warm, 926 MiB from an empty cache, 2026-11-29; both by
    ru_maxrss from a small parent, see SUBPROCESS_STORE)."""
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run(
            [sys.executable, "-c", SUBPROCESS_STORE, "64", f"{tmp}/warm.zarr"],
            capture_output=True,
            text=True,
        )
        started = time.perf_counter()
        out = subprocess.run(
            [sys.executable, "-c", SUBPROCESS_STORE, str(n), f"{tmp}/map.zarr"],
            capture_output=True,
            text=True,
        )
        seconds = time.perf_counter() - started
    if out.returncode != 0:
        text = f"failed: {out.stderr.strip().splitlines()[-1] if out.stderr else out.returncode}"
        rows.append(
            {
                "job": f"memory, steady {n}x{n} via store",
                "microslip": text,
                "peer": "-",
                "ratio": float("nan"),
                "accuracy": "-",
                "target": "<= 1 GB",
                "pass": False,
            }
        )
        return
    rss = float(out.stdout.split()[-1])
    rows.append(
        {
            "job": f"memory, steady {n}x{n} through the chunk store (kernels cached)",
            "microslip": f"peak RSS {rss / 2**20:.0f} MiB in {seconds:.0f} s",
            "peer": "-",
            "ratio": float("nan"),
            "accuracy": "-",
            "target": "<= 1 GB",
            "pass": bool(rss <= 1e9),
        }
    )


def plot(scaling, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for name, points in scaling.items():
        size, seconds = np.array(points).T
        ax.loglog(size, seconds, "o-", label=name)
    ax.set_xlabel("size: points, duration [s] x 1e4, or RK4 steps per natural period T0")
    ax.set_ylabel("run time [s]")
    ax.set_title("microslip: run time against job size (warm)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small sizes (about a minute)")
    parser.add_argument("--out", type=Path, default=HERE / "out")
    args = parser.parse_args(argv)
    # The scaling runs stop the forced-response branch at max_points on purpose.
    warnings.filterwarnings("ignore", message="forced_response stopped at max_points")
    args.out.mkdir(parents=True, exist_ok=True)
    quick = args.quick
    rows, scaling = [], {}
    log(f"machine: {cpu_model()}, {os.cpu_count()} CPUs, load {os.getloadavg()[0]:.2f}")
    log("time map ...")
    job_time_map(64 if quick else 256, 32 if quick else 64, rows, scaling)
    log("forced time map ...")
    job_forced_time_map(64 if quick else 256, 8 if quick else 64, rows)
    log("compliant time map ...")
    spring = ms.TangentialSpring(PARAMS.contact_stiffness)
    job_compliant_time_map(
        spring, "spring lanes", 32 if quick else 256, 8 if quick else 64, rows, scaling
    )
    log("compliant time map, Mindlin ...")
    mindlin = ms.MindlinSpring(0.8235)
    job_compliant_time_map(
        mindlin, "Mindlin lanes", 32 if quick else 256, 8 if quick else 64, rows, scaling
    )
    log("compliant time map, Mindlin on a Hertz contact with flights ...")
    hertz = ms.Parameters(m2=1.5)
    job_compliant_time_map(
        mindlin, "Mindlin lanes, flights by windows", 16 if quick else 64, 4 if quick else 16,
        rows, params=hertz, top=1.5 * hertz.static_deflection,
    )  # fmt: skip
    log("steady map ...")
    _, peer64 = best_time(
        bvm.numpy_rk4_naive,
        PARAMS,
        np.linspace(0.05, 0.95, 64),
        np.linspace(0.0, 3e-7, 64),
        T0 / 200,
    )
    job_steady_map(512 if quick else 2048, peer64, rows, scaling)
    log("forced response ...")
    job_forced_response(rows, scaling)
    log("effective friction ...")
    job_effective_friction(64 if quick else 256, rows, scaling)
    job_forced_effective_friction(64 if quick else 256, 4 if quick else 32, rows)
    log("JIT ...")
    job_jit(rows)
    log("memory ...")
    job_memory(1024 if quick else 8192, rows)
    plot(scaling, args.out / "scaling.png")
    (args.out / "results.json").write_text(
        json.dumps(
            {"rows": rows, "scaling": scaling, "load": os.getloadavg()[0], "cpu": cpu_model()},
            indent=1,
            default=str,
        )
    )
    header = ("job", "microslip", "peer", "ratio", "accuracy", "target", "pass")
    print(" | ".join(header))
    print(" | ".join("---" for _ in header))
    for r in rows:
        ratio = "-" if not np.isfinite(r["ratio"]) else f"{r['ratio']:.1f}x"
        print(
            " | ".join(
                [
                    r["job"],
                    r["microslip"],
                    r["peer"],
                    ratio,
                    r["accuracy"],
                    r["target"],
                    "yes" if r["pass"] else "no",
                ]
            )
        )
    log(f"wrote {args.out / 'results.json'} and {args.out / 'scaling.png'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
