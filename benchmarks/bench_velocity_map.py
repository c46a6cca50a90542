"""Benchmark: the mean-velocity map v(F, A) of Fig. 7 by four methods, on one F × A grid.

    python benchmarks/bench_velocity_map.py [NFxNA] [--numpy-grid 64] [--scipy-points 12]

Grid: F in [0.05, 0.95] N × A in [0, 3e-7] m, paper data (default 256 × 256).

1. steady map: the exact long-time mean (``microslip.velocity_map``, or the kernel
   ``mean_velocity_grid`` when the public function is missing);
2. batched kernel: ``simulate_batch``, RK4 with located switching, 0.05 s per point from
   rest at the top, dt = T0/200, v = x(0.05)/0.05;
3. scipy ``solve_ivp`` DOP853, rtol 1e-9, event restarts
   (``tests/validation/scipy_reference.py``), on a
   random sample of grid points, time extrapolated to the grid: the same 0.05 s job,
   and the steady cycle (mean = Δx/Δt between the 2nd and 3rd stick starts);
4. NumPy RK4 vectorised over the grid with the naive once-per-step stick/slip decision,
   0.05 s per point (on a smaller grid if asked; time extrapolated per trajectory-step).

Accuracy: against solve_ivp DOP853 rtol 1e-12 on sample grid points (stick-slip,
just above / below the motion threshold, loss of contact, plus the random scipy sample):
"err steady" = max |v - v_ref| / max v_ref with v_ref the steady-cycle mean (what the
map means); "err 0.05 s" = the same against the reference x(0.05)/0.05 (the integration
error of a time-domain method alone, without its start-up transient).
JIT compilation is excluded from the timings (every compiled function runs once on a
tiny input first) and printed separately. Times of runs shorter than 1 s are the best of
three.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numba
import numpy as np

# The independent scipy reference lives with the validation tests, which check it.
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "validation"))

from scipy_reference import finite_time_mean_velocity, steady_mean_velocity

import microslip
from microslip import Parameters
from microslip.analysis.steady_state import ORBIT_STEPS, mean_velocity_grid
from microslip.integrators.batched import simulate_batch, time_grid
from microslip.model.coefficients import FORCE, pack

F_RANGE = (0.05, 0.95)  # N
A_RANGE = (0.0, 3e-7)  # m
DURATION = 0.05  # s
STEPS_PER_PERIOD = 200
TARGET_STEADY_TIME = 0.5  # s for 256 × 256
TARGET_STEADY_ERROR = 1e-6
TARGET_THROUGHPUT = 5e8  # RK4 steps·trajectories per second


# --- the methods -----------------------------------------------------------------------
def steady_map(params, forces, amplitudes):
    """(v[F, A], name): the public map if present, else the compiled kernel."""
    if hasattr(microslip, "velocity_map"):
        return microslip.velocity_map(params, forces=forces, amplitudes=amplitudes).values
    return steady_kernel(params, forces, amplitudes)


def steady_kernel(params, forces, amplitudes):
    out = np.empty((forces.size, amplitudes.size))
    if not mean_velocity_grid(forces, amplitudes, pack(params, 0.0), ORBIT_STEPS, out):
        raise RuntimeError("orbit table overflow")
    return out


def lanes(params, forces, amplitudes):
    """Per-trajectory coefficients and initial states (rest at the top) for (F, A) pairs."""
    coeffs = np.repeat(pack(params, 0.0)[None, :], forces.size, axis=0)
    coeffs[:, FORCE] = forces
    states = np.zeros((forces.size, 4))
    states[:, 0] = params.static_deflection - amplitudes
    return coeffs, states


def batched(params, forces, amplitudes, dt):
    coeffs, states = lanes(params, forces, amplitudes)
    return simulate_batch(coeffs, states, DURATION, dt)


def numpy_rk4_naive(params, forces, amplitudes, dt):
    """The obvious vectorised RK4: stick or slip decided once per step, from its start.

    Slip if the slider moves (ẋ > 0) or the drive beats static friction (F > μ|R|);
    a slider whose velocity would turn negative stops instead (F >= 0: never backwards).
    """
    scn, mass, g, mu = params.stiffness_coefficient, params.mass, params.g, params.mu
    force = np.asarray(forces, dtype=float)
    y = params.static_deflection - np.asarray(amplitudes, dtype=float)
    yd = np.zeros_like(y)
    x = np.zeros_like(y)
    xd = np.zeros_like(y)

    def accelerations(y, slip):
        reaction = scn * np.maximum(y, 0.0) ** 2
        return g - reaction / mass, np.where(slip, (force - mu * reaction) / mass, 0.0)

    t = 0.0
    for target in time_grid(DURATION, dt):
        h = target - t
        slip = (xd > 0.0) | (force > mu * scn * np.maximum(y, 0.0) ** 2)
        a1, x1 = accelerations(y, slip)
        y2, yd2, xd2 = y + 0.5 * h * yd, yd + 0.5 * h * a1, xd + 0.5 * h * x1
        a2, x2 = accelerations(y2, slip)
        y3, yd3, xd3 = y + 0.5 * h * yd2, yd + 0.5 * h * a2, xd + 0.5 * h * x2
        a3, x3 = accelerations(y3, slip)
        y4, yd4, xd4 = y + h * yd3, yd + h * a3, xd + h * x3
        a4, x4 = accelerations(y4, slip)
        y = y + h / 6.0 * (yd + 2.0 * yd2 + 2.0 * yd3 + yd4)
        yd = yd + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)
        x = x + h / 6.0 * (xd + 2.0 * xd2 + 2.0 * xd3 + xd4)
        xd = np.maximum(xd + h / 6.0 * (x1 + 2.0 * x2 + 2.0 * x3 + x4), 0.0)
        t = target
    return x / DURATION


# --- helpers ---------------------------------------------------------------------------
def timed(fn, *args, repeat_below=1.0):
    """(result, seconds): best of three if a run takes less than ``repeat_below`` s."""
    start = time.perf_counter()
    result = fn(*args)
    best = time.perf_counter() - start
    if best < repeat_below:
        for _ in range(2):
            start = time.perf_counter()
            result = fn(*args)
            best = min(best, time.perf_counter() - start)
    return result, best


def parse_grid(text: str) -> tuple[int, int]:
    parts = text.lower().split("x")
    if len(parts) == 1:
        return int(parts[0]), int(parts[0])
    if len(parts) == 2:
        return int(parts[0]), int(parts[1])
    raise argparse.ArgumentTypeError(f"grid must be N or NFxNA, got {text!r}")


def sample_points(params, forces, amplitudes, rng):
    """24 grid nodes (i_F, i_A, label): stick-slip, contact loss, near threshold, at rest."""
    y0 = params.static_deflection
    threshold = np.array([params.motion_threshold(a) for a in amplitudes])
    i_f, i_a = np.meshgrid(np.arange(forces.size), np.arange(amplitudes.size), indexing="ij")
    moving = forces[i_f] > 1.05 * threshold[i_a]
    picks = []

    def choose(mask, count, label):
        candidates = np.flatnonzero(mask.ravel())
        for k in rng.choice(candidates, size=min(count, candidates.size), replace=False):
            picks.append((int(i_f.ravel()[k]), int(i_a.ravel()[k]), label))

    choose(moving & (amplitudes[i_a] <= y0), 10, "stick-slip")
    choose(moving & (amplitudes[i_a] > y0), 6, "contact loss")
    # Just above (6) and just below (2) the motion threshold, at random amplitudes A < y0.
    inside = np.flatnonzero((amplitudes > 0.05 * y0) & (amplitudes < 0.95 * y0))
    inside = [j for j in inside if forces[0] <= threshold[j] < forces[-1]]
    for n, j in enumerate(rng.choice(inside, size=min(8, len(inside)), replace=False)):
        if n < 6:
            picks.append((int(np.flatnonzero(forces > threshold[j])[0]), int(j), "near threshold"))
        else:
            picks.append((int(np.flatnonzero(forces <= threshold[j])[-1]), int(j), "at rest"))
    return picks


def row(name, grid, seconds, points, err_steady, err_time, steps=None, note=""):
    return {
        "name": name,
        "grid": grid,
        "time": seconds,
        "points": points,
        "err_steady": err_steady,
        "err_time": err_time,
        "steps": steps,
        "note": note,
    }


def fmt_err(value):
    return "-" if value is None else f"{value:.1e}"


# --- main ------------------------------------------------------------------------------
def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "grid", nargs="?", default="256", type=parse_grid, help="N or NFxNA (default 256)"
    )
    parser.add_argument(
        "--numpy-grid",
        type=parse_grid,
        default=(64, 64),
        help="grid of the NumPy RK4 run (default 64; time extrapolated)",
    )
    parser.add_argument("--scipy-points", type=int, default=12)
    parser.add_argument("--seed", type=int, default=2005)
    args = parser.parse_args(argv)
    n_f, n_a = args.grid
    params = Parameters()
    forces = np.linspace(*F_RANGE, n_f)
    amplitudes = np.linspace(*A_RANGE, n_a)
    dt = params.natural_period / STEPS_PER_PERIOD
    n_steps = time_grid(DURATION, dt).size
    n_points = n_f * n_a
    rng = np.random.default_rng(args.seed)
    print(
        f"microslip velocity map benchmark: {n_f} x {n_a} grid, F in {F_RANGE} N, "
        f"A in {A_RANGE} m, paper data"
    )
    print(
        f"time-domain job: {DURATION} s per point from rest at the top, dt = T0/"
        f"{STEPS_PER_PERIOD} = {dt:.4g} s, {n_steps} steps "
        f"({n_points * n_steps / 1e6:.1f}e6 trajectory-steps on the grid); "
        f"numba threads: {numba.get_num_threads()}"
    )

    # JIT warm-up on tiny inputs.
    start = time.perf_counter()
    steady_map(params, forces[:2], amplitudes[:2])
    steady_kernel(params, forces[:2], amplitudes[:2])
    warm_steady = time.perf_counter() - start
    start = time.perf_counter()
    coeffs, states = lanes(params, forces[:4], amplitudes[-4:])
    simulate_batch(coeffs, states, 20 * dt, dt)
    warm_batched = time.perf_counter() - start
    print(
        f"JIT warm-up (compilation or cache load, not in the timings): steady map "
        f"{warm_steady:.2f} s, batched kernel {warm_batched:.2f} s"
    )

    # Reference points: 24 designed + the random scipy sample.
    picks = sample_points(params, forces, amplitudes, rng)
    flat = rng.choice(n_points, size=args.scipy_points, replace=False)
    random_picks = [(int(k // n_a), int(k % n_a), "random") for k in flat]
    ref_points = picks + random_picks
    ref_f = np.array([forces[i] for i, _j, _l in ref_points])
    ref_a = np.array([amplitudes[j] for _i, j, _l in ref_points])
    start = time.perf_counter()
    v_ss = np.array(
        [steady_mean_velocity(params, f, a, rtol=1e-12) for f, a in zip(ref_f, ref_a, strict=True)]
    )
    v_t = np.array(
        [
            finite_time_mean_velocity(params, f, a, DURATION, rtol=1e-12)
            for f, a in zip(ref_f, ref_a, strict=True)
        ]
    )
    ref_time = time.perf_counter() - start
    scale = np.max(v_ss)
    labels = [label for _i, _j, label in ref_points]
    counts = {label: labels.count(label) for label in dict.fromkeys(labels)}
    print(
        f"reference: solve_ivp DOP853 rtol 1e-12 at {len(ref_points)} grid points "
        f"({', '.join(f'{v} {k}' for k, v in counts.items())}): steady cycle and "
        f"x(0.05)/0.05, {ref_time:.1f} s; max v_ref = {scale:.4e} m/s"
    )

    def errors(values, which=slice(None)):
        steady = np.max(np.abs(values - v_ss[which])) / scale
        finite = np.max(np.abs(values - v_t[which])) / scale
        return steady, finite

    def at_grid(grid_values):
        return np.array([grid_values[i, j] for i, j, _l in ref_points])

    rows = []
    # 1. Steady map.
    name = "steady map (microslip.velocity_map)"
    if not hasattr(microslip, "velocity_map"):
        name = "steady map (mean_velocity_grid kernel)"
    v_map, t_map = timed(steady_map, params, forces, amplitudes)
    err_map, _ = errors(at_grid(v_map))
    rows.append(row(name, f"{n_f}x{n_a}", t_map, n_points, err_map, None))
    if hasattr(microslip, "velocity_map"):
        v_kernel, t_kernel = timed(steady_kernel, params, forces, amplitudes)
        err_kernel, _ = errors(at_grid(v_kernel))
        rows.append(
            row(
                "  same, kernel mean_velocity_grid",
                f"{n_f}x{n_a}",
                t_kernel,
                n_points,
                err_kernel,
                None,
            )
        )

    # 2. Batched time-domain kernel.
    result, t_batch = timed(batched, params, np.repeat(forces, n_a), np.tile(amplitudes, n_f), dt)
    v_batch = result.mean_velocity.reshape(n_f, n_a)
    err_b = errors(at_grid(v_batch))
    rows.append(
        row(
            "batched RK4 kernel, located switching",
            f"{n_f}x{n_a}",
            t_batch,
            n_points,
            *err_b,
            steps=n_points * n_steps,
        )
    )

    # 3. scipy on the random sample, extrapolated.
    sample = slice(len(picks), len(ref_points))
    start = time.perf_counter()
    v_sc = np.array(
        [
            finite_time_mean_velocity(params, f, a, DURATION, rtol=1e-9)
            for f, a in zip(ref_f[sample], ref_a[sample], strict=True)
        ]
    )
    t_sc = (time.perf_counter() - start) / args.scipy_points * n_points
    err_sc = errors(v_sc, sample)
    rows.append(
        row(
            "scipy DOP853 rtol 1e-9, 0.05 s run",
            f"{args.scipy_points} pts",
            t_sc,
            n_points,
            *err_sc,
            note="time extrapolated",
        )
    )
    start = time.perf_counter()
    v_sc_ss = np.array(
        [steady_mean_velocity(params, f, a, rtol=1e-9) for f, a in zip(ref_f, ref_a, strict=True)]
    )
    t_sc_ss = (time.perf_counter() - start) / len(ref_points) * n_points
    err_sc_ss, _ = errors(v_sc_ss)
    rows.append(
        row(
            "scipy DOP853 rtol 1e-9, steady cycle",
            f"{len(ref_points)} pts",
            t_sc_ss,
            n_points,
            err_sc_ss,
            None,
            note="time extrapolated",
        )
    )

    # 4. NumPy RK4, naive stick/slip, on its own grid plus the reference points.
    nf_np, na_np = min(args.numpy_grid[0], n_f), min(args.numpy_grid[1], n_a)
    np_f = np.concatenate([np.repeat(np.linspace(*F_RANGE, nf_np), na_np), ref_f])
    np_a = np.concatenate([np.tile(np.linspace(*A_RANGE, na_np), nf_np), ref_a])
    start = time.perf_counter()
    v_np = numpy_rk4_naive(params, np_f, np_a, dt)
    t_np_run = time.perf_counter() - start
    t_np = t_np_run / np_f.size * n_points
    err_np = errors(v_np[nf_np * na_np :])
    extrapolated = (nf_np, na_np) != (n_f, n_a)
    rows.append(
        row(
            "NumPy RK4, naive once-per-step stick/slip",
            f"{nf_np}x{na_np}+{len(ref_points)}",
            t_np,
            n_points,
            *err_np,
            steps=n_points * n_steps,
            note=f"time extrapolated from {t_np_run:.1f} s" if extrapolated else "",
        )
    )

    # Table.
    slowest = max(r["time"] for r in rows)
    scipy_same = {"steady": t_sc_ss, "time": t_sc}
    print()
    print(
        f"{'method':<43} {'run on':>11} {'time [s]':>10} {'points/s':>9} "
        f"{'steps*traj/s':>12} {'err steady':>10} {'err 0.05 s':>10} "
        f"{'x slowest':>9} {'x scipy':>8}  note"
    )
    for r in rows:
        throughput = f"{r['steps'] / r['time']:.2e}" if r["steps"] else "-"
        kind = "time" if r["err_time"] is not None else "steady"
        ratio_scipy = scipy_same[kind] / r["time"]
        print(
            f"{r['name']:<43} {r['grid']:>11} {r['time']:>10.3g} "
            f"{r['points'] / r['time']:>9.2e} {throughput:>12} {fmt_err(r['err_steady']):>10} "
            f"{fmt_err(r['err_time']):>10} {slowest / r['time']:>9.3g} {ratio_scipy:>8.3g}  "
            f"{r['note']}"
        )
    print()
    print("err steady: max |v - v_ref| / max v_ref, v_ref = steady-cycle mean (rtol 1e-12); the")
    print("  time-domain methods include their start-up transient (a finite-time average).")
    print("err 0.05 s: the same against the reference x(0.05)/0.05: integration error alone.")
    print("x scipy: speed-up against scipy doing the same job (steady cycle for the steady")
    print("  map and the scipy steady row, the 0.05 s run for the time-domain rows).")
    print()
    print(
        f"steady map is {t_sc_ss / t_map:.3g}x faster than solve_ivp steady cycles and "
        f"{t_sc / t_map:.3g}x faster than solve_ivp 0.05 s runs (extrapolated), "
        f"{t_batch / t_map:.3g}x faster than the batched RK4 kernel"
    )
    print(
        f"batched RK4 kernel is {t_sc / t_batch:.3g}x faster than solve_ivp (extrapolated) "
        f"and {t_np / t_batch:.3g}x faster than NumPy RK4"
        f"{' (extrapolated)' if extrapolated else ''}"
    )
    steps_rate = n_points * n_steps / t_batch
    flagged = result.n_flagged.sum() / (n_points * n_steps)
    print(
        f"batched kernel: {result.n_switches.sum()} switches, "
        f"{flagged:.2%} of trajectory-steps redone by the scalar located switching"
    )
    moving = v_map > 0.0
    rel = np.abs(v_batch[moving] - v_map[moving]) / v_map[moving]
    print(
        f"batched x(0.05)/0.05 vs the steady map on the whole grid: max |diff| / max v = "
        f"{np.max(np.abs(v_batch - v_map)) / np.max(v_map):.2g}, median relative diff "
        f"{np.median(rel):.2g} where v > 0 (the start-up transient of a 0.05 s average)"
    )
    # The vector pass alone: trajectories that never switch (stuck, A < y0/2).
    quiet_f = np.full(4096, 0.01)
    quiet_a = np.linspace(0.0, 0.5 * params.static_deflection, 4096)
    quiet, t_quiet = timed(batched, params, quiet_f, quiet_a, dt)
    assert quiet.n_switches.sum() == 0 and quiet.n_flagged.sum() == 0
    quiet_rate = quiet_f.size * n_steps / t_quiet
    t_switching = t_batch - n_points * n_steps / quiet_rate
    print(
        f"batched kernel without any switch (4096 stuck trajectories): "
        f"{quiet_rate:.3g} steps*traj/s; on the map job the located switching takes "
        f"~{t_switching:.2g} s of {t_batch:.3g} s "
        f"(~{2 * t_switching / max(result.n_flagged.sum(), 1) * 1e6:.2g} us per redone step "
        f"and thread)"
    )
    print()
    scale_note = "" if (n_f, n_a) == (256, 256) else f" (grid {n_f}x{n_a}, target is for 256x256)"
    ok = "meets" if t_map < TARGET_STEADY_TIME else "MISSES"
    print(f"target steady map < {TARGET_STEADY_TIME} s: {t_map:.3g} s, {ok}{scale_note}")
    ok = "meets" if err_map <= TARGET_STEADY_ERROR else "MISSES"
    print(f"target steady map error <= {TARGET_STEADY_ERROR:g}: {err_map:.2g}, {ok}")
    ok = "meets" if steps_rate >= TARGET_THROUGHPUT else "MISSES"
    print(f"target batched kernel >= {TARGET_THROUGHPUT:.0e} steps*traj/s: {steps_rate:.3g}, {ok}")
    if not math.isfinite(scale):
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
