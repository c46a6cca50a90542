"""microslip: sliding under dry friction driven by normal contact micro-vibrations.

Implements the model of Grudziński & Kostek (2005), J. Theor. Appl. Mech. 43(1):
a slider on a power-law compliant contact that may lose contact, under a constant
tangential force and Coulomb friction, with exact stick and located switching; and its
extensions as parts of a :class:`Model` (normal damping, normal excitation; see
docs/design.md), with the forced response of the contact by shooting and
pseudo-arclength continuation.

The public names are imported on first use (PEP 562), so ``import microslip`` and the
command line start without loading numba, xarray or dask: a Ctrl-C during start-up
then reaches the command line's own handler (one line, exit 130). Every module that
defines jitted functions imports :mod:`microslip._jit_cache` itself, before numba
decorates anything, so its cache can never serve stale machine code.
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

# public name -> module that defines it
_EXPORTS = {
    "BaseMotion": "microslip.model.excitation",
    "ConstantForce": "microslip.model.drive",
    "Coulomb": "microslip.model.friction",
    "HarmonicDrive": "microslip.model.drive",
    "MindlinSpring": "microslip.model.tangential",
    "PrescribedVelocity": "microslip.model.drive",
    "Rigid": "microslip.model.tangential",
    "SpringDrive": "microslip.model.drive",
    "StaticKinetic": "microslip.model.friction",
    "Stribeck": "microslip.model.friction",
    "TangentialSpring": "microslip.model.tangential",
    "HarmonicForce": "microslip.model.excitation",
    "HuntCrossley": "microslip.model.damping",
    "Model": "microslip.model.composition",
    "Parameters": "microslip.model.parameters",
    "PrescribedPenetration": "microslip.model.excitation",
    "UnsupportedModelError": "microslip.model.capabilities",
    "Viscous": "microslip.model.damping",
    "forced_response": "microslip.analysis.forced_response",
    "EffectiveFriction": "microslip.analysis.effective_friction",
    "effective_friction": "microslip.analysis.effective_friction",
    "effective_friction_curve": "microslip.analysis.effective_friction",
    "effective_friction_map": "microslip.analysis.effective_friction",
    "flat_punch_reduction": "microslip.analysis.flat_punch",
    "DriveCycle": "microslip.analysis.spring_stick_slip",
    "constant_normal_cycle": "microslip.analysis.stick_slip_closed_form",
    "stick_slip_drive": "microslip.analysis.spring_stick_slip",
    "stick_slip_drive_map": "microslip.analysis.spring_stick_slip",
    "friction_curve": "microslip.analysis.friction_curve",
    "periodic_orbit": "microslip.analysis.periodic",
    "SimulationResult": "microslip.results",
    "StickSlipCycle": "microslip.analysis.steady_state",
    "WorkLimitError": "microslip.budget",
    "free_frequency": "microslip.analysis.free_vibration",
    "free_period": "microslip.analysis.free_vibration",
    "mean_velocity": "microslip.analysis.steady_state",
    "normal_energy": "microslip.analysis.free_vibration",
    "simulate": "microslip.simulation",
    "stick_slip_cycle": "microslip.analysis.steady_state",
    "sweep": "microslip.sweeps",
    "turning_points": "microslip.analysis.free_vibration",
    "velocity_map": "microslip.sweeps",
}
_SUBPACKAGES = ("analysis", "budget", "integrators", "io", "model", "plotting", "sweeps")

__all__ = ["__version__", *sorted(_EXPORTS)]


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        value = getattr(importlib.import_module(_EXPORTS[name]), name)
    elif name in _SUBPACKAGES:
        value = importlib.import_module(f"microslip.{name}")
    else:
        raise AttributeError(f"module 'microslip' has no attribute {name!r}")
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS) | set(_SUBPACKAGES))
