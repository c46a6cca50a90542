"""Integrators: fixed-step RK4 and adaptive Dormand–Prince 5(4), both with located switching."""

from microslip.integrators.driver import METHODS, RawTrajectory, integrate
from microslip.integrators.switching import EVENT_NAMES

__all__ = ["EVENT_NAMES", "METHODS", "RawTrajectory", "integrate"]
