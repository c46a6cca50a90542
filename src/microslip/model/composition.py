"""``Model``: a frozen composition of the parts of the slider–slideway system.

The paper's model (Grudziński & Kostek 2005) is ``Model(Parameters())``: elastic
power-law contact (2.3), no damping, free normal vibration, rigid tangential contact,
Coulomb friction (2.2), constant tangential force (Sec. 4). Each part is an optional
frozen object (``None`` is the paper's choice):

    damping     Viscous(ratio) | HuntCrossley(ratio)                 model/damping.py
    excitation  HarmonicForce | BaseMotion | PrescribedPenetration   model/excitation.py
    tangential  Rigid() | TangentialSpring(stiffness) | MindlinSpring(ratio)
                                                                     model/tangential.py
    friction    Coulomb() | StaticKinetic(mu_static, mu_kinetic) | Stribeck(...)
                                                                     model/friction.py
    drive       ConstantForce(force) | HarmonicDrive | SpringDrive | PrescribedVelocity
                                                                     model/drive.py

``Rigid()`` and ``Coulomb()`` are the paper's choices spelled out (as ``None``). With
``drive=None`` the constant force is given to each analysis (``force=``).

Every numeric field of every part has a dotted name ("damping.ratio",
"excitation.frequency"); the contact constants are the bare Parameters names ("mu",
"m2", ...; "params.mu" is accepted too). :meth:`Model.replace` and the sweeps use them.
See docs/design.md.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from microslip import validation as check
from microslip.model import damping, drive, excitation, friction, tangential  # noqa: F401
from microslip.model.coefficients import pack as pack_paper
from microslip.model.damping import HuntCrossley, Viscous
from microslip.model.drive import ConstantForce, HarmonicDrive, PrescribedVelocity, SpringDrive
from microslip.model.excitation import BaseMotion, HarmonicForce, PrescribedPenetration
from microslip.model.friction import Coulomb, StaticKinetic, Stribeck
from microslip.model.parameters import Parameters
from microslip.model.parts import REGISTRY, Part
from microslip.model.tangential import MindlinSpring, Rigid, TangentialSpring

__all__ = ["PART_TYPES", "Model", "as_model"]

#: The slots of a Model and the part types each one accepts (None: the paper's choice);
#: filled by the part modules themselves (:data:`microslip.model.parts.REGISTRY`).
PART_TYPES: dict[str, tuple[type, ...]] = {
    slot: tuple(REGISTRY[slot])
    for slot in ("damping", "excitation", "tangential", "friction", "drive")
}


@dataclass(frozen=True)
class Model:
    """The slider on a compliant contact, as a composition of parts.

    Attributes
    ----------
    params : Parameters
        Contact and friction constants (m, g, S, c_n, m2, μ); the paper's by default.
    damping : Viscous or HuntCrossley, optional
        Normal damping of the contact; ``None``: the paper's elastic contact.
    excitation : HarmonicForce, BaseMotion or PrescribedPenetration, optional
        Normal excitation; ``None``: the paper's free normal vibration.
    tangential : Rigid, TangentialSpring or MindlinSpring, optional
        Tangential contact; ``None`` or ``Rigid()``: the paper's rigid contact.
    friction : Coulomb, StaticKinetic or Stribeck, optional
        Friction law; ``None`` or ``Coulomb()``: Coulomb with ``params.mu`` (eq. 2.2).
    drive : ConstantForce, HarmonicDrive, SpringDrive or PrescribedVelocity, optional
        Tangential drive; ``None``: a constant force given to each analysis
        (``force=``), the paper's Sec. 4.
    """

    params: Parameters = field(default_factory=Parameters)
    damping: Viscous | HuntCrossley | None = None
    excitation: HarmonicForce | BaseMotion | PrescribedPenetration | None = None
    tangential: Rigid | TangentialSpring | MindlinSpring | None = None
    friction: Coulomb | StaticKinetic | Stribeck | None = None
    drive: ConstantForce | HarmonicDrive | SpringDrive | PrescribedVelocity | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.params, Parameters):
            raise ValueError(
                f"params must be a microslip.Parameters, got {type(self.params).__name__}"
            )
        for slot, types in PART_TYPES.items():
            part = getattr(self, slot)
            if part is not None and not isinstance(part, types):
                names = ", ".join(f"ms.{t.__name__}" for t in types)
                raise ValueError(
                    f"{slot} must be one of {names} or None, got {type(part).__name__}"
                )
            if part is not None:
                part.check(self.params)
        if isinstance(self.friction, Stribeck) and self.is_compliant:
            raise ValueError(
                "friction=Stribeck needs tangential=Rigid(): a massless contact point under "
                "velocity-weakening friction has no unique motion "
                "(docs/theory/friction_reduction.md); use StaticKinetic with a compliant contact"
            )

    # -- parts ---------------------------------------------------------------------------
    def parts(self) -> dict[str, Part | None]:
        """The parts by slot name (``None`` where the paper's choice is kept)."""
        return {slot: getattr(self, slot) for slot in PART_TYPES}

    def paper_choice(self, slot: str) -> bool:
        """True when ``slot`` holds the paper's choice (``None``, ``Rigid()``, ``Coulomb()``)."""
        part = getattr(self, slot)
        return part is None or part.paper_equivalent

    @property
    def is_paper(self) -> bool:
        """True when every part is the paper's choice (only ``params`` may differ)."""
        return all(self.paper_choice(slot) for slot in PART_TYPES)

    @property
    def is_compliant(self) -> bool:
        """True with a compliant tangential contact (a contact point and a spring)."""
        return not self.paper_choice("tangential")

    @property
    def is_kinematic(self) -> bool:
        """True with a prescribed body velocity (:class:`PrescribedVelocity`)."""
        return isinstance(self.drive, PrescribedVelocity)

    def resolve_force(self, force: float | None) -> float:
        """The constant force [N] to pack: ``force`` (required) with ``drive=None``; the
        drive's own force with ``ConstantForce``; 0 with any other drive (then ``force``
        must not be given)."""
        if self.drive is None:
            if force is None:
                raise ValueError(
                    "force is required: the model has no drive (give force=F in N, or "
                    "drive=ms.ConstantForce(F) / another drive)"
                )
            return check.force(self.params, force)
        if force is not None:
            raise ValueError(
                f"force={force!r} conflicts with the model's drive "
                f"{type(self.drive).__name__}: leave force out (the drive sets it)"
            )
        return self.drive.force if isinstance(self.drive, ConstantForce) else 0.0

    @property
    def is_periodically_forced(self) -> bool:
        """True with a normal excitation (the steady normal motion has its period)."""
        return self.excitation is not None

    def describe(self) -> str:
        """One line naming the parts, e.g. ``damping=Viscous(ratio=0.03), excitation=None``."""
        out = []
        for slot, part in self.parts().items():
            if part is None:
                out.append(f"{slot}=None")
            else:
                values = ", ".join(f"{k}={v!r}" for k, v in part.to_dict().items())
                out.append(f"{slot}={type(part).__name__}({values})")
        return ", ".join(out)

    # -- dotted names -------------------------------------------------------------------
    def numeric_fields(self) -> dict[str, tuple[float, str]]:
        """Every numeric field by dotted name: (value, SI unit)."""
        out = {
            name: (getattr(self.params, name), Parameters.field_unit(name))
            for name in Parameters.field_names()
        }
        for slot, part in self.parts().items():
            if part is None:
                continue
            for name in part.field_names():
                out[f"{slot}.{name}"] = (getattr(part, name), part.field_unit(name))
        return out

    def dotted_names(self) -> tuple[str, ...]:
        """The keys of :meth:`numeric_fields`, without their values and units (a sweep
        replaces a field per set-up, and this test of its name was most of that cost)."""
        names = list(Parameters.field_names())
        for slot, part in self.parts().items():
            if part is not None:
                names.extend(f"{slot}.{name}" for name in part.field_names())
        return tuple(names)

    def unit(self, name: str) -> str:
        """SI unit of the field with dotted ``name``."""
        return self.numeric_fields()[self.canonical_name(name)][1]

    def canonical_name(self, name: str) -> str:
        """``name`` as listed by :meth:`numeric_fields` ("params.mu" -> "mu")."""
        if not isinstance(name, str):
            raise ValueError(f"a field name must be a string, got {name!r}")
        short = name.removeprefix("params.")
        if short == "mu" and self.friction is not None and self.friction.owns_mu:
            raise ValueError(
                f"{name!r} is not used with friction={type(self.friction).__name__}: change "
                "friction.mu_static / friction.mu_kinetic instead"
            )
        if short in self.dotted_names():
            return short
        slot = name.split(".", 1)[0]
        if slot in PART_TYPES and getattr(self, slot) is None:
            raise ValueError(
                f"{name!r}: this model has no {slot} part (give one, e.g. "
                f"{PART_TYPES[slot][0].__name__}(...), before sweeping its fields)"
            )
        raise ValueError(f"unknown model field {name!r}; known: {', '.join(self.numeric_fields())}")

    def replace(self, **changes: Any) -> Model:
        """A copy with fields changed by dotted name, e.g.
        ``model.replace(**{"damping.ratio": 0.05, "mu": 0.2})``; a part given by its slot
        name (``damping=ms.Viscous(0.1)`` or ``damping=None``) replaces the whole part."""
        params_changes: dict[str, float] = {}
        part_changes: dict[str, dict[str, float]] = {}
        whole: dict[str, Any] = {}
        for name, value in changes.items():
            if name in PART_TYPES or name == "params":
                whole[name] = value
                continue
            name = self.canonical_name(name)
            if "." in name:
                slot, attr = name.split(".", 1)
                part_changes.setdefault(slot, {})[attr] = value
            else:
                params_changes[name] = value
        current = {"params": self.params, **self.parts(), **whole}
        if params_changes:
            current["params"] = current["params"].replace(**params_changes)
        for slot, values in part_changes.items():
            current[slot] = current[slot].replace(**values)
        return Model(**current)

    # -- compiled form --------------------------------------------------------------------
    def pack(self, force: float = 0.0) -> np.ndarray:
        """The coefficient vector of the compiled laws (:mod:`microslip.model.coefficients`)
        for a constant tangential force ``force`` [N]."""
        c = pack_paper(self.params, force)
        for part in self.parts().values():
            if part is not None:
                part.pack(c, self.params)
        return c

    def to_attrs(self) -> dict[str, Any]:
        """Flat attributes for NetCDF files: ``param_<field>``, ``<slot>`` (the part's
        class name or "none") and ``<slot>_<field>`` for each part field."""
        attrs: dict[str, Any] = {f"param_{k}": v for k, v in self.params.to_dict().items()}
        for slot, part in self.parts().items():
            attrs[slot] = "none" if part is None else type(part).__name__
            if part is not None:
                attrs.update({f"{slot}_{k}": v for k, v in part.to_dict().items()})
        return attrs


def as_model(value: Model | Parameters | None) -> Model:
    """A Model from a Model, a Parameters (the paper's parts) or None (the paper's data)."""
    if value is None:
        return Model()
    if isinstance(value, Model):
        return value
    if isinstance(value, Parameters):
        return Model(value)
    raise ValueError(
        f"expected a microslip.Model or microslip.Parameters, got {type(value).__name__}"
    )
