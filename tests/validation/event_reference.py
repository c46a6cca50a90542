"""The event method as the reference of a time sweep: x(T)/T of ``simulate`` (adaptive
DOP853 steps, located events, rtol 1e-12) at every point of a sweep's result."""

from __future__ import annotations

import numpy as np

import microslip as ms


def error_vs_event(model, axes, amplitudes, forces, values, duration) -> float:
    """The largest |sweep - event| of x(T)/T over the points of ``values``, relative to
    the largest |x(T)/T| of the event method. ``values`` is the sweep's (field, force)
    array for one swept field ``axes`` ({field: levels}, a forced model), else its
    (force, amplitude) array over ``amplitudes`` [m]."""
    if axes:
        ((field, levels),) = axes.items()
        runs = [(model.replace(**{field: a}), None, values[j]) for j, a in enumerate(levels)]
    else:
        runs = [(model, a, values[:, j]) for j, a in enumerate(amplitudes)]
    errors, reference = [], []
    for run_model, amplitude, column in runs:
        for i, force in enumerate(forces):
            event = ms.simulate(run_model, force=float(force), amplitude=amplitude,
                                duration=duration, rtol=1e-12)  # fmt: skip
            reference.append(event.x[-1] / duration)
            errors.append(abs(column[i] - reference[-1]))
    scale = float(np.max(np.abs(reference)))
    assert scale > 0.0
    return max(errors) / scale


def time_sweep_error(model, axes, amplitudes, forces, duration) -> float:
    """:func:`error_vs_event` of ``sweep(method="time")`` over the forces [N] and the one
    swept field ``axes`` (a forced model) or the ``amplitudes`` [m], for ``duration``
    [s]; its values must be finite."""
    result = ms.sweep(model, axes, force=forces, amplitude=amplitudes, method="time",
                      duration=duration)  # fmt: skip
    values = np.asarray(result.values)
    assert np.isfinite(values).all()
    return error_vs_event(model, axes, amplitudes, forces, values, duration)
