"""Parsing of value ranges given on the command line or in a configuration file."""

from __future__ import annotations

import math

import numpy as np

from microslip.validation import MAX_AXIS_VALUES

__all__ = ["MAX_AXIS_VALUES", "parse_values"]


def parse_values(name: str, text: str) -> np.ndarray:
    """Values from ``start:stop:count`` (inclusive linspace), ``a,b,c`` or one number.

    Raises ``ValueError`` naming ``name`` for empty or reversed ranges, counts < 1 or
    above ``MAX_AXIS_VALUES`` (1e7; checked before any array is made), repeated values,
    NaN, infinities, or anything that is not a plain number (Python's digit separators,
    as in ``1_0``, are refused rather than read as 10).
    """
    text = str(text).strip()
    if not text:
        raise ValueError(f"{name}: empty value")
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            raise ValueError(f"{name}: expected start:stop:count, got {text!r}")
        start, stop = (_number(name, p) for p in parts[:2])
        count_text = parts[2].strip()
        if "_" in count_text:
            raise ValueError(f"{name}: count must be an integer, got {parts[2]!r}")
        try:
            count = int(count_text)
        except ValueError:
            raise ValueError(f"{name}: count must be an integer, got {parts[2]!r}") from None
        if count < 1:
            raise ValueError(f"{name}: count must be >= 1, got {count}")
        if count > MAX_AXIS_VALUES:
            raise ValueError(
                f"{name}: count {count_text} is more than the {MAX_AXIS_VALUES} values supported"
            )
        if stop < start:
            raise ValueError(f"{name}: reversed range {text!r} (stop < start)")
        if count == 1 and stop != start:
            raise ValueError(f"{name}: count 1 needs start == stop, got {text!r}")
        if count > 1 and stop == start:
            raise ValueError(f"{name}: empty range {text!r} (start == stop with count > 1)")
        return np.linspace(start, stop, count)
    if text.count(",") >= MAX_AXIS_VALUES:
        raise ValueError(f"{name}: more than the {MAX_AXIS_VALUES} values supported")
    values = np.array([_number(name, p) for p in text.split(",")])
    if np.unique(values).size != values.size:
        raise ValueError(f"{name}: repeated values in {text!r}")
    return values


def _number(name: str, text: str) -> float:
    if "_" in text:  # float() reads "1_0" as 10
        raise ValueError(f"{name}: not a number: {text!r}")
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"{name}: not a number: {text!r}") from None
    if not math.isfinite(value):
        raise ValueError(f"{name}: value must be finite, got {text!r}")
    return value
