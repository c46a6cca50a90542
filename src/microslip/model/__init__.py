"""The model: parameters, the parts (contact, damping, excitation, friction, drive), their
composition (:class:`~microslip.model.composition.Model`) and the composed system.

Integrators import the compiled laws from here; nothing in this package knows about
time stepping. Names are imported on first use, so that ``microslip.model.parameters``
(what the command line needs to build its parser) loads no numba.
"""

from __future__ import annotations

import importlib
from typing import Any

_EXPORTS = {
    "PARAMETER_UNITS": "microslip.model.parameters",
    "Parameters": "microslip.model.parameters",
    "normal_reaction": "microslip.model.contact",
    "potential_energy": "microslip.model.contact",
    "reaction_array": "microslip.model.contact",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> Any:
    if name not in _EXPORTS:
        raise AttributeError(f"module 'microslip.model' has no attribute {name!r}")
    return getattr(importlib.import_module(_EXPORTS[name]), name)
