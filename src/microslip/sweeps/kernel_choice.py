"""Where a sweep runs and how much work it is: the time kernel a model takes, the
backend (CPU or an NVIDIA GPU) it can run on, and the work, run time and memory
estimated from the sweep's sizes (:mod:`microslip.budget`)."""

from __future__ import annotations

import functools
import itertools
import math
from typing import Any

import numpy as np

from microslip import budget
from microslip import validation as check
from microslip.analysis.steady_state import TANGENTIAL_INSTEAD
from microslip.integrators.setup_copies import SetupCopies
from microslip.model.composition import Model
from microslip.model.friction import StaticKinetic
from microslip.model.parameters import Parameters
from microslip.model.tangential import MindlinSpring, TangentialSpring
from microslip.sweeps import cost
from microslip.sweeps.axes import field_grid, grid_logs, kinetic_mu_grid, log_step_period
from microslip.validation import DEFAULT_RK4_STEPS_PER_PERIOD

__all__ = [
    "BACKENDS",
    "CUDA_CHUNK_LANES",
    "SWEEP_INSTEAD",
    "TIME_FRICTION",
    "TIME_TANGENTIAL",
    "allowed_parts",
    "checked_backend",
    "estimate_work",
    "rough_exponents",
    "rough_setups",
    "time_kernel",
]

BACKENDS = ("cpu", "cuda")  # where the shared-normal time kernel runs
CUDA_CHUNK_LANES = 2**18  # default lanes per chunk on a GPU (it needs many to be busy)
# The tangential contacts of a time sweep.
TIME_TANGENTIAL = (None, TangentialSpring, MindlinSpring)
# The friction laws of a time sweep: every lane kernel takes a static and a kinetic
# coefficient (stick up to μ_s N, slip against μ_k N).
TIME_FRICTION = (None, StaticKinetic)
SWEEP_INSTEAD = (
    f"{TANGENTIAL_INSTEAD}; method='time' also takes a compliant tangential contact "
    "(TangentialSpring, MindlinSpring) and StaticKinetic friction"
)


def allowed_parts(method: str) -> dict[str, tuple[type | None, ...]]:
    """The tangential part types a sweep of ``method`` takes beyond the paper's, for
    :func:`microslip.model.capabilities.require`: with "time" a compliant contact
    (:data:`TIME_TANGENTIAL`) and StaticKinetic friction (:data:`TIME_FRICTION`); with
    "steady" none (its reflected process needs a rigid contact and Coulomb friction)."""
    if method == "time":
        return {"tangential": TIME_TANGENTIAL, "friction": TIME_FRICTION}
    return {}


def time_kernel(model: Model) -> str:
    """The kernel of a time sweep of ``model`` (:func:`microslip.sweeps.cost.estimate_sweep`):
    "shared" (rigid contact), "spring" (TangentialSpring) or "mindlin" (MindlinSpring),
    each a shared-normal kernel (:mod:`microslip.integrators.shared_lanes`,
    :mod:`~microslip.integrators.spring_lanes`, :mod:`~microslip.integrators.mindlin_lanes`).
    The Mindlin lanes of a set-up that leaves contact at a contact exponent m2 outside
    :func:`~microslip.integrators.mindlin_lanes.supports_exponent` (a Hertz contact,
    m2 = 1.5) cross each flight on the scalar RK4 step
    (:mod:`~microslip.integrators.mindlin_windows`): :func:`rough_setups` counts those
    for the estimate. What the lanes still hand back (a window out of sight) runs on the
    batched RK4 kernel (:mod:`microslip.integrators.batched`, one trajectory per force)."""
    if not model.is_compliant:
        return "shared"
    if isinstance(model.tangential, TangentialSpring):
        return "spring"
    return "mindlin"


def rough_exponents(model: Model, param_axes=()) -> bool:
    """True for a MindlinSpring sweep with a contact exponent m2 (of the model or of an
    "m2" axis) outside :func:`~microslip.integrators.mindlin_lanes.supports_exponent`."""
    if not isinstance(model.tangential, MindlinSpring):
        return False
    # Imported here: the Mindlin kernel's modules are ~18 ms of a start that runs none.
    from microslip.integrators.mindlin_rows import supports_exponent

    exponents = dict(param_axes).get("m2", (model.params.m2,))
    return not all(supports_exponent(float(m2)) for m2 in exponents)


def rough_setups(model: Model, param_axes, amplitudes) -> float:
    """The fraction [1] of a rough-exponent Mindlin sweep's set-ups (:func:`rough_exponents`)
    that may leave contact, and so cross flights on the scalar step
    (:mod:`~microslip.integrators.mindlin_windows`): those of a free vibration
    from rest at A >= y0 (below, the motion stays in contact: it starts at rest at
    y0 - A > 0 and no damping law adds energy); every set-up of a forced model, of a
    parameter axis or without known amplitudes. 0 for every other sweep."""
    if not rough_exponents(model, param_axes):
        return 0.0
    if model.excitation is not None or len(param_axes) > 0 or amplitudes is None:
        return 1.0
    amplitudes = np.asarray(amplitudes, dtype=float)
    return float(np.mean(amplitudes >= model.params.static_deflection))


def flying_setups(model: Model, param_axes, amplitudes, duration: float, dt) -> float:
    """The fraction [1] of a rough-exponent Mindlin sweep's set-ups that leave contact,
    and so cross flights on the scalar step, found set by set where :func:`rough_setups` bounds
    it: of a free vibration those from rest at A >= y0 of their parameter set; of a
    forced one those whose normal motion from rest at y0 has a flight within
    ``duration`` [s], integrated at the sweep's step ``dt`` [s] (None: 1/200 of the
    period to resolve) as the lanes would
    (:func:`~microslip.integrators.normal_tape.leaves_contact`). The sets of an
    exponent the lanes run through flights count 0. Remembered for the last few sweeps
    (a sweep is estimated when it is built and again when its budget is checked)."""
    axes = tuple((name, tuple(float(v) for v in values)) for name, values in param_axes)
    return _flying_setups(model, axes, tuple(float(a) for a in np.ravel(amplitudes)),
                          float(duration), None if dt is None else float(dt))  # fmt: skip


@functools.lru_cache(maxsize=8)
def _flying_setups(model: Model, param_axes, amplitudes, duration: float, dt) -> float:
    from microslip.integrators.mindlin_rows import supports_exponent
    from microslip.integrators.normal_tape import leaves_contact, normal_coefficients

    names = [name for name, _ in param_axes]
    amplitudes = np.asarray(amplitudes, dtype=float)
    flying = []
    for values in itertools.product(*(values for _, values in param_axes)):
        at = model.replace(**dict(zip(names, values, strict=True))) if names else model
        y0 = at.params.static_deflection
        if supports_exponent(at.params.m2):
            flying.append(0.0)
        elif at.excitation is None:
            flying.append(float(np.mean(amplitudes >= y0)))
        else:
            step = budget.shortest_period(at) / DEFAULT_RK4_STEPS_PER_PERIOD if dt is None else dt
            c = normal_coefficients(at.pack(0.0))
            flying.append(1.0 if leaves_contact(c, y0, 0.0, duration, step) else 0.0)
    return float(np.mean(flying))


def checked_backend(backend: Any, model: Model, method: str, param_axes=()) -> str:
    """``backend`` if this sweep (of ``model`` over ``param_axes``) can run there, else
    ValueError in one line."""
    backend = check.one_of("backend", backend, BACKENDS)
    if backend == "cpu":
        return backend
    if method != "time":
        raise ValueError("backend='cuda' runs method='time' only; 'steady' runs on the CPU")
    from microslip.integrators.shared_lanes_cuda import cuda_unavailable

    reason = cuda_unavailable()
    if reason is not None:
        raise ValueError(f"backend='cuda': {reason}")
    return backend


# The largest share of budget.TIME_LIMIT_S that estimate_work spends integrating normal
# motions to see which set-ups leave contact (flying_setups).
PROBE_SHARE = 0.02


def estimate_work(
    model: Model,
    param_axes,
    n_forces: int,
    n_amplitudes: int,
    method: str,
    duration: float,
    dt: float | None,
    amplitude_chunk: int,
    forces=None,
    amplitudes=None,
) -> budget.Estimate:
    """Work, run time [s] and memory [bytes] from the sizes; with the ``forces`` [N] and
    ``amplitudes`` [m], a rigid time sweep of a free vibration is estimated on its
    repeated tape (:func:`repeated_tape_work`)."""
    n_sets = math.prod(len(values) for _, values in param_axes)
    lane_steps = setup_steps = total_steps = 0.0
    n_chunks = 0
    if method == "time":
        if dt is not None:
            steps = np.full(1, float(math.ceil(duration / dt))) * n_sets
        else:  # dt = 1/200 of the period to resolve, per set
            period = 10.0 ** log_step_period(model, param_axes)
            steps = np.ceil(duration * DEFAULT_RK4_STEPS_PER_PERIOD / period).ravel()
        total_steps = float(np.sum(steps))
        lane_steps = total_steps * n_forces * n_amplitudes
        # Chunks: full ones of amplitude_chunk amplitudes and the remainder.
        full, rest = divmod(n_amplitudes, amplitude_chunk)
        rounds = full * cost.shared_chunk_rounds(amplitude_chunk)
        if rest:
            rounds += cost.shared_chunk_rounds(rest)
        setup_steps = total_steps * rounds
        n_chunks = n_sets * (full + (1 if rest else 0))
    kernel = time_kernel(model)
    tape_fraction, lane_fraction, cycles = 1.0, 1.0, 0
    if method == "time" and kernel == "shared" and forces is not None and amplitudes is not None:
        tape_fraction, lane_fraction, cycles = repeated_tape_work(
            model, param_axes, forces, amplitudes, duration
        )
    if method == "time" and model.excitation is None:
        # A chunk of fewer set-ups than threads runs each as copies sharing out its lanes
        # (integrators/setup_copies.py).
        lane_fraction /= SetupCopies.copies_for(
            min(amplitude_chunk, n_amplitudes), n_forces, cost.batch_threads()
        )
    elif method == "time":
        # A forced model's chunks (one set-up each) run up to LOCAL_BATCH at a time, their
        # set-ups spread over the threads (each round above counted one).
        setup_steps /= min(cost.batch_threads(), cost.LOCAL_BATCH, max(n_chunks, 1))
    # The spring and Mindlin lanes of a free vibration run on its repeated tape too (the
    # rigid lanes' repeated tape is in the fractions above): cost.estimate_sweep decides.
    repeated = amplitudes is not None and repeats_from_rest(model, float(np.max(amplitudes)))
    values = n_forces + n_amplitudes + sum(len(v) for _, v in param_axes)
    estimate = cost.estimate_sweep(
        method=method,
        n_sets=n_sets,
        n_forces=n_forces,
        n_amplitudes=n_amplitudes,
        lane_steps=lane_steps,
        setup_steps=setup_steps,
        chunk_points=n_forces * amplitude_chunk,
        axis_values=values,
        kernel=kernel,
        tape_fraction=tape_fraction,
        lane_fraction=lane_fraction,
        cycles=cycles,
        n_chunks=n_chunks,
        repeated_tape=repeated,
    )
    if method != "time":
        return estimate

    def with_batched(handed_back: float) -> budget.Estimate:
        """The estimate with the fraction ``handed_back`` of the set-ups also crossing
        flights on the scalar step: cost.ROUGH_FLIGHT_SHARE of a batched run of them, a
        run per chunk (at least one set-up; a forced chunk is one), the times added, the
        memory the larger (a set-up the windows cannot take is still handed back)."""
        if handed_back <= 0.0:
            return estimate
        run_setups = max(1.0, min(amplitude_chunk, n_amplitudes) * handed_back)
        batched = cost.estimate_sweep(
            method=method, n_sets=n_sets, n_forces=n_forces, n_amplitudes=n_amplitudes,
            lane_steps=lane_steps * handed_back, chunk_points=n_forces * amplitude_chunk,
            axis_values=values, kernel="batched", run_lanes=run_setups * n_forces,
            free_vibration=model.damping is None and model.excitation is None,
        )  # fmt: skip
        return budget.Estimate(
            what=estimate.what, work=estimate.work, unit=estimate.unit,
            seconds=estimate.seconds + cost.ROUGH_FLIGHT_SHARE * batched.seconds,
            bytes=max(estimate.bytes, batched.bytes),
        )  # fmt: skip

    # Set-ups that may leave contact at a rough exponent cross their flights on the
    # scalar step: counted as a share of a batched run, on top of the lanes (a bound).
    handed_back = rough_setups(model, param_axes, amplitudes)
    bound = with_batched(handed_back)
    if handed_back == 0.0 or bound.seconds <= budget.TIME_LIMIT_S or amplitudes is None:
        return bound
    # Over the limit on a bound that counts every forced set-up (and every one of a
    # parameter axis) as leaving contact: find which do, where that costs no more than
    # a share of the limit (a forced one's normal motions alone, a tape each).
    probe_seconds = total_steps * cost.SHARED_S_PER_SETUP_STEP
    if model.excitation is not None and probe_seconds > PROBE_SHARE * budget.TIME_LIMIT_S:
        return bound
    return with_batched(flying_setups(model, param_axes, amplitudes, duration, dt))


def repeats_from_rest(model: Model, amplitude: float) -> bool:
    """Whether the normal motion of ``model`` from rest at amplitude A [m] above its
    equilibrium repeats from t = 0: a conservative free vibration (no damping, no
    excitation) with 0 <= A <= max_amplitude, whose tape is one period, repeated
    (:mod:`~microslip.integrators.periodic_tape`). At A = 0 the slider rests at its
    equilibrium, N = m g for ever: periodic with any period, T0 taken
    (:func:`~microslip.analysis.free_vibration.free_period`)."""
    return (
        model.damping is None
        and model.excitation is None
        and 0.0 <= amplitude <= model.params.max_amplitude
    )


def repeated_tape_work(model: Model, param_axes, forces, amplitudes, duration: float):
    """(tape, lane, repeating) of a rigid time sweep on a free vibration's repeated tape:
    the fractions [1] of a set-up's stepped tape (with the walk over its rows) and lane
    work left where it repeats (:func:`repeats_from_rest`; :func:`parking_fractions`),
    and the number of set-ups, each of which builds its one-period tape. (1, 1, 0),
    every set-up at the full cost, where the tape is not repeated: damping, excitation,
    or fewer than two periods.

    Upper bounds over the parameter sets: the fewest periods (the longest of the
    periods at the smallest and largest A of any set) and the smallest μ m g. T(A)/T0
    depends on A/y0 and m2 alone (with u = y/y0 and s = t/T0 the free vibration is
    u'' = (2π)²/m2 (1 - u^m2), and (2π)²/m2 in flight: docs/theory/free_vibration.md),
    so it is computed once per exponent, at the extreme ratios A/y0 of the sets."""
    none = (1.0, 1.0, 0)
    if not repeats_from_rest(model, 0.0):  # damped or forced: no tape repeats
        return none
    from microslip.analysis.free_vibration import free_period

    grid = field_grid(model.params, param_axes)  # broadcast views: no copy per field
    logs = grid_logs(model.params, param_axes)
    y0, t0 = 10.0 ** np.ravel(logs["y0"]), 10.0 ** np.ravel(logs["T0"])
    exponents = np.ravel(grid["m2"])
    amplitudes = np.asarray(amplitudes, dtype=float)
    ratio_cap = model.params.max_amplitude / model.params.static_deflection
    longest = 0.0
    for m2 in np.unique(exponents):
        sets = np.flatnonzero(exponents == m2)
        one = Parameters(**{name: float(values.flat[sets[0]]) for name, values in grid.items()})
        ratios = (amplitudes.min() / y0[sets].max(), amplitudes.max() / y0[sets].min())
        stretch = max(
            free_period(one, min(r, ratio_cap) * one.static_deflection) / one.natural_period
            for r in ratios
        )
        longest = max(longest, stretch * float(t0[sets].max()))
    periods = duration / longest
    if periods < 2.0:
        return none
    # The smallest μ_k m g [N]: a lane past it, once sliding, never stops.
    limit = float(np.min(kinetic_mu_grid(model, param_axes) * grid["mass"] * grid["g"]))
    tape, lane = parking_fractions(np.asarray(forces, dtype=float), limit, periods)
    return tape, lane, amplitudes.size * int(exponents.size)


# A lane this close to μ m g, relatively, is counted as never parking: the tape's mean
# normal force is m g only to its RK4 error, and such a lane may slide for ever.
NEAR_LIMIT = 1e-6


def parking_fractions(forces: np.ndarray, limit: float, periods: float) -> tuple[float, float]:
    """(tape, lane): the fractions [1] of the stepped tape and lane work of a set-up on
    a repeated tape of ``periods`` periods, forces F [N], μ m g = ``limit`` [N]
    (:data:`microslip.sweeps.cost.PARKED_LANE_PERIODS`, docs/theory/numerics.md,
    "Repeating lanes").

    A lane with |F| > μ m g accelerates for ever and never parks; so, counted, does one
    within :data:`NEAR_LIMIT` of it. One below slides through whole periods at most
    μ m g/(μ m g - |F|) times, as the mean normal force over a period is m g: it gains at
    most μ g T in a period and loses (μ m g - |F|) T/m over each whole period slid.
    After it has stopped once in a period it parks within PARKED_LANE_PERIODS. The tape
    is built over 2 periods; while any lane is live the kernel walks every row
    (:data:`~microslip.sweeps.cost.SHARED_S_PER_ROW`)."""
    magnitudes = np.abs(forces)
    below = magnitudes < limit * (1.0 - NEAR_LIMIT)
    to_park = np.full(magnitudes.shape, np.inf)
    to_park[below] = cost.PARKED_LANE_PERIODS + limit / (limit - magnitudes[below])
    live = np.minimum(1.0, to_park / periods)  # the share of the periods each lane is live
    walk = float(np.max(live)) * cost.SHARED_S_PER_ROW / cost.SHARED_S_PER_SETUP_STEP
    return min(1.0, 2.0 / periods + walk), float(np.mean(live))
