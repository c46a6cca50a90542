"""The shared-normal lanes on a GPU (integrators/shared_lanes_cuda.py).

Without a GPU (CI) the kernel runs under numba's CUDA simulator in a subprocess: Python
arithmetic without FMA, so it must give the CPU kernel's bits. That catches what the
port can get wrong (a lane reading another set-up's tape, a block of tapes lost or
replayed, a lane state not written back, the start-mode rule, the count columns).
Where a GPU is found the same lanes run on it and must agree with the CPU kernel to
rounding (the GPU contracts multiply-adds).
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from cli_inprocess import run as run_cli

import microslip as ms
from microslip.integrators import shared_lanes_cuda as slc
from microslip.integrators.normal_tape import normal_coefficients
from microslip.integrators.shared_lanes import run_shared

PARAMS = ms.Parameters()
DT = PARAMS.natural_period / 200


def mixed_lanes(n_steps: int):
    """Set-ups of every kind in one run (free with and without flights, forced with
    damping), lanes shuffled across them, with zero force, F > μ m g, μ_s > μ_k and a
    moving start. Returns the arguments of run_shared."""
    from microslip.simulation import initial_state_from_amplitude

    y0 = PARAMS.static_deflection
    free = normal_coefficients(ms.Model(PARAMS).pack(0.0))
    forced_model = ms.Model(
        PARAMS, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(3.0, 1400.0)
    )
    forced = normal_coefficients(forced_model.pack(0.0))
    coeffs = np.array([free, free, free, forced])
    normal0 = np.array(
        [initial_state_from_amplitude(PARAMS, a)[:2] for a in (0.0, 0.6 * y0, 2.5 * y0)]
        + [[y0, 0.0]]
    )
    mg = PARAMS.mass * PARAMS.g
    forces = np.array([0.0, 0.2, 0.5, 0.7, 0.95, 1.3]) * PARAMS.mu * mg
    groups = np.repeat(np.arange(4), forces.size)
    lane_forces = np.tile(forces, 4)
    mu_s = np.full(lane_forces.size, PARAMS.mu)
    mu_k = mu_s.copy()
    mu_k[1::3] *= 0.8  # static above kinetic on a third of the lanes
    v0 = np.zeros(lane_forces.size)
    v0[5::7] = 1e-5  # a few lanes start sliding
    order = np.random.default_rng(3).permutation(lane_forces.size)
    return (
        coeffs, normal0, groups[order], lane_forces[order], mu_s[order], mu_k[order],
        n_steps * DT, DT, None, v0[order],
    )  # fmt: skip


def spring_lanes(n_steps: int):
    """Spring set-ups (free with and without flights, forced with damping, a stiff and
    a soft spring), lanes by set-up. Returns the arguments of run_spring_lanes."""
    args = mixed_lanes(n_steps)
    coeffs, normal0, n_groups = args[0], args[1], args[0].shape[0]
    stiffness = PARAMS.contact_stiffness * np.array([1.0, 0.3, 2.0, 1.0])
    forces = np.array([0.0, 0.2, 0.5, 0.7, 0.95, 1.3]) * PARAMS.mu * PARAMS.mass * PARAMS.g
    lane_forces = np.tile(forces, n_groups)
    mu_s = np.full(lane_forces.size, PARAMS.mu)
    mu_k = mu_s.copy()
    mu_k[1::3] *= 0.8
    groups = np.repeat(np.arange(n_groups), forces.size)
    return coeffs, normal0, stiffness, groups, lane_forces, mu_s, mu_k, n_steps * DT, DT


def mindlin_lanes(n_steps: int):
    """The set-ups of :func:`spring_lanes` on Mindlin springs (λ = 1, 0.3, 1.7, 0.8235).
    Returns the arguments of run_mindlin_lanes. (λ = 2 on the set-up that starts in
    flight would put the lanes with F = μ m g / λ on an exact tie of the touchdown's
    stick and slip, where the CPU kernel's stick search stalls: docs/theory/numerics.md.)"""
    args = list(spring_lanes(n_steps))
    args[2] = np.array([1.0, 0.3, 1.7, 0.8235])
    return tuple(args)


def hertz_lanes(n_steps: int):
    """Mindlin set-ups at m2 = 1.5 (a Hertz contact, rough at touchdown) that stay in
    contact (A = 0.5 y0), leave it (A = 2.5 y0) or are forced into flights, and one at
    m2 = 2 in flight (which the lanes run through), with dt = T0/200 of m2 = 1.5.
    Returns (arguments of run_mindlin_lanes, the periods of the free set-ups, the
    set-ups handed back)."""
    from microslip.simulation import initial_state_from_amplitude

    hertz, square = ms.Parameters(m2=1.5), ms.Parameters(m2=2.0)
    forced = ms.Model(hertz, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(8.0, 16e3))
    setups = [
        (ms.Model(hertz), 0.5 * hertz.static_deflection),
        (ms.Model(hertz), 2.5 * hertz.static_deflection),
        (forced, None),
        (ms.Model(square), 2.5 * square.static_deflection),
    ]
    coeffs = np.array([normal_coefficients(model.pack(0.0)) for model, _ in setups])
    normal0 = np.array(
        [
            initial_state_from_amplitude(model.params, a)[:2]
            if a is not None
            else [model.params.static_deflection, 0.0]
            for model, a in setups
        ]
    )
    periods = [ms.free_period(model.params, a) if a else 0.0 for model, a in setups]
    mg = hertz.mass * hertz.g
    forces = np.array([0.0, 0.3, 0.7, 0.95, 1.3]) * hertz.mu * mg
    groups = np.repeat(np.arange(4), forces.size)
    lane_forces = np.tile(forces, 4)
    mu = np.full(lane_forces.size, hertz.mu)
    ratio = np.array([0.8, 0.8, 0.5, 0.8])
    dt = hertz.natural_period / 200
    args = (coeffs, normal0, ratio, groups, lane_forces, mu, mu.copy(), n_steps * dt, dt)
    return args, periods, np.array([1, 2])


def handed_back(run, *args, **options):
    """(set-ups handed back, results complete for the others) of a Mindlin-lane run that
    hands some back."""
    from microslip.integrators.shared_lanes import LaneStalledError

    with pytest.raises(LaneStalledError) as error:
        run(*args, **options)
    return error.value.setups, error.value.partial


SIMULATED = textwrap.dedent(
    """
    import numpy as np
    import pytest
    from test_cuda_lanes import mixed_lanes
    from microslip.integrators.shared_lanes import run_shared
    from microslip.integrators.shared_lanes_cuda import cuda_unavailable, run_shared_cuda

    assert cuda_unavailable() is None
    args = mixed_lanes(240)
    cpu = run_shared(*args)
    gpu = run_shared_cuda(*args, tape_rows=24)  # ten blocks of tapes
    for name, a, b in zip(("x", "v", "mode", "switches", "flagged"), cpu, gpu):
        assert np.array_equal(a, b), (name, a, b)
    moving = np.abs(cpu[0]) > 0
    assert cpu[3].sum() > 15 and moving.sum() > 10, (cpu[3].sum(), moving.sum())
    print("same bits", int(cpu[3].sum()), "switches")
    # The next run of that shape reuses the page-locked blocks, stale rows and all: a
    # run on other set-ups (the normal motions reversed) still gets the CPU's bits.
    from microslip.integrators import shared_lanes_cuda as slc
    assert len(slc._PINNED) == 1
    kept = next(iter(slc._PINNED.values()))[0][0]  # the first page-locked block
    other = (args[0][::-1].copy(), args[1][::-1].copy(), *args[2:])
    cpu = run_shared(*other)
    gpu = run_shared_cuda(*other, tape_rows=24)
    assert next(iter(slc._PINNED.values()))[0][0] is kept
    for name, a, b in zip(("x", "v", "mode", "switches", "flagged"), cpu, gpu):
        assert np.array_equal(a, b), ("reused blocks", name, a, b)
    # Free set-ups on a repeated tape (~4 periods): lanes that repeat a period park and
    # take the rest at once on both, with the same bits (shared_lanes._run_cycle).
    import microslip as ms
    from test_cuda_lanes import PARAMS
    amplitudes = PARAMS.static_deflection - args[1][:, 0]
    periods = [ms.free_period(PARAMS, a) if a > 0.0 else 0.0 for a in amplitudes[:3]] + [0.0]
    args = mixed_lanes(850)
    cpu = run_shared(*args, periods=periods)
    gpu = run_shared_cuda(*args, tape_rows=200, periods=periods)  # blocks cut periods
    for name, a, b in zip(("x", "v", "mode", "switches", "flagged"), cpu, gpu):
        assert np.array_equal(a, b), ("repeated", name, a, b)
    assert not np.array_equal(cpu[0], run_shared(*args, periods=periods, park=False)[0])

    from test_cuda_lanes import mindlin_lanes, spring_lanes
    from microslip.integrators.mindlin_lanes import run_mindlin_lanes
    from microslip.integrators.mindlin_lanes_cuda import run_mindlin_lanes_cuda
    from microslip.integrators.spring_lanes import run_spring_lanes
    from microslip.integrators.spring_lanes_cuda import run_spring_lanes_cuda

    for kernel, lanes, on_cpu, on_gpu in (
        ("spring", spring_lanes, run_spring_lanes, run_spring_lanes_cuda),
        ("mindlin", mindlin_lanes, run_mindlin_lanes, run_mindlin_lanes_cuda),
    ):
        args = lanes(240)
        cpu = on_cpu(*args)
        gpu = on_gpu(*args, tape_rows=24)
        for name, a, b in zip(("x", "v", "f", "mode", "switches", "flagged"), cpu, gpu):
            assert np.array_equal(a, b), (kernel, name, a, b)
        assert cpu[4].sum() > 15 and (cpu[3] == 2.0).any() and (np.abs(cpu[0]) > 0).sum() > 10
        print(kernel, "same bits", int(cpu[4].sum()), "switches")
    # A step too coarse for the Mindlin tangential oscillation is refused as on the CPU.
    coarse = list(args)
    coarse[-1] *= 100.0
    with pytest.raises(ValueError, match="too coarse for the Mindlin"):
        run_mindlin_lanes_cuda(*coarse)

    # Hertz set-ups (m2 = 1.5): those that leave contact are handed back, as on the CPU
    # without windows, with the other set-ups' results, on a stepped and on a repeated
    # tape.
    from test_cuda_lanes import handed_back, hertz_lanes
    args, periods, back = hertz_lanes(240)
    for options in (dict(), dict(periods=periods)):
        cpu_back, cpu = handed_back(run_mindlin_lanes, *args, windowed=False, **options)
        gpu_back, gpu = handed_back(run_mindlin_lanes_cuda, *args, tape_rows=24, **options)
        assert np.array_equal(cpu_back, back) and np.array_equal(gpu_back, back), gpu_back
        kept = ~np.isin(args[3], back)
        for name, a, b in zip(("x", "v", "f", "mode", "switches", "flagged"), cpu, gpu):
            assert np.array_equal(a[kept], b[kept]), ("hertz", options, name, a, b)
        assert cpu[4][kept].sum() >= 4 and (cpu[3][kept] == 2.0).any(), cpu[4]
    print("hertz hand-back same bits")

    # A touchdown tie (λ = 1, F = μ m g from rest in flight: tests/unit/
    # test_sweep_compliant_time.py): the lane that stalls is handed back alone on both
    # (the CPU without windows), NaN, and the other lane of its set-up keeps the CPU's
    # bits.
    import microslip as ms
    from microslip.integrators.normal_tape import normal_coefficients
    from microslip.simulation import initial_state_from_amplitude
    from microslip.validation import DEFAULT_RK4_STEPS_PER_PERIOD
    params = ms.Parameters()
    tie = ms.Model(params, tangential=ms.MindlinSpring(1.0))
    mg = params.mass * params.g
    dt = ms.budget.shortest_period(tie) / DEFAULT_RK4_STEPS_PER_PERIOD
    args = (
        normal_coefficients(tie.pack(0.0))[None],
        np.array([initial_state_from_amplitude(params, 3.0 * params.static_deflection)[:2]]),
        [1.0], [0, 0], [0.5 * params.mu * mg, params.mu * mg], params.mu, params.mu,
        200 * dt, dt,
    )
    from functools import partial as bound
    from microslip.integrators.shared_lanes import LaneStalledError
    partial = []
    for run in (bound(run_mindlin_lanes, windowed=False), run_mindlin_lanes_cuda):
        with pytest.raises(LaneStalledError) as stalled:
            run(*args)
        assert list(stalled.value.setups) == [] and list(stalled.value.lanes) == [1], run
        partial.append(stalled.value.partial)
    for name, a, b in zip(("x", "v", "f"), partial[0], partial[1]):
        assert np.isnan(a[1]) and np.isnan(b[1]) and a[0] == b[0], ("tie", name, a, b)
    print("tie hand-back")

    # The public path: velocity_map / sweep with backend="cuda", free and forced.
    import tempfile
    from pathlib import Path
    import microslip as ms
    from microslip.sweeps.store import StoreMismatchError

    options = dict(method="time", duration=0.0005)
    free = dict(forces=[0.3, 0.6, 0.9], amplitudes=[1e-7, 4e-7], **options)
    on_cpu = ms.velocity_map(**free)
    on_gpu = ms.velocity_map(**free, backend="cuda")
    assert np.array_equal(on_cpu.values, on_gpu.values) and np.abs(on_cpu.values).max() > 0
    # Over two periods of a free vibration the tapes repeat one period: the CPU cores
    # serve the GPU the same rows (integrators/periodic_tape.py); the rest at A = 0
    # repeats with T0.
    periodic = dict(forces=[0.3, 1.2], amplitudes=[0.0, 1e-7], method="time", duration=0.0016)
    assert periodic["duration"] > 2 * ms.free_period(ms.Parameters(), 1e-7)
    on_cpu = ms.velocity_map(**periodic)
    on_gpu = ms.velocity_map(**periodic, backend="cuda")
    assert np.array_equal(on_cpu.values, on_gpu.values) and np.abs(on_cpu.values).max() > 0
    forced = ms.Model(damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(3.0, 1400.0))
    axes = {"excitation.amplitude": [1.0, 3.0]}
    on_cpu = ms.sweep(forced, axes, force=[0.3, 0.9], **options)
    on_gpu = ms.sweep(forced, axes, force=[0.3, 0.9], **options, backend="cuda")
    assert np.array_equal(on_cpu.values, on_gpu.values)
    spring = ms.Model(tangential=ms.TangentialSpring(ms.Parameters().contact_stiffness))
    on_cpu = ms.sweep(spring, None, force=[0.3, 0.9], amplitude=[1e-7, 4e-7], **options)
    on_gpu = ms.sweep(spring, None, force=[0.3, 0.9], amplitude=[1e-7, 4e-7], **options,
                      backend="cuda")
    assert np.array_equal(on_cpu.values, on_gpu.values) and np.abs(on_cpu.values).max() > 0
    mindlin = ms.Model(tangential=ms.MindlinSpring(0.8235))
    on_cpu = ms.sweep(mindlin, None, force=[0.3, 0.9], amplitude=[1e-7, 4e-7], **options)
    on_gpu = ms.sweep(mindlin, None, force=[0.3, 0.9], amplitude=[1e-7, 4e-7], **options,
                      backend="cuda")
    assert np.array_equal(on_cpu.values, on_gpu.values) and np.abs(on_cpu.values).max() > 0
    # StaticKinetic friction: each lane sticks up to μ_s N and slides against μ_k N,
    # through flights (A = 4e-7 m > y0) and a runaway between μ_k m g and μ_s m g.
    for tangential in (None, spring.tangential, mindlin.tangential):
        static = ms.Model(tangential=tangential, friction=ms.StaticKinetic(0.15, 0.1))
        grid = dict(force=[0.3, 1.2], amplitude=[0.2e-7, 4e-7], **options)
        on_cpu = ms.sweep(static, None, **grid)
        on_gpu = ms.sweep(static, None, **grid, backend="cuda")
        assert np.array_equal(on_cpu.values, on_gpu.values) and np.abs(on_cpu.values).max() > 0
    # A Hertz contact: the set-up in flight runs on the CPU lanes on both (the GPU lanes
    # hand it back to them).
    hertz = mindlin.replace(m2=1.5)
    y0 = hertz.params.static_deflection
    on_cpu = ms.sweep(hertz, None, force=[0.3, 0.9], amplitude=[0.5 * y0, 2.5 * y0], **options)
    on_gpu = ms.sweep(hertz, None, force=[0.3, 0.9], amplitude=[0.5 * y0, 2.5 * y0], **options,
                      backend="cuda")
    assert np.array_equal(on_cpu.values, on_gpu.values) and np.abs(on_cpu.values).max() > 0
    # A store computed on one backend is not resumed on the other (bits would mix).
    with tempfile.TemporaryDirectory() as tmp:
        store = Path(tmp) / "map.zarr"
        ms.velocity_map(**free, store=store, backend="cuda")
        with pytest.raises(StoreMismatchError, match="differs in: backend"):
            ms.velocity_map(**free, store=store)
    print("public path same bits")
    """
)


def test_simulated_gpu_kernel_gives_the_cpu_kernels_bits():
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1")
    env["PYTHONPATH"] = os.pathsep.join(
        [os.path.dirname(__file__), *filter(None, [env.get("PYTHONPATH")])]
    )
    run = subprocess.run(
        [sys.executable, "-c", SIMULATED], env=env, capture_output=True, text=True, timeout=500
    )
    assert run.returncode == 0, run.stderr[-3000:]
    assert "public path same bits" in run.stdout


def test_without_a_gpu_the_cuda_path_refuses_in_one_line(monkeypatch):
    monkeypatch.setattr(slc, "cuda", None)
    monkeypatch.setattr(slc, "_IMPORT_ERROR", "no module named 'numba.cuda'", raising=False)
    reason = slc.cuda_unavailable()
    assert reason is not None and "\n" not in reason and "numba.cuda" in reason
    with pytest.raises(RuntimeError, match="CUDA target cannot be imported"):
        slc.run_shared_cuda(*mixed_lanes(4))


@pytest.mark.skipif(slc.cuda_unavailable() is not None, reason="needs a CUDA GPU")
@pytest.mark.parametrize("repeated", [False, True])
def test_gpu_lanes_agree_with_the_cpu_kernel(repeated):
    args = mixed_lanes(4000)
    periods = None
    if repeated:  # the free set-ups' tapes are one period, repeated (~20 periods)
        amplitudes = PARAMS.static_deflection - args[1][:3, 0]
        periods = [ms.free_period(PARAMS, a) if a > 0.0 else 0.0 for a in amplitudes] + [0.0]
    cpu = run_shared(*args, periods=periods)
    gpu = slc.run_shared_cuda(*args, tape_rows=512, periods=periods)  # eight blocks of tapes
    scale = np.abs(cpu[0]).max()
    assert scale > 0
    assert np.abs(gpu[0] - cpu[0]).max() <= 1e-9 * scale
    assert np.abs(gpu[1] - cpu[1]).max() <= 1e-9 * np.abs(cpu[1]).max()
    assert np.array_equal(gpu[2], cpu[2])


@pytest.mark.skipif(slc.cuda_unavailable() is not None, reason="needs a CUDA GPU")
@pytest.mark.parametrize("kernel", ["spring", "mindlin"])
def test_gpu_compliant_lanes_agree_with_the_cpu_kernel(kernel):
    from microslip.integrators.mindlin_lanes import run_mindlin_lanes
    from microslip.integrators.mindlin_lanes_cuda import run_mindlin_lanes_cuda
    from microslip.integrators.spring_lanes import run_spring_lanes
    from microslip.integrators.spring_lanes_cuda import run_spring_lanes_cuda

    lanes, on_cpu, on_gpu = {
        "spring": (spring_lanes, run_spring_lanes, run_spring_lanes_cuda),
        "mindlin": (mindlin_lanes, run_mindlin_lanes, run_mindlin_lanes_cuda),
    }[kernel]
    args = lanes(4000)
    cpu = on_cpu(*args)
    gpu = on_gpu(*args, tape_rows=512)
    for k in range(3):  # x, ẋ, f
        assert np.abs(gpu[k] - cpu[k]).max() <= 1e-9 * np.abs(cpu[k]).max()
    assert np.array_equal(gpu[3], cpu[3])


@pytest.mark.skipif(slc.cuda_unavailable() is not None, reason="needs a CUDA GPU")
@pytest.mark.parametrize("periodic", [False, True])
def test_gpu_hands_back_the_hertz_setups_that_leave_contact(periodic):
    from microslip.integrators.mindlin_lanes import run_mindlin_lanes
    from microslip.integrators.mindlin_lanes_cuda import run_mindlin_lanes_cuda

    args, periods, back = hertz_lanes(4000)
    options = dict(periods=periods) if periodic else {}
    cpu_back, cpu = handed_back(run_mindlin_lanes, *args, windowed=False, **options)
    gpu_back, gpu = handed_back(run_mindlin_lanes_cuda, *args, tape_rows=512, **options)
    assert np.array_equal(cpu_back, back) and np.array_equal(gpu_back, back)
    kept = ~np.isin(args[3], back)
    for k in range(3):  # x, ẋ, f
        assert np.abs(gpu[k][kept] - cpu[k][kept]).max() <= 1e-9 * np.abs(cpu[k][kept]).max()
    assert np.array_equal(gpu[3][kept], cpu[3][kept])


@pytest.mark.skipif(slc.cuda_unavailable() is not None, reason="needs a CUDA GPU")
def test_gpu_hertz_mindlin_map_agrees_with_the_cpu_one():
    hertz = ms.Model(ms.Parameters(m2=1.5), tangential=ms.MindlinSpring(0.8))
    y0 = hertz.params.static_deflection
    options = dict(force=np.linspace(0.05, 0.95, 32), amplitude=np.linspace(0.0, 2.0 * y0, 8),
                   method="time", duration=0.005)  # fmt: skip
    on_cpu = ms.sweep(hertz, None, **options).values
    on_gpu = ms.sweep(hertz, None, **options, backend="cuda").values
    assert np.abs(on_gpu - on_cpu).max() <= 1e-9 * np.abs(on_cpu).max()


@pytest.mark.skipif(slc.cuda_unavailable() is not None, reason="needs a CUDA GPU")
def test_gpu_velocity_map_agrees_with_the_cpu_one():
    forces = np.linspace(0.05, 0.95, 64)
    amplitudes = np.linspace(0.0, 3e-7, 16)
    options = dict(forces=forces, amplitudes=amplitudes, method="time", duration=0.01)
    on_cpu = ms.velocity_map(**options).values
    on_gpu = ms.velocity_map(**options, backend="cuda").values
    assert np.abs(on_gpu - on_cpu).max() <= 1e-9 * np.abs(on_cpu).max()


NO_GPU = slc.cuda_unavailable()
TIME = dict(forces=[0.3, 0.6], amplitudes=[1e-7], method="time", duration=0.001)


@pytest.mark.parametrize(
    ("model", "options", "words"),
    [
        (None, dict(TIME, backend="gpu"), ["backend must be one of cpu, cuda", "'gpu'"]),
        (None, dict(TIME, method="steady", duration=None, backend="cuda"),
         ["backend='cuda' runs method='time' only"]),
        (ms.Model(drive=ms.PrescribedVelocity(1e-4)), dict(backend="cuda"),
         ["does not apply to an effective-friction sweep"]),
    ],
)  # fmt: skip
def test_a_sweep_the_gpu_cannot_run_is_refused_in_one_line(model, options, words):
    if isinstance(model, ms.Model) and model.is_kinematic:
        call = lambda: ms.sweep(model, {"drive.velocity": [1e-4]}, amplitude=1e-7, **options)  # noqa: E731
    else:
        call = lambda: ms.velocity_map(model, **options)  # noqa: E731
    with pytest.raises(ValueError) as error:
        call()
    message = str(error.value)
    assert "\n" not in message
    for word in words:
        assert word in message


@pytest.mark.skipif(NO_GPU is None, reason="a GPU is present")
def test_without_a_gpu_backend_cuda_says_why(capsys, tmp_path, monkeypatch):
    with pytest.raises(ValueError, match="backend='cuda': no CUDA GPU"):
        ms.velocity_map(**TIME, backend="cuda")
    monkeypatch.chdir(tmp_path)
    status, out, err = run_cli(
        capsys, "map", "--method", "time", "--backend", "cuda", "--force", "0.3",
        "--amplitude", "1e-7", "--duration", "0.001", "--out", "m.nc",
    )  # fmt: skip
    assert status == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and "backend='cuda'" in err
    assert list(tmp_path.iterdir()) == []
