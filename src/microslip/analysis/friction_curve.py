"""Friction reduction by normal excitation: v at fixed F, or μ_eff at fixed v, against f.

Both come from the exact steady mean velocity on the stable periodic normal motion at each
excitation frequency (:mod:`microslip.analysis.forced_sliding`; docs/design.md). The mean
velocity v(F) does not decrease with F (the reflected process of G + F t/m dominates that
of G), so the force F_needed that gives a mean velocity v is found by bracketing on
[μ min N, μ N̄] and Brent's method; μ_eff = F_needed/(m g).
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np
import xarray as xr
from scipy.optimize import brentq

from microslip import validation as check
from microslip.analysis.forced_sliding import SlidingTable, mean_velocities
from microslip.analysis.periodic import FORCED, NotPeriodOneError
from microslip.analysis.sliding_tables import model_sliding_table
from microslip.model.capabilities import require
from microslip.model.composition import Model, as_model

__all__ = ["friction_curve"]


def _needed_force(table: SlidingTable, mu: float, velocity: float) -> float:
    """F [N] with steady mean velocity ``velocity`` [m/s] (μ N̄ where v(μ N̄) is smaller:
    just above that force the slider accelerates without bound)."""

    def excess(force: float) -> float:
        return float(mean_velocities(table, mu, np.array([force]))[0]) - velocity

    low = max(mu * table.min_normal_force, 0.0)
    high = mu * table.mean_normal_force
    if excess(high) <= 0.0:
        return high
    return float(brentq(excess, low, high, xtol=1e-14 * high, rtol=1e-13))


def friction_curve(
    model: Model,
    *,
    frequencies: Any,
    force: float | None = None,
    velocity: float | None = None,
) -> xr.Dataset:
    """Steady sliding on a normally excited contact against the excitation frequency.

    Parameters
    ----------
    model : Model
        A model with a normal excitation; its ``excitation.frequency`` is replaced by
        each of ``frequencies``.
    frequencies : array of float
        Excitation frequencies f [Hz] (each validated by the model's own range).
    force : float, optional
        Constant tangential force F [N] >= 0: the result holds ``mean_velocity`` [m/s].
    velocity : float, optional
        Mean sliding velocity v [m/s] > 0: the result holds ``force_needed`` [N], the
        effective friction ``mu_eff`` = F_needed/(m g) [1] and ``mu_eff_ratio`` = μ_eff/μ
        [1]. Where v is beyond the steady velocities (any F > μ N̄ accelerates the
        slider without bound) F_needed = μ N̄.

    Exactly one of ``force`` and ``velocity``. Frequencies whose response is not a
    stable period-1 orbit hold NaN (``period_one`` False, with a ``RuntimeWarning``).

    Returns
    -------
    xarray.Dataset
        On dimension ``frequency`` [Hz]; ``units`` on every variable; model attrs.
    """
    model = as_model(model)
    require(
        model, "friction_curve", allowed={"excitation": FORCED},
        instead="give the model an excitation (ms.HarmonicForce, ms.BaseMotion, ...)",
    )  # fmt: skip
    if (force is None) == (velocity is None):
        raise ValueError("give exactly one of force [N] and velocity [m/s]")
    freqs = check.real_array("frequencies", frequencies)
    if force is not None:
        force = check.force(model.params, force, nonnegative=True)
    else:
        velocity = check.real("velocity", velocity, minimum=0.0, strict=True)
    models = [model.replace(**{"excitation.frequency": float(f)}) for f in freqs]
    mu = model.params.mu
    values = np.full(freqs.size, np.nan)
    period_one = np.ones(freqs.size, dtype=bool)
    for i, m in enumerate(models):
        try:
            table = model_sliding_table(m)
        except NotPeriodOneError:
            period_one[i] = False
            continue
        if force is not None:
            values[i] = mean_velocities(table, mu, np.array([force]))[0]
        else:
            values[i] = _needed_force(table, mu, velocity)
    if not period_one.all():
        bad = freqs[~period_one]
        warnings.warn(
            f"no stable period-1 response at {bad.size} frequencies (first {bad[0]!r} Hz): "
            "NaN there",
            RuntimeWarning,
            stacklevel=2,
        )
    coords = {
        "frequency": ("frequency", freqs, {"units": "Hz", "long_name": "excitation frequency"})
    }
    flag = ("frequency", period_one, {"units": "1", "long_name": "stable period-1 response"})
    if force is not None:
        data = {
            "mean_velocity": (
                "frequency",
                values,
                {"units": "m s-1", "long_name": f"steady mean sliding velocity at F = {force!r} N"},
            ),
            "period_one": flag,
        }
    else:
        weight = model.params.mass * model.params.g
        data = {
            "force_needed": (
                "frequency",
                values,
                {"units": "N", "long_name": f"force giving mean velocity {velocity!r} m/s"},
            ),
            "mu_eff": ("frequency", values / weight, {"units": "1", "long_name": "F_needed/(m g)"}),
            "mu_eff_ratio": (
                "frequency",
                values / weight / mu if mu > 0 else values * np.nan,
                {"units": "1", "long_name": "mu_eff / mu"},
            ),
            "period_one": flag,
        }
    attrs = {
        **model.to_attrs(),
        "quantity": "mean_velocity" if force is not None else "mu_eff",
        "force": "none" if force is None else force,
        "velocity": "none" if velocity is None else velocity,
    }
    return xr.Dataset(data, coords=coords, attrs=attrs)
