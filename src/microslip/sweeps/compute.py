"""Computing one chunk of a sweep: a pure function of (spec, chunk key), safe to ship to Dask."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from microslip.analysis.steady_state import ORBIT_STEPS, mean_velocity_grid
from microslip.model.coefficients import MU, MU_STATIC, TANGENTIAL_STIFFNESS, pack
from microslip.simulation import DEFAULT_RK4_STEPS_PER_PERIOD, initial_state_from_amplitude
from microslip.sweeps.kernel_choice import repeats_from_rest, time_kernel
from microslip.sweeps.mindlin_run import batched_run, mindlin_run
from microslip.sweeps.spec import ChunkKey, SweepSpec

# A caller's progress: called with the fraction [1] of the work of a compute call done
# since the last call (a time run's set-ups as they advance: threads.run_ranges' on_done).
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
    run's set-ups as they advance on the CPU (:data:`Progress`).
    """
    if spec.forced:
        return forced_chunk(spec, key, progress)
    if spec.base.damping is not None and spec.method == "steady":
        return damped_free_chunk(spec, key)
    if spec.method == "time":
        return _time_chunks(spec, [key], progress)[0]
    params = spec.params_at(key)
    forces = np.asarray(spec.forces)
    amplitudes = np.asarray(spec.amplitudes[spec.amplitude_slice(key)])
    out = np.empty((forces.size, amplitudes.size))
    if not mean_velocity_grid(forces, amplitudes, pack(params, 0.0), ORBIT_STEPS, out):
        raise RuntimeError(f"orbit table overflow in chunk {key}")
    return out


def _share(progress: Progress | None, parts: int) -> Callable[[float], None] | None:
    """``progress`` of a whole of ``parts`` equal parts, told of parts done (set-ups as a
    kernel's ``on_done`` counts them, or one chunk's fraction): None stays None."""
    if progress is None:
        return None
    return lambda done: progress(done / parts)


def shares_runs(spec: SweepSpec) -> bool:
    """True when :func:`compute_chunks` computes several chunks in one run: the time
    chunks, whose normal set-ups then spread over the cores, and whose set-ups that
    differ only in friction coefficients share one tape (:func:`_time_chunks`)."""
    return spec.method == "time"


def tape_order(spec: SweepSpec) -> Callable[[ChunkKey], tuple]:
    """A sort key for chunk keys that puts next to each other the chunks whose normal
    set-ups differ only in friction coefficients (axes "mu", "friction.*": no normal law
    reads them), so that a batch of :func:`compute_chunks` finds them together and runs
    them on one tape each."""
    friction = [i for i, (name, _) in enumerate(spec.param_axes)
                if name == "mu" or name.startswith("friction.")]  # fmt: skip
    normal = [i for i in range(len(spec.param_axes)) if i not in friction]

    def order(key: ChunkKey) -> tuple:
        return (*(key[i] for i in normal), key[-1], *(key[i] for i in friction))

    return order


def compute_chunks(
    spec: SweepSpec, keys: list[ChunkKey], progress: Progress | None = None
) -> list[np.ndarray]:
    """:func:`compute_chunk` of each key, the same bits; time chunks go through one
    shared-normal run (:func:`_time_chunks`: a set-up's lanes depend on nothing else in
    the run). ``progress`` hears of the fraction of all the keys' work done."""
    if not shares_runs(spec):
        return [compute_chunk(spec, key, _share(progress, len(keys))) for key in keys]
    return _time_chunks(spec, keys, progress)


def _time_chunks(
    spec: SweepSpec, keys: list[ChunkKey], progress: Progress | None = None
) -> list[np.ndarray]:
    """Time chunks through one shared-normal run per step size: a row per normal set-up
    (a forced model's chunk is one, from rest at y0; a free vibration's one per amplitude
    of the chunk, from rest at y0 - A), every force on each (:func:`_shared_run`, where
    rows that differ only in friction coefficients share a tape). Blocks (forces,
    amplitudes) of x(T)/T [m/s], one per key."""
    models = [spec.model_at(key) for key in keys]
    steps = [_time_step(spec, model) for model in models]
    rows_of_key: list[list[int]] = []
    row_models, normal0 = [], []
    for key, model in zip(keys, models, strict=True):
        if spec.forced:
            starts = [(model.params.static_deflection, 0.0)]
        else:
            amplitudes = np.asarray(spec.amplitudes[spec.amplitude_slice(key)])
            starts = [initial_state_from_amplitude(model.params, a)[:2] for a in amplitudes]
        rows_of_key.append(list(range(len(row_models), len(row_models) + len(starts))))
        row_models += [model] * len(starts)
        normal0 += starts
    normal0 = np.array(normal0, dtype=float).reshape(-1, 2)
    share = _share(progress, len(row_models))
    x = np.empty((len(row_models), len(spec.forces)))
    for dt in dict.fromkeys(steps):  # one run per step size, in first-seen order
        rows = [r for k, step in enumerate(steps) if step == dt for r in rows_of_key[k]]
        x[rows] = _shared_run(
            [row_models[r] for r in rows], normal0[rows], spec.forces, spec.duration, dt,
            spec.backend, share,
        )  # fmt: skip
    return [(x[rows] / spec.duration).T for rows in rows_of_key]


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
        return _time_chunks(spec, [key], progress)[0]
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
        states = batched_run([model], forces, half, dt).states
        end = batched_run([model], forces, half, dt, states0=states).states
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
    """x(duration) [m], shape (rows, forces), from rest on each row's normal set-up (one
    model per row of ``normal0``: y [m], ẏ [m/s] at t = 0) under every constant force
    [N], on the shared-normal kernel of the models' tangential contact (all rigid, all
    springs of constant stiffness or all Mindlin springs; a relaxed spring at t = 0);
    ``backend`` "cuda" runs the lanes on a GPU
    (:mod:`~microslip.integrators.shared_lanes_cuda`,
    :mod:`~microslip.integrators.spring_lanes_cuda`,
    :mod:`~microslip.integrators.mindlin_lanes_cuda`); ``on_done`` as for
    :func:`~microslip.integrators.shared_lanes.run_shared` (the CPU kernels only), told
    in rows.

    Rows whose models differ only in their friction coefficients share one normal set-up
    (:func:`_normal_setups`): one tape for all their lanes, each lane with its own
    μ_s, μ_k. A lane's bits depend only on its own parameters and its tape, so they are
    those of a run of its row alone."""
    from microslip.integrators.shared_lanes import run_shared
    from microslip.integrators.spring_lanes import run_spring_lanes

    forces = np.asarray(forces, dtype=float)
    periods = _normal_periods(models, normal0)
    setups, setup_of_row, coeffs = _normal_setups(models, normal0, periods)
    # Lanes by set-up (stably), each row's forces with its own friction coefficients.
    rows = np.argsort(setup_of_row, kind="stable")
    groups = np.repeat(setup_of_row[rows], forces.size)
    lane_forces, mu_s, mu_k = _lane_arrays(coeffs[rows], forces)
    on_done = _per_row(on_done, len(models), setups.size)
    setup = (coeffs[setups], normal0[setups])
    kernel = time_kernel(models[0])
    if kernel == "mindlin":
        x = mindlin_run(models, rows, setups, groups, normal0, periods, forces, lane_forces,
                        mu_s, mu_k, coeffs, duration, dt, backend, on_done)  # fmt: skip
    elif kernel == "spring":
        stiffness = [models[r].tangential.stiffness for r in setups]
        if backend == "cuda":
            from microslip.integrators.spring_lanes_cuda import run_spring_lanes_cuda

            x = run_spring_lanes_cuda(*setup, stiffness, groups, lane_forces, mu_s, mu_k,
                                      duration, dt, periods=periods[setups])[0]  # fmt: skip
        else:
            x = run_spring_lanes(*setup, stiffness, groups, lane_forces, mu_s, mu_k, duration,
                                 dt, periods=periods[setups], on_done=on_done)[0]  # fmt: skip
    elif backend == "cuda":
        from microslip.integrators.shared_lanes_cuda import run_shared_cuda

        x = run_shared_cuda(*setup, groups, lane_forces, mu_s, mu_k, duration, dt,
                            periods=periods[setups])[0]  # fmt: skip
    else:
        x = run_shared(*setup, groups, lane_forces, mu_s, mu_k, duration, dt,
                       periods=periods[setups], on_done=on_done)[0]  # fmt: skip
    out = np.empty((len(models), forces.size))
    out[rows] = np.asarray(x).reshape(len(models), forces.size)
    return out


def _normal_setups(models, normal0, periods):
    """(setups, setup_of_row, coefficients): the distinct normal set-ups of the rows, by
    first row, the set-up of each row, and each row's normal coefficient vector
    (:func:`~microslip.integrators.normal_tape.normal_coefficients`). Rows share a set-up
    where their normal motion is the same (:func:`~microslip.integrators.normal_tape.normal_key`,
    the same start and period) and so is their tangential spring (the spring and Mindlin
    kernels hold it per set-up): in a sweep over friction coefficients."""
    from microslip.integrators.normal_tape import normal_coefficients, normal_key

    packed = {id(model): model.pack(0.0) for model in models}
    coeffs = np.array([normal_coefficients(packed[id(model)]) for model in models])
    index: dict[tuple, int] = {}
    first_rows: list[int] = []  # a set-up's first row stands for it (coefficients, spring)
    setup_of_row = np.empty(len(models), dtype=np.int64)
    for r, model in enumerate(models):
        spring = packed[id(model)][TANGENTIAL_STIFFNESS] if model.is_compliant else 0.0
        key = (normal_key(packed[id(model)]), normal0[r].tobytes(), periods[r], spring)
        if key not in index:
            index[key] = len(first_rows)
            first_rows.append(r)
        setup_of_row[r] = index[key]
    return np.array(first_rows, dtype=np.int64), setup_of_row, coeffs


def _per_row(on_done, n_rows: int, n_setups: int):
    """``on_done`` told in set-ups, counted in rows (a set-up of k rows is k of them;
    the rows of a sweep's set-ups are as many each, so the count is exact there)."""
    if on_done is None or n_rows == n_setups:
        return on_done
    return lambda count: on_done(count * n_rows / n_setups)


def _lane_arrays(coeffs, forces):
    """(force [N], μ_s [-], μ_k [-]) of every lane of rows of coefficient vectors
    ``coeffs`` (each row's model packed, :func:`_normal_setups`), each under every force,
    row-major. The coefficients are those the model's friction law packs (Coulomb: μ for
    both; StaticKinetic: its own)."""
    mu_static = np.repeat(coeffs[:, MU_STATIC], forces.size)
    mu_kinetic = np.repeat(coeffs[:, MU], forces.size)
    return np.tile(forces, coeffs.shape[0]), mu_static, mu_kinetic
