"""Integrators: fixed-step RK4 and adaptive Dormand–Prince pairs with located switching.

They advance the composed system of :mod:`microslip.model.system` without knowing how
many state variables it has or what they mean.
"""

from microslip.integrators.driver import METHODS, RawTrajectory, integrate
from microslip.model.system import EVENT_NAMES

__all__ = ["EVENT_NAMES", "METHODS", "RawTrajectory", "integrate"]
