"""What every part of a :class:`~microslip.model.composition.Model` shares.

A part (a damping law, a normal excitation, ...) is a frozen dataclass of SI numbers.
Each field declares its unit, a description and its supported range through
:func:`part_field`; :class:`Part` checks them on construction, so a part can never hold
a non-finite or out-of-range value. Ranges that depend on the contact (the static
deflection y0, the natural frequency f0, m g) are checked by :meth:`Part.check`, which
the model calls with its :class:`~microslip.model.parameters.Parameters`.

A part writes its own slots of the coefficient vector in :meth:`Part.pack`
(:mod:`microslip.model.coefficients`); its compiled law lives in the same module.
"""

from __future__ import annotations

import functools
import math
from dataclasses import field, fields, replace
from typing import Any, ClassVar

import numpy as np

from microslip import validation as check
from microslip.model.parameters import Parameters

__all__ = ["REGISTRY", "Part", "part_field"]

#: Concrete part classes by slot name, in definition order: a class that defines its own
#: ``kind`` registers itself, so a new law is added in its own module only.
REGISTRY: dict[str, list[type]] = {}


def part_field(default: float, unit: str, description: str, low: float, high: float) -> Any:
    """A numeric field of a part: SI ``unit``, ``description``, range [low, high]."""
    return field(
        default=default,
        metadata={"unit": unit, "description": description, "range": (low, high)},
    )


class Part:
    """Mixin of the part dataclasses: field checks, units, replace, pack."""

    #: Name of the slot this part fills in a Model ("damping", "excitation", ...).
    slot: ClassVar[str] = ""
    #: True for a part that is the paper's choice spelled out (``Rigid()``, ``Coulomb()``):
    #: a model holding it is treated as holding ``None``.
    paper_equivalent: ClassVar[bool] = False
    #: True for a friction law with its own coefficients (``Parameters.mu`` unused).
    owns_mu: ClassVar[bool] = False

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if cls.slot and "kind" in cls.__dict__:
            REGISTRY.setdefault(cls.slot, []).append(cls)

    def __post_init__(self) -> None:
        for f in fields(self):  # type: ignore[arg-type]
            name = f"{self.slot}.{f.name}"
            value = check.real(name, getattr(self, f.name))
            low, high = f.metadata["range"]
            if not low <= value <= high:
                raise ValueError(
                    f"{name}={value!r} [{f.metadata['unit']}] is outside the supported "
                    f"range [{low:g}, {high:g}]"
                )
            object.__setattr__(self, f.name, value)

    @classmethod
    @functools.cache
    def field_names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))  # type: ignore[arg-type]

    @classmethod
    def field_unit(cls, name: str) -> str:
        return {f.name: f.metadata["unit"] for f in fields(cls)}[name]  # type: ignore[arg-type]

    @classmethod
    def field_description(cls, name: str) -> str:
        return {f.name: f.metadata["description"] for f in fields(cls)}[name]  # type: ignore[arg-type]

    def to_dict(self) -> dict[str, float]:
        return {name: getattr(self, name) for name in self.field_names()}

    def replace(self, **changes: float) -> Part:
        """A copy with some fields changed (validated like the constructor)."""
        unknown = sorted(set(changes) - set(self.field_names()))
        if unknown:
            raise ValueError(
                f"{type(self).__name__} has no field {unknown[0]!r}; "
                f"known: {', '.join(self.field_names())}"
            )
        return replace(self, **changes)  # type: ignore[type-var]

    def check(self, params: Parameters) -> None:
        """Refuse values outside the ranges that depend on the contact (ValueError)."""

    def pack(self, c: np.ndarray, params: Parameters) -> None:
        """Write this part's slots of the coefficient vector ``c``."""
        raise NotImplementedError


def relative_range(name: str, value: float, unit: str, low: float, high: float, what: str) -> None:
    """Refuse ``value`` outside [low, high] (bounds computed from the contact, ``what``
    says how), naming the field, its value and the bounds."""
    if not low <= value <= high:
        raise ValueError(
            f"{name}={value!r} {unit} is outside the supported range "
            f"[{low:.6g}, {high:.6g}] {unit} ({what})"
        )


def angular(frequency: float) -> float:
    """ω = 2π f [rad/s] for f [Hz]."""
    return 2.0 * math.pi * frequency
