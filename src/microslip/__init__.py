"""microslip: sliding under dry friction driven by normal contact micro-vibrations.

Implements the model of Grudziński & Kostek (2005), J. Theor. Appl. Mech. 43(1):
a slider on a power-law compliant contact that may lose contact, under a constant
tangential force and Coulomb friction, with exact stick and located switching.
"""

# First, before any jitted function is decorated: numba's on-disk cache keyed on the
# whole reachable source, so an edit of any module is always compiled afresh.
from microslip import _jit_cache  # noqa: F401  (sorts first; keep it first)
from microslip.analysis.free_vibration import (
    free_frequency,
    free_period,
    normal_energy,
    turning_points,
)
from microslip.analysis.steady_state import StickSlipCycle, mean_velocity, stick_slip_cycle
from microslip.model.parameters import Parameters
from microslip.results import SimulationResult
from microslip.simulation import simulate
from microslip.sweeps import sweep, velocity_map

__version__ = "0.1.0"

__all__ = [
    "Parameters",
    "SimulationResult",
    "StickSlipCycle",
    "__version__",
    "free_frequency",
    "free_period",
    "mean_velocity",
    "normal_energy",
    "simulate",
    "stick_slip_cycle",
    "sweep",
    "turning_points",
    "velocity_map",
]
