"""The model: parameters, the normal contact law, the friction law and the drive.

Integrators import the compiled laws from here; nothing in this package knows about
time stepping.
"""

from microslip.model.contact import normal_reaction, potential_energy, reaction_array
from microslip.model.parameters import PARAMETER_UNITS, Parameters

__all__ = [
    "PARAMETER_UNITS",
    "Parameters",
    "normal_reaction",
    "potential_energy",
    "reaction_array",
]
