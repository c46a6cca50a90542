"""Sweeps: the mean-velocity map of Fig. 7 and grids over any parameter, local or on Dask."""

from microslip.sweeps.api import sweep, velocity_map
from microslip.sweeps.runner import run_sweep
from microslip.sweeps.spec import SweepSpec
from microslip.sweeps.store import StoreBusyError, StoreMismatchError, exclusive_lock, remove_store

__all__ = [
    "StoreBusyError",
    "StoreMismatchError",
    "SweepSpec",
    "exclusive_lock",
    "remove_store",
    "run_sweep",
    "sweep",
    "velocity_map",
]
