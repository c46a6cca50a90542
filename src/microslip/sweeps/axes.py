"""Validation of sweep axes: each value in its field's range, every combination a valid model.

Fields of :class:`Parameters` are checked vectorised on the grid of the Parameters axes (as
the constructor checks them); fields of parts (dotted names, "damping.ratio") by building
the :class:`Model`, whose own one-line message names the field and the value. The grid
quantities the work estimate needs (the period a time step resolves) are computed here
too, vectorised over the same grid.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import fields
from typing import Any

import numpy as np

from microslip import validation as check
from microslip.model.composition import Model
from microslip.model.parameters import FIELD_RANGES, Parameters, derived_log10
from microslip.model.tangential import MindlinSpring, TangentialSpring
from microslip.validation import MAX_AXIS_VALUES

# Values of part axes (dotted names) are checked by building the Model, once per value and
# per combination of the Parameters axes: at most this many Models are built.
MAX_MODEL_CHECKS = 200_000
_DERIVED_FIELDS = ("mass", "g", "area", "c_n", "m2")


def checked_axis(name: str, values: Any) -> np.ndarray:
    """One sweep axis: distinct finite reals, at most ``MAX_AXIS_VALUES`` of them."""
    size = np.size(values) if isinstance(values, np.ndarray) else None
    if size is not None and size > MAX_AXIS_VALUES:  # before any copy
        raise ValueError(f"{name}: {size} values; at most {MAX_AXIS_VALUES} are supported")
    array = check.real_array(name, values)
    if array.size > MAX_AXIS_VALUES:
        raise ValueError(f"{name}: {array.size} values; at most {MAX_AXIS_VALUES} are supported")
    ordered = np.sort(array)
    repeated = ordered[1:][ordered[1:] == ordered[:-1]]
    if repeated.size:  # a repeated value would make an ambiguous coordinate
        raise ValueError(f"{name}: value {float(repeated[0])!r} is given more than once")
    return array


def check_fields(params: Parameters, arrays: list[tuple[str, np.ndarray]]) -> None:
    """Each swept value within its field's own range (as the Parameters constructor
    checks it, vectorised); the first bad one is refused by the constructor's message."""
    specs = {f.name: f for f in fields(Parameters)}
    for name, values in arrays:
        if name not in specs:
            continue
        positive = specs[name].metadata["positive"]
        ok = values > 0.0 if positive else values >= 0.0
        low, high = FIELD_RANGES.get(name, (-math.inf, math.inf))
        ok &= (values >= low) & (values <= high)
        if not ok.all():
            params.replace(**{name: float(values[np.argmin(ok)])})


def check_part_axes(model: Model, arrays: list[tuple[str, np.ndarray]]) -> None:
    """Each value of a part axis valid (the Model's own message) for every combination of
    the Parameters axes (a part's ranges depend on the contact: f0, y0, m g)."""
    parts = [(name, values) for name, values in arrays if "." in name]
    if not parts:
        return
    fixed = [(name, values) for name, values in arrays if "." not in name]
    n_checks = math.prod(len(v) for _, v in fixed) * sum(len(v) for _, v in parts)
    if n_checks > MAX_MODEL_CHECKS:
        raise ValueError(
            f"the sweep needs {n_checks} model checks of its part axes; at most "
            f"{MAX_MODEL_CHECKS} are supported (fewer Parameters or part values)"
        )
    for combo in itertools.product(*(values for _, values in fixed)):
        changes = {name: float(v) for (name, _), v in zip(fixed, combo, strict=True)}
        base = model.replace(**changes) if changes else model
        for name, values in parts:
            for value in values:
                try:
                    base.replace(**{name: float(value)})
                except ValueError as error:
                    where = ", ".join(f"{k}={v!r}" for k, v in changes.items())
                    raise ValueError(f"{error}{f' at {where}' if where else ''}") from None


def _on_grid(name: str, value: float, param_axes, shape: tuple[int, ...]) -> np.ndarray:
    """Field ``name`` on the parameter grid of ``shape``: its swept values along its own
    axis, or its one ``value`` everywhere."""
    array = np.asarray(value, dtype=float)
    for axis, (swept, values) in enumerate(param_axes):
        if swept == name:
            index = [1] * len(shape)
            index[axis] = len(values)
            array = np.asarray(values, dtype=float).reshape(index)
    return np.broadcast_to(array, shape)


def field_grid(base: Parameters, param_axes) -> dict[str, np.ndarray]:
    """Each Parameters field, broadcast to the parameter axes' shape."""
    shape = tuple(len(values) for _, values in param_axes)
    return {name: _on_grid(name, getattr(base, name), param_axes, shape)
            for name in Parameters.field_names()}  # fmt: skip


def grid_logs(base: Parameters, param_axes) -> dict[str, np.ndarray]:
    grid = field_grid(base, param_axes)
    logs = derived_log10(*(grid[name] for name in _DERIVED_FIELDS))
    shape = grid["mass"].shape
    logs = {name: np.broadcast_to(value, shape) for name, value in logs.items()}
    logs["mg"] = np.broadcast_to(np.log10(grid["mass"]) + np.log10(grid["g"]), shape)
    return logs


def _part_grid(model: Model, param_axes, name: str, shape: tuple[int, ...]) -> np.ndarray:
    """Part field ``name`` ("slot.field") of every parameter set, broadcast to ``shape``."""
    slot, field = name.split(".", 1)
    return _on_grid(name, getattr(getattr(model, slot), field), param_axes, shape)


def kinetic_mu_grid(model: Model, param_axes) -> np.ndarray:
    """The kinetic friction coefficient μ_k [-] of every parameter set: the friction
    law's own (StaticKinetic) or ``mu`` (Coulomb)."""
    shape = tuple(len(values) for _, values in param_axes)
    if model.friction is not None and model.friction.owns_mu:
        return _part_grid(model, param_axes, "friction.mu_kinetic", shape)
    return field_grid(model.params, param_axes)["mu"]


def log_step_period(model: Model, param_axes) -> np.ndarray:
    """log10 of the period [s] a time step must resolve, per parameter set: the shortest
    of T0, the excitation period and the body's tangential oscillation on a compliant
    contact (:func:`microslip.budget.shortest_period`, vectorised over the grid)."""
    logs = grid_logs(model.params, param_axes)
    shape = logs["T0"].shape
    log_period = np.asarray(logs["T0"], dtype=float)
    if model.excitation is not None:
        frequency = _part_grid(model, param_axes, "excitation.frequency", shape)
        log_period = np.minimum(log_period, -np.log10(frequency))
    two_pi = math.log10(2.0 * math.pi)
    if isinstance(model.tangential, TangentialSpring):  # 2π sqrt(m / k_t)
        stiffness = _part_grid(model, param_axes, "tangential.stiffness", shape)
        mass = field_grid(model.params, param_axes)["mass"]
        log_period = np.minimum(log_period, two_pi + 0.5 * np.log10(mass / stiffness))
    elif isinstance(model.tangential, MindlinSpring):  # k_t = λ m2 m g / y0
        ratio = _part_grid(model, param_axes, "tangential.ratio", shape)
        grid = field_grid(model.params, param_axes)
        log_tangential = two_pi + 0.5 * (logs["y0"] - np.log10(ratio * grid["m2"] * grid["g"]))
        log_period = np.minimum(log_period, log_tangential)
    return log_period
