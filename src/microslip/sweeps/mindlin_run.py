"""The Mindlin lanes of a time sweep's run, and what they hand back.

:func:`mindlin_run` runs a sweep's Mindlin set-ups on the Mindlin lanes (CPU or GPU,
:mod:`microslip.integrators.mindlin_lanes`); what the GPU lanes hand back runs on the CPU
lanes, and what those still hand back on the batched RK4 kernel (:func:`batched_run`,
also the fallback of a forced model's steady state in :mod:`microslip.sweeps.compute`).
"""

from __future__ import annotations

import threading
from collections.abc import Callable

import numpy as np

from microslip.model.coefficients import FORCE


def mindlin_run(models, rows, setups, groups, normal0, periods, forces, lane_forces, mu_s,
                 mu_k, coeffs, duration, dt, backend, on_done=None):  # fmt: skip
    """x(duration) [m] of the Mindlin lanes of :func:`microslip.sweeps.compute._shared_run`
    (lanes in its order:
    ``rows`` by set-up, each under every force).

    What the lanes hand back runs on the batched RK4 kernel instead, one trajectory per
    lane (``simulate(method="rk4")`` bit for bit), the rest keeping the lanes' results
    (the CPU and GPU lanes hand them on as the error's ``partial``): each lane's result
    still depends on nothing else in the run. The GPU lanes hand back a set-up that
    leaves contact at a contact exponent outside
    :func:`~microslip.integrators.mindlin_lanes.supports_exponent`, whose stiffness
    k_t ∝ δ^(m2-1) is rough at touchdown (docs/theory/numerics.md, "Lanes on a Mindlin
    spring"), and a lane that stalls (an exact tie of stick and slip at a touchdown):
    the CPU lanes take those on, crossing such flights and ties on the scalar step
    (:mod:`~microslip.integrators.mindlin_windows`), and hand back only a set-up whose
    window does not fit the rows in sight.

    ``on_done`` (set-ups) hears of the lanes' progress, a set-up handed back counting
    only for what it reached (:func:`~microslip.integrators.threads.hand_back`), then of
    the batched run's, as the rest of the whole."""
    from microslip.integrators.shared_lanes import LaneStalledError

    told = None if on_done is None else _Counted(on_done)
    if backend == "cuda":
        from microslip.integrators.mindlin_lanes_cuda import run_mindlin_lanes_cuda as run
    else:
        from functools import partial

        from microslip.integrators.mindlin_lanes import run_mindlin_lanes

        run = partial(run_mindlin_lanes, on_done=told)
    ratio = np.array([models[r].tangential.ratio for r in setups])
    setup_args = (coeffs[setups], normal0[setups], ratio)
    try:
        return run(*setup_args, groups, lane_forces, mu_s, mu_k, duration, dt,
                   periods=periods[setups])[0]  # fmt: skip
    except LaneStalledError as error:
        x = np.array(error.partial[0])  # the rest ran to the end
        back = np.flatnonzero(_handed_back(groups, error))
    if backend == "cuda":
        # The GPU lanes hand back a rough set-up's flights and a lane that stalls: the CPU
        # lanes take them on, by windows on the scalar step (a lane's bits are those of
        # a CPU run: they depend on nothing else in it).
        x[back], back = _cpu_mindlin_lanes(back, groups, setup_args, periods[setups],
                                           lane_forces, mu_s, mu_k, duration, dt)  # fmt: skip
    if back.size == 0:
        return x
    # In one batched run: blocks full of lanes, spread over the threads (a lane's bits
    # do not depend on its block).
    row_of = rows[back // forces.size]
    states0 = np.zeros((back.size, 4))
    states0[:, :2] = normal0[row_of]
    share = None
    if told is not None and setups.size > told.total:
        rest = setups.size - told.total  # the handed-back set-ups' share of the whole

        def share(part: float) -> None:
            told(part * rest)

    batch = _batched_lanes([models[r] for r in row_of], lane_forces[back], duration, dt,
                           states0, on_done=share)  # fmt: skip
    x[back] = batch.states[:, 2]
    return x


def _cpu_mindlin_lanes(lanes, groups, setup_args, periods, forces, mu_s, mu_k, duration, dt):
    """(x(duration) [m] of ``lanes`` (indices of a Mindlin run's lanes, ``groups`` their
    set-ups) on the CPU Mindlin lanes, the indices of those still handed back)."""
    from microslip.integrators.mindlin_lanes import run_mindlin_lanes
    from microslip.integrators.shared_lanes import LaneStalledError

    used, local = np.unique(groups[lanes], return_inverse=True)
    per_lane = [np.broadcast_to(a, groups.shape)[lanes] for a in (forces, mu_s, mu_k)]
    try:
        return run_mindlin_lanes(*(a[used] for a in setup_args), local, *per_lane, duration,
                                 dt, periods=periods[used])[0], lanes[:0]  # fmt: skip
    except LaneStalledError as error:
        return np.array(error.partial[0]), lanes[_handed_back(local, error)]


def _handed_back(groups, error):
    """The lanes (a mask over ``groups``, their set-ups) that a Mindlin-lane run's
    LaneStalledError hands back: every lane of a set-up it names, and those it names
    alone."""
    back = np.isin(groups, error.setups)
    back[error.lanes] = True
    return back


class _Counted:
    """A progress callback that adds up what it is told, from any thread."""

    def __init__(self, on_done: Callable[[float], None]) -> None:
        self.on_done, self.total, self._lock = on_done, 0.0, threading.Lock()

    def __call__(self, amount: float) -> None:
        with self._lock:
            self.total += amount
        self.on_done(amount)


def batched_run(models, forces, duration, dt, states0=None, on_done=None):
    """The batched RK4 run (:class:`~microslip.integrators.batched.BatchResult`) of step
    ``dt`` [s], one lane per (model, force [N]), model-major, from ``states0`` at t = 0
    (default: rest at y0, a relaxed spring); ``on_done`` told the fraction [1] of it done.

    ``duration`` must be a whole number of excitation periods when ``states0`` continues
    an earlier run (the excitation restarts at phase 0)."""
    forces = np.asarray(forces, dtype=float)
    lane_models = [model for model in models for _ in range(forces.size)]
    return _batched_lanes(lane_models, np.tile(forces, len(models)), duration, dt, states0,
                          on_done)  # fmt: skip


def _batched_lanes(models, forces, duration, dt, states0=None, on_done=None):
    """:func:`batched_run` of one lane per (models[i], forces[i] [N]), in blocks that
    spread the run over the threads (:func:`~microslip.integrators.batched.block_for`)."""
    from microslip.integrators.batched import block_for, simulate_batch
    from microslip.integrators.threads import thread_count

    packed = {id(model): model.pack(0.0) for model in models}
    coeffs = np.array([packed[id(model)] for model in models]).reshape(len(models), -1)
    coeffs[:, FORCE] = forces
    if states0 is None:
        states0 = np.zeros((coeffs.shape[0], 4))
        states0[:, 0] = [model.params.static_deflection for model in models]
    block = block_for(len(models), thread_count())
    return simulate_batch(coeffs, states0, duration, dt, block=block, on_done=on_done)
