"""Which parts each analysis supports; an unsupported combination is refused in one line.

Each analysis declares what it supports with :func:`require` at its entry point. The
table of docs/design.md lists them all. Refusals are :class:`UnsupportedModelError`
(a ``ValueError``), naming the analysis, the part and what to use instead.
"""

from __future__ import annotations

from microslip.model.composition import Model

__all__ = ["UnsupportedModelError", "require"]


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
    choice); slots not listed accept anything. ``instead`` says what to use.
    """
    for slot, types in allowed.items():
        part = getattr(model, slot)
        kind = None if part is None else type(part)
        if kind not in types:
            name = "None" if part is None else type(part).__name__
            raise UnsupportedModelError(f"{analysis} does not support {slot}={name}; {instead}")
