"""Computing one chunk of a sweep: a pure function of (spec, chunk key), safe to ship to Dask."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from microslip.analysis.steady_state import ORBIT_STEPS, mean_velocity_grid
from microslip.model.coefficients import FORCE, MU, MU_STATIC, pack
from microslip.simulation import DEFAULT_RK4_STEPS_PER_PERIOD, initial_state_from_amplitude
from microslip.sweeps.kernel_choice import repeats_from_rest, time_kernel
from microslip.sweeps.spec import ChunkKey, SweepSpec

# A caller's progress: called with the fraction [1] of the work of a compute call just
# done (a time run's set-ups as they end, from the threads that ran them).
Progress = Callable[[float], None]


def compute_chunk(spec: SweepSpec, key: ChunkKey, progress: Progress | None = None) -> np.ndarray:
    """Mean velocity [m/s] on the chunk's (force, amplitude) block.

    "steady": the exact long-time mean (inf where F > μ m g). "time": x(T)/T after a
    run of duration T from the paper's initial state (rest at the top), by a
    shared-normal kernel (:mod:`microslip.integrators.shared_lanes`, or
    :mod:`microslip.integrators.spring_lanes` for a TangentialSpring,
    :mod:`microslip.integrators.mindlin_lanes` for a MindlinSpring): one RK4 normal
    motion per amplitude, shared by every force.
    Each point is computed independently of the chunking, so results are bit-identical
    however the sweep is split or distributed. ``progress``, where given, hears of a time
    run's set-ups as they end on the CPU (:data:`Progress`).
    """
    if spec.forced:
        return forced_chunk(spec, key, progress)
    if spec.base.damping is not None and spec.method == "steady":
        return damped_free_chunk(spec, key)
    params = spec.params_at(key)
    forces = np.asarray(spec.forces)
    amplitudes = np.asarray(spec.amplitudes[spec.amplitude_slice(key)])
    if spec.method == "steady":
        out = np.empty((forces.size, amplitudes.size))
        if not mean_velocity_grid(forces, amplitudes, pack(params, 0.0), ORBIT_STEPS, out):
            raise RuntimeError(f"orbit table overflow in chunk {key}")
        return out
    dt = _time_step(spec, spec.model_at(key))
    normal0 = np.array([initial_state_from_amplitude(params, a)[:2] for a in amplitudes])
    x = _shared_run(
        [spec.model_at(key)] * amplitudes.size, normal0, forces, spec.duration, dt, spec.backend,
        _share(progress, amplitudes.size),
    )  # fmt: skip
    return (x / spec.duration).T


def _share(progress: Progress | None, parts: int) -> Callable[[float], None] | None:
    """``progress`` of a whole of ``parts`` equal parts, told of parts done (set-ups as a
    kernel's ``on_done`` counts them, or one chunk's fraction): None stays None."""
    if progress is None:
        return None
    return lambda done: progress(done / parts)


def shares_runs(spec: SweepSpec) -> bool:
    """True when :func:`compute_chunks` computes several chunks in one run: a forced
    model's time chunks on a shared-normal kernel, one normal set-up each."""
    return spec.forced and spec.method == "time"


def compute_chunks(
    spec: SweepSpec, keys: list[ChunkKey], progress: Progress | None = None
) -> list[np.ndarray]:
    """:func:`compute_chunk` of each key, the same bits; a forced model's time chunks go
    through one shared-normal run, so that their normal set-ups (one per chunk) spread
    over the cores (a set-up's lanes depend on nothing else in the run). ``progress``
    hears of the fraction of all the keys' work done."""
    if not shares_runs(spec):
        return [compute_chunk(spec, key, _share(progress, len(keys))) for key in keys]
    return _forced_time_chunks(spec, keys, progress)


def _forced_time_chunks(
    spec: SweepSpec, keys: list[ChunkKey], progress: Progress | None = None
) -> list[np.ndarray]:
    """A forced model's time chunks through one shared-normal run (:func:`compute_chunks`);
    each chunk's model runs on a shared-normal kernel."""
    models = [spec.model_at(key) for key in keys]
    steps = [_time_step(spec, model) for model in models]
    blocks: list[np.ndarray | None] = [None] * len(keys)
    for dt in dict.fromkeys(steps):  # one run per step size, in first-seen order
        picked = [k for k, step in enumerate(steps) if step == dt]
        normal0 = np.array([[models[k].params.static_deflection, 0.0] for k in picked])
        x = _shared_run(
            [models[k] for k in picked], normal0, spec.forces, spec.duration, dt, spec.backend,
            _share(progress, len(keys)),
        )  # fmt: skip
        for row, k in enumerate(picked):
            blocks[k] = (x[row] / spec.duration)[:, None]
    return blocks


def _time_step(spec: SweepSpec, model) -> float:
    """The RK4 step [s] of a time run: ``spec.dt`` or 1/200 of the period the step must
    resolve (:meth:`SweepSpec.step_period`)."""
    if spec.dt is not None:
        return spec.dt
    return SweepSpec.step_period(model) / DEFAULT_RK4_STEPS_PER_PERIOD


# -- models past the paper's (docs/design.md) ---------------------------------------------
def damped_free_chunk(spec: SweepSpec, key: ChunkKey) -> np.ndarray:
    """Damped free vibration: it decays to rest, N -> m g; 0 below μ m g, inf above."""
    params = spec.params_at(key)
    forces = np.asarray(spec.forces)
    amplitudes = np.asarray(spec.amplitudes[spec.amplitude_slice(key)])
    limit = params.static_friction_force
    if np.any(forces == limit) and np.any(amplitudes > 0.0):
        raise ValueError(
            f"force={limit!r} N equals mu m g on a damped free vibration: the long-time speed "
            "depends on the transient; use method='time'"
        )
    out = np.where(forces > limit, np.inf, 0.0)
    return np.repeat(out[:, None], amplitudes.size, axis=1)


def forced_chunk(spec: SweepSpec, key: ChunkKey, progress: Progress | None = None) -> np.ndarray:
    """A forced model's chunk: every force on one parameter set, shape (forces, 1).

    "steady": the reflected process over one period of the periodic orbit reached from
    rest, shared by every force (a time average where that response is not period-1,
    with a ``RuntimeWarning``). "time": x(T)/T from rest at y0 by the shared-normal
    kernel (:func:`compute_chunks`).
    """
    import warnings

    from microslip.analysis.forced_sliding import mean_velocities
    from microslip.analysis.periodic import NotPeriodOneError
    from microslip.analysis.sliding_tables import model_sliding_table
    from microslip.analysis.steady_state import FALLBACK_PERIODS

    model = spec.model_at(key)
    forces = np.asarray(spec.forces, dtype=float)
    if spec.method == "time":
        return _forced_time_chunks(spec, [key], progress)[0]
    try:
        table = model_sliding_table(model)
    except NotPeriodOneError as error:
        warnings.warn(
            f"{error}; the sweep point uses the time average of an RK4 run over "
            f"{FALLBACK_PERIODS} excitation periods (second half)",
            RuntimeWarning,
            stacklevel=2,
        )
        half = 0.5 * FALLBACK_PERIODS * model.excitation.period
        dt = _time_step(spec, model)
        states = _batched_run([model], forces, half, dt).states
        end = _batched_run([model], forces, half, dt, states0=states).states
        return ((end[:, 2] - states[:, 2]) / half)[:, None]
    return mean_velocities(table, model.params.mu, forces)[:, None]


def _normal_periods(models, normal0) -> np.ndarray:
    """Period [s] of each set-up's normal motion where it is periodic from t = 0, else 0:
    a conservative free vibration (no damping, no excitation) started at rest above its
    equilibrium, T(A) of :func:`~microslip.analysis.free_vibration.free_period`. The
    lanes then run on one period's tape, repeated
    (:mod:`~microslip.integrators.periodic_tape`)."""
    from microslip.analysis.free_vibration import free_period

    periods = np.zeros(len(models))
    for g, model in enumerate(models):
        amplitude = model.params.static_deflection - normal0[g, 0]
        if normal0[g, 1] == 0.0 and repeats_from_rest(model, amplitude):
            periods[g] = free_period(model.params, amplitude)
    return periods


def _shared_run(models, normal0, forces, duration, dt, backend="cpu", on_done=None) -> np.ndarray:
    """x(duration) [m], shape (set-ups, forces), from rest on each normal set-up (one
    model per row of ``normal0``: y [m], ẏ [m/s] at t = 0) under every constant force
    [N], on the shared-normal kernel of the models' tangential contact (all rigid, all
    springs of constant stiffness or all Mindlin springs; a relaxed spring at t = 0);
    ``backend`` "cuda" runs the lanes on a GPU
    (:mod:`~microslip.integrators.shared_lanes_cuda`,
    :mod:`~microslip.integrators.spring_lanes_cuda`,
    :mod:`~microslip.integrators.mindlin_lanes_cuda`); ``on_done`` as for
    :func:`~microslip.integrators.shared_lanes.run_shared` (the CPU kernels only)."""
    from microslip.integrators.normal_tape import normal_coefficients
    from microslip.integrators.shared_lanes import run_shared
    from microslip.integrators.spring_lanes import run_spring_lanes

    forces = np.asarray(forces, dtype=float)
    n_setups = normal0.shape[0]
    periods = _normal_periods(models, normal0)
    packed = {id(model): normal_coefficients(model.pack(0.0)) for model in models}
    coeffs = np.array([packed[id(model)] for model in models])
    if time_kernel(models[0]) == "mindlin":
        x = _mindlin_run(models, coeffs, normal0, forces, duration, dt, periods, backend,
                         on_done)  # fmt: skip
        return x.reshape(n_setups, forces.size)
    groups, lane_forces, mu_s, mu_k = _lane_arrays(models, forces)
    if models[0].is_compliant:
        stiffness = [model.tangential.stiffness for model in models]
        if backend == "cuda":
            from microslip.integrators.spring_lanes_cuda import run_spring_lanes_cuda

            x = run_spring_lanes_cuda(coeffs, normal0, stiffness, groups, lane_forces, mu_s,
                                      mu_k, duration, dt, periods=periods)[0]  # fmt: skip
        else:
            x = run_spring_lanes(coeffs, normal0, stiffness, groups, lane_forces, mu_s, mu_k,
                                 duration, dt, periods=periods, on_done=on_done)[0]  # fmt: skip
    elif backend == "cuda":
        from microslip.integrators.shared_lanes_cuda import run_shared_cuda

        x = run_shared_cuda(coeffs, normal0, groups, lane_forces, mu_s, mu_k, duration, dt,
                            periods=periods)[0]  # fmt: skip
    else:
        x = run_shared(coeffs, normal0, groups, lane_forces, mu_s, mu_k, duration, dt,
                       periods=periods, on_done=on_done)[0]  # fmt: skip
    return x.reshape(n_setups, forces.size)


def _lane_arrays(models, forces):
    """(set-up, force [N], μ_s [-], μ_k [-]) of every lane of :func:`_shared_run`: each
    model's set-up under every force, set-up-major. The coefficients are those the
    model's friction law packs (Coulomb: μ for both; StaticKinetic: its own)."""
    groups = np.repeat(np.arange(len(models)), forces.size)
    packed = np.array([model.pack(0.0)[[MU_STATIC, MU]] for model in models])
    mu_static = np.repeat(packed[:, 0], forces.size)
    mu_kinetic = np.repeat(packed[:, 1], forces.size)
    return groups, np.tile(forces, len(models)), mu_static, mu_kinetic


def _mindlin_run(models, coeffs, normal0, forces, duration, dt, periods, backend, on_done=None):
    """x(duration) [m] per lane (set-up-major) of the Mindlin lanes of :func:`_shared_run`.

    A set-up the lanes hand back runs on the batched RK4 kernel instead, one trajectory
    per force (``simulate(method="rk4")`` bit for bit); the other set-ups keep their
    lanes' results (the CPU and GPU lanes both hand them on as the error's ``partial``):
    each set-up's result still depends on nothing else in the run. The
    lanes hand back a set-up where a lane stalls (an exact tie of stick and slip at a
    touchdown) and one that leaves contact at a contact exponent outside
    :func:`~microslip.integrators.mindlin_lanes.supports_exponent`, whose stiffness
    k_t ∝ δ^(m2-1) is rough at touchdown (docs/theory/numerics.md, "Lanes on a Mindlin
    spring")."""
    from microslip.integrators.shared_lanes import LaneStalledError

    if backend == "cuda":
        from microslip.integrators.mindlin_lanes_cuda import run_mindlin_lanes_cuda as run
    else:
        from functools import partial

        from microslip.integrators.mindlin_lanes import run_mindlin_lanes

        run = partial(run_mindlin_lanes, on_done=on_done)

    def lanes(setups):
        picked = [models[g] for g in setups]
        ratio = [model.tangential.ratio for model in picked]
        groups, lane_forces, mu_s, mu_k = _lane_arrays(picked, forces)
        x = run(coeffs[setups], normal0[setups], ratio, groups, lane_forces, mu_s, mu_k,
                duration, dt, periods=periods[setups])[0]  # fmt: skip
        return x.reshape(setups.size, forces.size)

    everything = np.arange(len(models))
    try:
        return lanes(everything).ravel()
    except LaneStalledError as error:
        stalled, partial = error.setups, error.partial
    x = np.empty((len(models), forces.size))
    rest = np.setdiff1d(everything, stalled)
    x[rest] = partial[0].reshape(len(models), forces.size)[rest]  # ran to the end
    if stalled.size:
        # One batched run for all of them: blocks full of lanes, spread over the threads
        # (a lane's bits do not depend on its block).
        states0 = np.zeros((stalled.size * forces.size, 4))
        states0[:, :2] = np.repeat(normal0[stalled], forces.size, axis=0)
        run = _batched_run([models[g] for g in stalled], forces, duration, dt, states0)
        x[stalled] = run.states[:, 2].reshape(stalled.size, forces.size)
    return x.ravel()


def _batched_run(models, forces, duration, dt, states0=None):
    """The batched RK4 run (:class:`~microslip.integrators.batched.BatchResult`) of step
    ``dt`` [s], one lane per (model, force [N]), model-major, from ``states0`` at t = 0
    (default: rest at y0, a relaxed spring).

    ``duration`` must be a whole number of excitation periods when ``states0`` continues
    an earlier run (the excitation restarts at phase 0)."""
    from microslip.integrators.batched import simulate_batch

    coeffs = np.repeat([model.pack(0.0) for model in models], forces.size, axis=0)
    coeffs[:, FORCE] = np.tile(forces, len(models))
    if states0 is None:
        states0 = np.zeros((coeffs.shape[0], 4))
        states0[:, 0] = np.repeat([model.params.static_deflection for model in models],
                                  forces.size)  # fmt: skip
    return simulate_batch(coeffs, states0, duration, dt)
