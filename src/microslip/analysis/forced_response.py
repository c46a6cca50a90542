"""Forced response of the normal motion: periodic orbits continued in frequency or amplitude.

The branch of period-1 orbits (:mod:`microslip.analysis.periodic`) is followed by
pseudo-arclength continuation (:mod:`microslip.analysis.continuation`) in the scaled
shooting state u = (y/y0, ẏ/(y0 ω0)) at t = 0 and the scaled parameter λ = f/f0 (or
a/a_ref for the excitation amplitude, a_ref = m g for a force, y0 for a base motion).
It starts on the orbit reached from rest at the first value and ends exactly at the
second, the first time the branch gets there; so on a folded curve the two directions
end on different stable orbits inside the hysteresis band. Each point carries its
Floquet multipliers (stable, largest modulus), whether contact is lost, and whether a
multiplier left the unit circle through -1 (period doubling: that stretch is continued
as unstable period-1 orbits and flagged).
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import xarray as xr

from microslip.analysis.continuation import continue_branch
from microslip.analysis.normal_flow import (
    S_FLIGHT,
    S_NMAX,
    S_NMIN,
    S_SIZE,
    S_YMAX,
    S_YMIN,
    VARIATIONAL,
    propagate_each,
)
from microslip.analysis.periodic import (
    FREE_VIBRATION_INSTEAD,
    STABILITY_MARGIN,
    periodic_orbit,
    state_scale,
    steps_per_period,
)
from microslip.metadata import cf_static_attributes
from microslip.model.capabilities import require
from microslip.model.coefficients import EXCITATION_AMPLITUDE, EXCITATION_OMEGA
from microslip.model.composition import Model, as_model
from microslip.model.excitation import FREQUENCY_FACTOR, BaseMotion, HarmonicForce

__all__ = ["forced_response"]

MAX_POINTS_LIMIT = 100_000
# Relative step of the forward difference ∂F/∂λ: truncation ~h, rounding ~1e-16/h. It
# enters the tangent and the bordered Newton matrix only, never the residual, so the
# branch points are exact solutions whatever its error.
_DIFF_STEP = 1e-7


def _pair(name: str, value: Any) -> tuple[float, float]:
    try:
        a, b = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a pair (start, end) of numbers, got {value!r}") from None
    if not (math.isfinite(a) and math.isfinite(b)):
        raise ValueError(f"{name} must be finite, got {value!r}")
    if a == b:
        raise ValueError(f"{name} must have distinct start and end, got {value!r}")
    return a, b


def _check(
    model: Model, frequencies: Any, amplitudes: Any, max_points: Any
) -> tuple[str, float, float]:
    require(
        model,
        "forced_response",
        allowed={"excitation": (HarmonicForce, BaseMotion)},
        instead=(
            "a prescribed penetration has no normal dynamics to continue; "
            if model.excitation is not None
            else ""
        )
        + "give a HarmonicForce or BaseMotion excitation"
        + ("" if model.excitation is not None else f" ({FREE_VIBRATION_INSTEAD})"),
    )
    if (frequencies is None) == (amplitudes is None):
        raise ValueError(
            "give exactly one of frequencies=(f_start, f_end) or amplitudes=(a_start, a_end)"
        )
    if isinstance(max_points, bool) or not isinstance(max_points, int | np.integer):
        raise ValueError(f"max_points must be an int, got {max_points!r}")
    if not 2 <= max_points <= MAX_POINTS_LIMIT:
        raise ValueError(f"max_points must be in [2, {MAX_POINTS_LIMIT}], got {max_points!r}")
    if frequencies is not None:
        start, end = _pair("frequencies", frequencies)
        f0 = model.params.natural_frequency
        for f in (start, end):
            if not f0 / FREQUENCY_FACTOR <= f <= f0 * FREQUENCY_FACTOR:
                raise ValueError(
                    f"frequencies must lie in [1e-3 f0, 1e3 f0] = [{f0 / FREQUENCY_FACTOR:.6g}, "
                    f"{f0 * FREQUENCY_FACTOR:.6g}] Hz, got {f!r}"
                )
        return "frequency", start, end
    start, end = _pair("amplitudes", amplitudes)
    for a in (start, end):
        model.replace(**{"excitation.amplitude": a})  # the part's own range check
    return "amplitude", start, end


def forced_response(
    model: Model,
    *,
    frequencies: tuple[float, float] | None = None,
    amplitudes: tuple[float, float] | None = None,
    max_points: int = 2000,
    step: float = 0.01,
    max_step: float = 0.05,
) -> xr.Dataset:
    """Period-1 forced response of the normal motion, continued through folds.

    Parameters
    ----------
    model : Model
        With a HarmonicForce or BaseMotion excitation (its frequency is replaced along a
        frequency branch; its amplitude along an amplitude branch).
    frequencies : (f_start, f_end), optional
        Excitation frequencies [Hz], in [1e-3 f0, 1e3 f0], distinct.
    amplitudes : (a_start, a_end), optional
        Excitation amplitudes [N for a force, m for a base motion], at the model's
        frequency. Exactly one of ``frequencies`` and ``amplitudes``.
    max_points : int
        Cap on the number of branch points (the branch may then stop short of the end:
        a warning, and ``attrs["complete"] = 0``).
    step, max_step : float
        Initial and largest pseudo-arclength step in scaled variables.

    Returns
    -------
    xarray.Dataset
        On dim ``point``: frequency [Hz], excitation_amplitude [N or m], amplitude
        (y_max - y_min)/2 [m], y_min, y_max [m], N_min, N_max [N], stable,
        max_multiplier [1], contact_lost, period_doubling; attrs ``folds`` (indices of
        the points just past each fold), ``complete``, the model's attributes and the CF
        global attributes.
    """
    model = as_model(model)
    kind, start, end = _check(model, frequencies, amplitudes, max_points)
    params = model.params
    f0 = params.natural_frequency
    scale = state_scale(model)
    amp_unit = "N" if isinstance(model.excitation, HarmonicForce) else "m"
    a_ref = params.mass * params.g if amp_unit == "N" else params.static_deflection
    if kind == "frequency":
        first = model.replace(**{"excitation.frequency": start})
        lam_ref = f0
    else:
        first = model.replace(**{"excitation.amplitude": start})
        lam_ref = a_ref
    base = first.pack(0.0)

    def steps(lam: float) -> int:
        """Fixed steps over the period at λ: 96 per natural period, at least 64
        (:func:`~microslip.analysis.periodic.steps_per_period`), for the frequency of
        that point, not the lowest of the branch (a point at 2 f0 took the 400 steps a
        0.3 f0 start needs). Its flow and the one at λ + h for ∂F/∂λ take the same."""
        if kind == "amplitude":
            return steps_per_period(first)
        return steps_per_period(model, max(abs(lam) * lam_ref, f0 / FREQUENCY_FACTOR))

    def coefficients(lam: float) -> tuple[np.ndarray, float]:
        c = base.copy()
        if kind == "frequency":
            c[EXCITATION_OMEGA] = 2.0 * math.pi * lam * lam_ref
        else:
            c[EXCITATION_AMPLITUDE] = lam * lam_ref
        return c, 2.0 * math.pi / c[EXCITATION_OMEGA]

    def flows(lams: list[float], states: np.ndarray, record: bool, n_steps: np.ndarray):
        """(ends, Φs, summaries) of one period from states[i] [m, m/s] at lams[i] in
        n_steps[i] steps, the rows integrated side by side
        (:func:`normal_flow.propagate_each`)."""
        cs = np.empty((len(lams), base.size))
        periods = np.empty(len(lams))
        for i, lam in enumerate(lams):
            cs[i], periods[i] = coefficients(lam)
        ends = np.empty((len(lams), 2))
        phis = np.empty((len(lams), 2, 2))
        summaries = np.empty((len(lams), S_SIZE))
        propagate_each(cs, states, periods, n_steps, record, ends, phis, summaries, VARIATIONAL)
        return ends, phis, summaries

    def residual(u: np.ndarray, lam: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        # ∂F/∂λ by a forward difference: its flow runs beside the flow at λ (two cores).
        h = _DIFF_STEP * max(abs(lam), 1e-3)
        s = u * scale
        n_steps = np.full(2, steps(lam), dtype=np.int64)
        ends, phis, _ = flows([lam, lam + h], np.array([s, s]), False, n_steps)
        f = ends[0] / scale - u
        jac = phis[0] * scale[np.newaxis, :] / scale[:, np.newaxis] - np.eye(2)
        return f, jac, (ends[1] - ends[0]) / (scale * h)

    orbit = periodic_orbit(first, strict=False)
    branch = continue_branch(
        residual,
        orbit.y0_state / scale,
        start / lam_ref,
        end / lam_ref,
        step=step,
        max_step=max_step,
        max_points=max_points,
    )
    if not branch.complete:
        warnings.warn(
            f"forced_response stopped at max_points = {max_points} before reaching {end!r}",
            RuntimeWarning,
            stacklevel=2,
        )
    n_steps = np.array([steps(lam) for lam in branch.lam], dtype=np.int64)
    _ends, phis, summaries = flows(branch.lam, np.array(branch.u) * scale, True, n_steps)
    rows = [_point(phi, summary) for phi, summary in zip(phis, summaries, strict=True)]
    table = np.array(rows)
    lam = np.array(branch.lam) * lam_ref
    if kind == "frequency":
        freq, exc = lam, np.full(lam.size, float(first.excitation.amplitude))
    else:
        freq, exc = np.full(lam.size, float(first.excitation.frequency)), lam
    data = {
        "frequency": (freq, "Hz", "excitation frequency"),
        "excitation_amplitude": (exc, amp_unit, "excitation amplitude"),
        "amplitude": (
            0.5 * (table[:, 1] - table[:, 0]),
            "m",
            "response amplitude (y_max - y_min)/2",
        ),
        "y_min": (table[:, 0], "m", "lowest normal position over the period"),
        "y_max": (table[:, 1], "m", "highest normal position over the period"),
        "N_min": (table[:, 2], "N", "smallest normal force over the period"),
        "N_max": (table[:, 3], "N", "largest normal force over the period"),
        "stable": (table[:, 5] < 1.0 + STABILITY_MARGIN, "1", "orbit is stable (Floquet)"),
        "max_multiplier": (table[:, 5], "1", "largest Floquet multiplier modulus"),
        "contact_lost": (table[:, 4] > 0.0, "1", "normal force reaches zero on the orbit"),
        "period_doubling": (table[:, 6] > 0.0, "1", "a Floquet multiplier is real and below -1"),
    }
    ds = xr.Dataset(
        {
            name: ("point", values, {"units": units, "long_name": long_name})
            for name, (values, units, long_name) in data.items()
        }
    )
    ds.attrs.update(cf_static_attributes("microslip forced response of the normal motion"))
    ds.attrs.update(model.to_attrs())
    ds.attrs["continuation_parameter"] = kind
    ds.attrs["folds"] = np.array(branch.folds, dtype=np.int64)
    ds.attrs["complete"] = int(branch.complete)
    return ds


def _point(phi: np.ndarray, summary: np.ndarray) -> list[float]:
    """[y_min, y_max, N_min, N_max, contact lost, max |λ|, period doubling] of one orbit
    from its monodromy matrix Φ and its propagate summary."""
    mult = np.linalg.eigvals(phi)
    modulus = np.abs(mult)
    flipped = np.any(
        (modulus > 1.0 + STABILITY_MARGIN)
        & (mult.real < 0.0)
        & (np.abs(mult.imag) <= 1e-9 * modulus)
    )
    lost = summary[S_FLIGHT] > 0.0 or summary[S_NMIN] <= 0.0
    return [
        summary[S_YMIN],
        summary[S_YMAX],
        summary[S_NMIN],
        summary[S_NMAX],
        float(lost),
        float(modulus.max()),
        float(flipped),
    ]
