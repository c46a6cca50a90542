"""Sweeps: the mean-velocity map of Fig. 7 and grids over any parameter, local or on Dask."""

from microslip.sweeps.api import sweep, velocity_map
from microslip.sweeps.runner import run_sweep
from microslip.sweeps.spec import SweepSpec
from microslip.sweeps.store import StoreMismatchError

__all__ = ["StoreMismatchError", "SweepSpec", "run_sweep", "sweep", "velocity_map"]
