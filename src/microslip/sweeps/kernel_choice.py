"""Where a sweep runs and how much work it is: the time kernel a model takes, the
backend (CPU or an NVIDIA GPU) it can run on, and the work, run time and memory
estimated from the sweep's sizes (:mod:`microslip.budget`)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from microslip import budget
from microslip import validation as check
from microslip.analysis.steady_state import TANGENTIAL_INSTEAD
from microslip.integrators.mindlin_lanes import supports_exponent
from microslip.model.composition import Model
from microslip.model.tangential import MindlinSpring, TangentialSpring
from microslip.sweeps.axes import log_step_period
from microslip.validation import DEFAULT_RK4_STEPS_PER_PERIOD

__all__ = [
    "BACKENDS",
    "CUDA_CHUNK_LANES",
    "SWEEP_INSTEAD",
    "TIME_TANGENTIAL",
    "checked_backend",
    "estimate_work",
    "time_kernel",
]

BACKENDS = ("cpu", "cuda")  # where the shared-normal time kernel runs
CUDA_CHUNK_LANES = 2**18  # default lanes per chunk on a GPU (it needs many to be busy)
# The tangential contacts of a time sweep.
TIME_TANGENTIAL = (None, TangentialSpring, MindlinSpring)
SWEEP_INSTEAD = (
    f"{TANGENTIAL_INSTEAD}; method='time' also takes a compliant tangential contact "
    "(TangentialSpring, MindlinSpring)"
)


def time_kernel(model: Model, param_axes=()) -> str:
    """The kernel of a time sweep of ``model`` (:func:`microslip.budget.estimate_sweep`):
    "shared" (rigid contact), "spring" (TangentialSpring) or "mindlin" (MindlinSpring),
    each a shared-normal kernel (:mod:`microslip.integrators.shared_lanes`,
    :mod:`~microslip.integrators.spring_lanes`, :mod:`~microslip.integrators.mindlin_lanes`);
    "batched" (:mod:`microslip.integrators.batched`, one trajectory per point) for a
    MindlinSpring whose contact exponent m2, or one of the ``param_axes``' values of
    "m2", the Mindlin lanes do not run
    (:func:`~microslip.integrators.mindlin_lanes.supports_exponent`)."""
    if not model.is_compliant:
        return "shared"
    if isinstance(model.tangential, TangentialSpring):
        return "spring"
    exponents = dict(param_axes).get("m2", (model.params.m2,))
    return "mindlin" if all(supports_exponent(m2) for m2 in exponents) else "batched"


def checked_backend(backend: Any, model: Model, method: str, param_axes=()) -> str:
    """``backend`` if this sweep (of ``model`` over ``param_axes``) can run there, else
    ValueError in one line."""
    backend = check.one_of("backend", backend, BACKENDS)
    if backend == "cpu":
        return backend
    if method != "time":
        raise ValueError("backend='cuda' runs method='time' only; 'steady' runs on the CPU")
    if time_kernel(model, param_axes) == "batched":
        raise ValueError(
            "backend='cuda' runs the shared-normal time kernels (a rigid contact, a "
            "TangentialSpring, a MindlinSpring at m2 = 1, 2 or >= 3); this "
            f"{type(model.tangential).__name__} at m2 = {model.params.m2!r} (or an m2 axis) "
            "takes the batched kernel, which runs on the CPU"
        )
    from microslip.integrators.shared_lanes_cuda import cuda_unavailable

    reason = cuda_unavailable()
    if reason is not None:
        raise ValueError(f"backend='cuda': {reason}")
    return backend


def estimate_work(
    model: Model,
    param_axes,
    n_forces: int,
    n_amplitudes: int,
    method: str,
    duration: float,
    dt: float | None,
    amplitude_chunk: int,
) -> budget.Estimate:
    """Work, run time [s] and memory [bytes] from the sizes (no per-point structure)."""
    n_sets = math.prod(len(values) for _, values in param_axes)
    lane_steps = setup_steps = 0.0
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
        rounds = full * budget.shared_chunk_rounds(amplitude_chunk)
        if rest:
            rounds += budget.shared_chunk_rounds(rest)
        setup_steps = total_steps * rounds
    values = n_forces + n_amplitudes + sum(len(v) for _, v in param_axes)
    return budget.estimate_sweep(
        method=method,
        n_sets=n_sets,
        n_forces=n_forces,
        n_amplitudes=n_amplitudes,
        lane_steps=lane_steps,
        setup_steps=setup_steps,
        chunk_points=n_forces * amplitude_chunk,
        axis_values=values,
        kernel=time_kernel(model, param_axes),
    )
