"""``velocity_map`` and ``sweep``: the mean sliding velocity over grids of inputs (Fig. 7)."""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from microslip.model.parameters import Parameters
from microslip.sweeps.runner import check_store_path, check_workers, run_sweep
from microslip.sweeps.spec import SweepSpec


def sweep(
    params: Parameters | None = None,
    axes: Mapping[str, Any] | None = None,
    *,
    force: Any,
    amplitude: Any,
    method: str = "steady",
    duration: float | None = None,
    dt: float | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    store: str | Path | None = None,
    progress: bool = False,
    amplitude_chunk: int | None = None,
    allow_large: bool = False,
) -> xr.DataArray:
    """Mean sliding velocity [m/s] over any Parameters fields, force and amplitude.

    Parameters
    ----------
    params : Parameters, optional
        Values of the fields that are not swept (paper's data by default).
    axes : mapping of field name -> values, optional
        Parameters fields to sweep (e.g. ``{"mu": [...], "m2": [...]}``), in SI units;
        each becomes a dimension, in this order. Every axis, force and amplitude
        included, holds distinct values (at most 1e7).
    force, amplitude : float or array
        Tangential force F in [0, 1e6 m g] [N] and amplitude A = y0 - y_min in
        [0, 1e3 y0] [m] (for every swept parameter set); always the last two
        dimensions ("force", "amplitude").
    method : {"steady", "time"}
        "steady": exact long-time mean (docs/model-facts.md, fact 6; 0 where the slider never
        moves, inf where F > μ m g). "time": batched RK4 with located switching for
        ``duration`` [s] from rest at the top, mean = x(duration)/duration.
    duration : float, optional
        Simulated time per point for "time" [s] (default 0.05 s), at least 1e-6 T0 of
        every parameter set. Refused with "steady" unless it is the default.
    dt : float, optional
        RK4 step for "time" [s] (default T0/200 of each parameter set); must be
        <= T0/10 for every parameter set. Refused with "steady".
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

    Returns
    -------
    xarray.DataArray
        ``mean_velocity`` with dims (*axes, "force", "amplitude") and ``units`` attrs.
    """
    workers = check_workers(workers)  # before anything is built or started
    if store is not None:
        store = check_store_path(store)
    if not isinstance(allow_large, bool):
        raise ValueError(f"allow_large must be True or False, got {allow_large!r}")
    if amplitude_chunk is None and store is None and scheduler is None and workers is None:
        amplitude_chunk = np.size(amplitude)  # in memory, one chunk per parameter set is fastest
    spec = SweepSpec.build(
        params, axes, force, amplitude, method=method, duration=duration, dt=dt,
        amplitude_chunk=amplitude_chunk, allow_large=allow_large,
    )  # fmt: skip
    ds = run_sweep(spec, store=store, scheduler=scheduler, workers=workers, progress=progress)
    velocity = ds["mean_velocity"]
    if np.isinf(velocity.values).any():
        warnings.warn(
            "some points have F > mu m g: no steady state, mean velocity set to inf",
            RuntimeWarning,
            stacklevel=2,
        )
    return velocity


_SWEEP_OPTIONS = (
    "method", "duration", "dt", "scheduler", "workers", "store", "progress",
    "amplitude_chunk", "allow_large",
)  # fmt: skip


def velocity_map(
    params: Parameters | None = None,
    *,
    forces: Any,
    amplitudes: Any,
    **options: Any,
) -> xr.DataArray:
    """Mean sliding velocity v(F, A) [m/s] on a grid: the map of Fig. 7.

    ``forces`` [N] and ``amplitudes`` [m] are 1-D arrays; the result has dims
    ("force", "amplitude"). Other options as for :func:`sweep` (``method``,
    ``duration``, ``dt``, ``scheduler``, ``workers``, ``store``, ``progress``,
    ``amplitude_chunk``, ``allow_large``); any other keyword is refused with
    ``ValueError``.
    """
    unknown = sorted(set(options) - set(_SWEEP_OPTIONS))
    if unknown:
        raise ValueError(
            f"velocity_map() got an unknown keyword {unknown[0]!r}; "
            f"known: forces, amplitudes, {', '.join(_SWEEP_OPTIONS)}"
        )
    return sweep(params, None, force=forces, amplitude=amplitudes, **options)
