"""Effective-friction sweeps: μ_eff over any numeric fields of a kinematically driven model.

``ms.sweep(m, {"drive.velocity": v, "excitation.amplitude": a})`` on a model with
``drive=PrescribedVelocity`` lands here: the quantity is μ_eff = <F_t>/<N> of
:func:`microslip.analysis.effective_friction.effective_friction`
(docs/theory/friction_reduction.md), not a mean velocity, and there is no force axis.
The drive speed, when swept, is the innermost loop: one normal motion per combination
of the other axes is shared by every speed (:func:`effective_friction_curve`).
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from typing import Any

import numpy as np
import xarray as xr

from microslip.model.composition import Model
from microslip.sweeps.axes import checked_axis

__all__ = ["VELOCITY", "friction_sweep"]

VELOCITY = "drive.velocity"


def friction_sweep(
    model: Model,
    axes: Mapping[str, Any],
    *,
    amplitude: Any = None,
    progress: bool = False,
) -> xr.DataArray:
    """μ_eff [-] over the product of ``axes`` (dotted field names -> values, SI units).

    ``amplitude`` (free normal vibration only): A = y0 - y_min [m], a value or an array
    (then the last dimension, "amplitude"). Returns a DataArray ``mu_eff`` with dims the
    axes in order (plus "amplitude"), units "1", coordinates with their units.
    """
    from microslip.analysis.effective_friction import (
        effective_friction,
        effective_friction_curve,
    )

    names = [model.canonical_name(name) for name in axes]
    values = [checked_axis(name, axes[raw]) for name, raw in zip(names, axes, strict=True)]
    amplitudes = None if amplitude is None else np.atleast_1d(np.asarray(amplitude, dtype=float))
    all_names = names + (["amplitude"] if amplitudes is not None and np.ndim(amplitude) else [])
    all_values = values + ([amplitudes] if "amplitude" in all_names else [])
    if len(set(all_names)) != len(all_names):
        raise ValueError(f"an axis is given twice: {all_names}")
    shape = tuple(v.size for v in all_values)
    out = np.empty(shape)
    inner = all_names.index(VELOCITY) if VELOCITY in all_names else None
    outer = [k for k in range(len(all_names)) if k != inner]
    combos = list(itertools.product(*(range(shape[k]) for k in outer)))
    bar = _progress(len(combos), progress)
    for combo in combos:
        changes = {}
        amp = None if amplitudes is None else float(amplitudes[0])
        for k, i in zip(outer, combo, strict=True):
            if all_names[k] == "amplitude":
                amp = float(all_values[k][i])
            else:
                changes[all_names[k]] = float(all_values[k][i])
        point = model.replace(**changes) if changes else model
        index: list[Any] = [None] * len(all_names)
        for k, i in zip(outer, combo, strict=True):
            index[k] = i
        if inner is None:
            out[tuple(index)] = effective_friction(point, amplitude=amp).mu_eff
        else:
            index[inner] = slice(None)
            curve = effective_friction_curve(point, all_values[inner], amplitude=amp)
            out[tuple(index)] = curve["mu_eff"].values
        if bar is not None:
            bar.update(1)
    if bar is not None:
        bar.close()
    coords = {}
    for name, vals in zip(all_names, all_values, strict=True):
        unit = "m" if name == "amplitude" else model.unit(name)
        coords[name] = (name, vals, {"units": unit})
    result = xr.DataArray(
        out,
        dims=all_names,
        coords=coords,
        name="mu_eff",
        attrs={"units": "1", "long_name": "effective friction coefficient <F_t>/<N>"},
    )
    result.attrs.update(model.to_attrs())
    return result


def _progress(total: int, enabled: bool):
    if not enabled:
        return None
    from tqdm import tqdm

    return tqdm(total=total, unit="curve", desc="mu_eff", leave=False)
