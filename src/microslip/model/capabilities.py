"""Which parts each analysis supports; an unsupported combination is refused in one line.

Each analysis declares what it supports with :func:`require` at its entry point. The
table of docs/design.md lists them all. Refusals are :class:`UnsupportedModelError`
(a ``ValueError``), naming the analysis, the part and what to use instead.
"""

from __future__ import annotations

from microslip.model.composition import Model

__all__ = ["TANGENTIAL_SLOTS", "UnsupportedModelError", "require"]

#: The slots of the tangential side. An analysis that does not list one of them in
#: ``allowed`` supports only the paper's choice there (rigid contact, Coulomb friction,
#: a constant force given per call): a new tangential law is refused until an analysis
#: says it supports it.
TANGENTIAL_SLOTS = ("tangential", "friction", "drive")


class UnsupportedModelError(ValueError):
    """The analysis does not support a part of the model (the message says what to use)."""


def require(
    model: Model,
    analysis: str,
    *,
    allowed: dict[str, tuple[type | None, ...]],
    instead: str,
) -> None:
    """Refuse ``model`` unless each slot's part is of an allowed type.

    ``allowed`` maps a slot name to the allowed part types (``None``: the paper's
    choice, which also stands for ``Rigid()`` and ``Coulomb()``). The normal slots not
    listed accept anything; the tangential slots not listed (:data:`TANGENTIAL_SLOTS`)
    accept only the paper's choice. ``instead`` says what to use.
    """
    allowed = {**{slot: (None,) for slot in TANGENTIAL_SLOTS}, **allowed}
    for slot, types in allowed.items():
        part = getattr(model, slot)
        kind = None if model.paper_choice(slot) else type(part)
        if kind not in types:
            name = "None" if part is None else type(part).__name__
            raise UnsupportedModelError(f"{analysis} does not support {slot}={name}; {instead}")
