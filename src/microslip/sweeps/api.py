"""``velocity_map`` and ``sweep``: the mean sliding velocity over grids of inputs (Fig. 7)."""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from microslip.model.composition import Model
from microslip.model.parameters import Parameters
from microslip.sweeps.runner import check_store_path, check_workers, run_sweep
from microslip.sweeps.spec import SweepSpec

IN_MEMORY_TIME_CHUNK_LANES = 2**18  # lanes of an in-memory time chunk, at most


def sweep(
    model_or_params: Model | Parameters | None = None,
    axes: Mapping[str, Any] | None = None,
    *,
    force: Any = None,
    amplitude: Any = None,
    method: str = "steady",
    duration: float | None = None,
    dt: float | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    store: str | Path | None = None,
    progress: bool = False,
    amplitude_chunk: int | None = None,
    allow_large: bool = False,
    backend: str = "cpu",
) -> xr.DataArray:
    """Mean sliding velocity [m/s] over any numeric fields of a model, force and amplitude;
    or, for a model driven at a prescribed velocity, the effective friction coefficient.

    Parameters
    ----------
    model_or_params : Model or Parameters, optional
        The model whose fields are not swept (the paper's data and parts by default).
    axes : mapping of dotted field name -> values, optional
        Model fields to sweep by their dotted names (:meth:`Model.numeric_fields`, e.g.
        ``{"mu": [...], "damping.ratio": [...], "excitation.frequency": [...]}``), in SI
        units; each becomes a dimension, in this order. Each value is checked by
        building the Model (its own one-line message names the field). Every axis,
        force and amplitude included, holds distinct values (at most 1e7).
    force : float or array
        Tangential force F in [0, 1e6 m g] [N] (for every swept parameter set). Not
        given for a model with ``drive=PrescribedVelocity``: then the result is μ_eff
        [-] over the axes (e.g. ``{"drive.velocity": v, "excitation.amplitude": a}``),
        computed in memory by :mod:`microslip.sweeps.friction_sweep` (``store``,
        ``scheduler`` and ``workers`` are refused there).
    amplitude : float or array
        Free vibration only: amplitude A = y0 - y_min in [0, 1e3 y0] [m]; the last
        two dimensions are then ("force", "amplitude"). A model with a normal
        excitation refuses it: its dimensions are (*axes, "force").
    method : {"steady", "time"}
        "steady": exact long-time mean (docs/model-facts.md, fact 6; 0 where the slider
        never moves, inf where F > μ m g); on a forced contact the reflected process
        over one period of the periodic orbit reached from rest, one orbit per
        parameter set shared by all forces; a damped free vibration decays to rest (0
        below μ m g). "time": RK4 with located switching for ``duration`` [s] from
        rest (at the top for the free vibration, at y0 under excitation), mean =
        x(duration)/duration: a shared-normal kernel (one normal motion per set-up,
        shared by every force) on a rigid contact, a TangentialSpring or a MindlinSpring
        (the compliant contacts, which "steady" refuses); a MindlinSpring set-up that
        leaves contact at m2 other than 1, 2 or >= 3 (a Hertz contact, m2 = 1.5), and
        one whose lane stalls, run as one batched trajectory per force instead,
        ``simulate(method="rk4")`` bit for bit, at ~0.4-1.3 µs per trajectory-step and
        thread.
    duration : float, optional
        Simulated time per point for "time" [s] (default 0.05 s), at least 1e-6 T0 of
        every parameter set. Refused with "steady" unless it is the default.
    dt : float, optional
        RK4 step for "time" [s] (default T/200 of each parameter set, T the shortest of
        T0, the excitation period and the body's tangential oscillation on a compliant
        contact, 2π sqrt(m/k_t)); must be <= T/10 for every parameter set.
        Refused with "steady".
    scheduler : str, optional
        Address of a running Dask scheduler (``tcp://host:port``).
    workers : int, optional
        Start a local Dask cluster of this many worker processes, at most 4 per CPU
        (:func:`microslip.sweeps.runner.max_workers`).
    store : path, optional
        Resumable Zarr working store; chunks already there are not recomputed. Its
        parent directory must exist.
    progress : bool
        Progress bar with ETA on standard error.
    allow_large : bool
        Run even when the estimated run time exceeds 10 minutes or the memory half of
        the available memory; otherwise refused up front with
        :class:`microslip.budget.WorkLimitError` (:meth:`SweepSpec.check_budget`).
        The estimate is the CPU's, also for ``backend="cuda"``.
    backend : {"cpu", "cuda"}
        "cuda": the lanes of the shared-normal time kernels (``method="time"``, a rigid
        contact or a TangentialSpring) run on an NVIDIA GPU through numba's CUDA
        target, the normal tapes on the CPU cores; the result agrees with "cpu" to
        rounding (the GPU fuses multiply-adds) and is refused in one line where no GPU
        can be used. Default chunks then hold 2^18 points (a GPU needs many lanes).

    Returns
    -------
    xarray.DataArray
        ``mean_velocity`` with dims (*axes, "force", "amplitude") (free vibration) or
        (*axes, "force") (forced), ``units`` attrs on it and its coordinates, and the
        model's parts as attrs (:meth:`Model.to_attrs`).
    """
    if isinstance(model_or_params, Model) and model_or_params.is_kinematic:
        return _friction_sweep(
            model_or_params, axes, force=force, amplitude=amplitude, method=method,
            duration=duration, dt=dt, scheduler=scheduler, workers=workers, store=store,
            progress=progress, amplitude_chunk=amplitude_chunk, backend=backend,
        )  # fmt: skip
    if force is None:
        raise ValueError(
            "force is required (N): the mean velocity is swept over forces; for the "
            "effective friction give the model drive=ms.PrescribedVelocity(v)"
        )
    workers = check_workers(workers)  # before anything is built or started
    if store is not None:
        store = check_store_path(store)
    if not isinstance(allow_large, bool):
        raise ValueError(f"allow_large must be True or False, got {allow_large!r}")
    if amplitude_chunk is None and store is None and scheduler is None and workers is None:
        # In memory, one chunk per parameter set is fastest; a time chunk's lanes (~190 B
        # each) are capped, which is as fast and bounds memory (2048 x 2048: 2.8-2.9 s in
        # chunks of 128 amplitudes, 5.0 s and 0.8 GB in one).
        amplitude_chunk = np.size(amplitude)
        if method == "time":
            lanes = max(1, IN_MEMORY_TIME_CHUNK_LANES // max(1, np.size(force)))
            amplitude_chunk = max(1, min(amplitude_chunk, lanes))
    spec = SweepSpec.build(
        model_or_params, axes, force, amplitude, method=method, duration=duration, dt=dt,
        amplitude_chunk=amplitude_chunk, allow_large=allow_large, backend=backend,
    )  # fmt: skip
    ds = run_sweep(spec, store=store, scheduler=scheduler, workers=workers, progress=progress)
    velocity = ds["mean_velocity"]
    velocity.attrs.update(spec.base.to_attrs())
    if np.isinf(velocity.values).any():
        warnings.warn(
            "some points have F > mu m g: no steady state, mean velocity set to inf",
            RuntimeWarning,
            stacklevel=2,
        )
    return velocity


def _friction_sweep(model: Model, axes, *, force, amplitude, progress, **options) -> xr.DataArray:
    """The μ_eff sweep of a kinematically driven model; options it cannot honour refused."""
    from microslip.sweeps.friction_sweep import friction_sweep

    if force is not None:
        raise ValueError(
            f"force={force!r} does not apply: the model's drive PrescribedVelocity sets the "
            "motion and the sweep gives the effective friction coefficient"
        )
    if options.pop("method") != "steady":
        raise ValueError("method='time' does not apply to an effective-friction sweep")
    if options.pop("backend") != "cpu":
        raise ValueError("backend='cuda' does not apply to an effective-friction sweep")
    for name, value in options.items():
        if value is not None:
            raise ValueError(
                f"{name}={value!r} is not supported by effective-friction sweeps (computed "
                "in memory, one shared normal motion per curve)"
            )
    if not isinstance(progress, bool):
        raise ValueError(f"progress must be True or False, got {progress!r}")
    return friction_sweep(model, axes or {}, amplitude=amplitude, progress=progress)


_SWEEP_OPTIONS = (
    "method", "duration", "dt", "scheduler", "workers", "store", "progress",
    "amplitude_chunk", "allow_large", "backend",
)  # fmt: skip


def velocity_map(
    model_or_params: Model | Parameters | None = None,
    *,
    forces: Any,
    amplitudes: Any = None,
    frequencies: Any = None,
    **options: Any,
) -> xr.DataArray:
    """Mean sliding velocity v(F, A) [m/s] on a grid: the map of Fig. 7.

    ``forces`` [N] and ``amplitudes`` [m] are 1-D arrays; the result has dims
    ("force", "amplitude"). For a model with a normal excitation give no amplitudes;
    with ``frequencies`` [Hz] the map is v(f, F) with dims ("excitation.frequency",
    "force"), otherwise ("force",). Other options as for :func:`sweep` (``method``,
    ``duration``, ``dt``, ``scheduler``, ``workers``, ``store``, ``progress``,
    ``amplitude_chunk``, ``allow_large``, ``backend``); any other keyword is refused with
    ``ValueError``.
    """
    unknown = sorted(set(options) - set(_SWEEP_OPTIONS))
    if unknown:
        raise ValueError(
            f"velocity_map() got an unknown keyword {unknown[0]!r}; "
            f"known: forces, amplitudes, frequencies, {', '.join(_SWEEP_OPTIONS)}"
        )
    axes = None if frequencies is None else {"excitation.frequency": frequencies}
    return sweep(model_or_params, axes, force=forces, amplitude=amplitudes, **options)
