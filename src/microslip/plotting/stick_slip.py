"""Spring-driven stick–slip with and without normal vibration
(docs/theory/stick_slip_drive.md).

- :func:`stick_slip_model`: the rigid contact with StaticKinetic friction pushed by a
  SpringDrive, scaled on the given parameters.
- :func:`spring_stick_slip_figure`: drive force, friction limit and body velocity over the
  last established cycles, for the free normal vibration amplitudes
  :data:`STICK_SLIP_AMPLITUDES`, the mean force drop marked.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from microslip.model.composition import Model
from microslip.model.drive import SpringDrive
from microslip.model.friction import StaticKinetic
from microslip.model.parameters import Parameters
from microslip.plotting.friction import si_unit
from microslip.plotting.scales import Unit, require_friction

__all__ = ["STICK_SLIP_AMPLITUDES", "spring_stick_slip_figure", "stick_slip_model"]

_BOX = {"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.85}

STICK_SLIP_MU_RATIO = 1.5  # μ_s / μ_k, μ_k = params.mu
STICK_SLIP_STIFFNESS = 1e-3  # k_d / K_n: the slip lasts ~ (1/2) sqrt(K_n/k_d) T0 ≈ 16 T0
STICK_SLIP_SPEED = 0.1  # v_d / ((μ_s − μ_k) g / Ω), Ω = sqrt(k_d/m)
STICK_SLIP_AMPLITUDES = (0.0, 0.1, 0.3)  # A / y0 of the free normal vibration
STICK_SLIP_REGULAR = 0.1  # force drops regular (arrow drawn): std <= 10 % of the mean


def stick_slip_model(params: Parameters) -> Model:
    """Rigid contact, StaticKinetic(μ_s = 1.5 μ, μ_k = μ), SpringDrive(k_d = 1e-3 K_n,
    v_d = 0.1 (μ_s − μ_k) g / sqrt(k_d/m))."""
    mu_k = params.mu
    mu_s = min(STICK_SLIP_MU_RATIO * mu_k, 10.0)
    k_d = STICK_SLIP_STIFFNESS * params.contact_stiffness
    rate = (STICK_SLIP_MU_RATIO - 1.0) * mu_k * params.g  # (μ_s − μ_k) g, μ_s unclipped
    v_d = STICK_SLIP_SPEED * rate / math.sqrt(k_d / params.mass)
    return Model(
        params,
        friction=StaticKinetic(mu_static=mu_s, mu_kinetic=mu_k),
        drive=SpringDrive(stiffness=k_d, velocity=v_d),
    )


def _stick_slip_case(model: Model, amplitude: float) -> dict[str, Any]:
    """The established motion of :func:`stick_slip_drive` at the free-vibration amplitude
    ``amplitude`` [m]: its last cycles (time from the first of their slip starts) and
    statistics; the first slip of the history located for the force-drop arrow."""
    from microslip.analysis.spring_stick_slip import stick_slip_drive

    cycle = stick_slip_drive(model, amplitude=amplitude)
    h = cycle.history
    moving = np.r_[0, (h.direction != 0).astype(np.int8)]  # the history starts slipping
    starts = np.flatnonzero(np.diff(moving) == 1)
    stops = np.flatnonzero(np.diff(moving) == -1)
    later = stops[stops > starts[0]] if starts.size else stops
    nan = math.nan
    return {
        "time": h.t - h.t[0], "drive_force": h.drive_force, "friction_limit": h.friction_limit,
        "xdot": h.xdot, "direction": h.direction.astype(float),
        "force_drop": cycle.force_drop, "force_drop_std": cycle.force_drop_std,
        "period": cycle.period, "slips_per_normal_period": cycle.slips_per_normal_period,
        "slip_start_time": h.t[starts[0]] - h.t[0] if later.size else nan,
        "stick_start_time": h.t[later[0]] - h.t[0] if later.size else nan,
    }  # fmt: skip


def spring_stick_slip_figure(params: Parameters) -> tuple[Figure, xr.Dataset]:
    """Drive force, friction limit μ_s N and body velocity against time over the last
    three established cycles of :func:`~microslip.analysis.spring_stick_slip.stick_slip_drive`
    for the model of :func:`stick_slip_model`, without normal vibration and with the
    paper's free vibration of amplitude A (:data:`STICK_SLIP_AMPLITUDES`); the mean
    force drop marked at the first slip drawn. Without vibration it is 2 (μ_s − μ_k) m g."""
    require_friction(params, "spring_stick_slip")
    model = stick_slip_model(params)
    drive, law = model.drive, model.friction
    amplitudes = np.array(STICK_SLIP_AMPLITUDES) * params.static_deflection
    runs = [_stick_slip_case(model, float(a)) for a in amplitudes]

    f_unit = si_unit([law.mu_static * params.mass * params.g], "N")
    v_unit = si_unit(np.concatenate([r["xdot"] for r in runs]), "m s-1")
    fig = Figure(figsize=(4.2 * len(runs) + 0.6, 6.0), layout="constrained")
    axes = fig.subplots(2, len(runs), sharex="col", sharey="row", squeeze=False)
    for k, (run, a) in enumerate(zip(runs, STICK_SLIP_AMPLITUDES, strict=True)):
        top, low = axes[0, k], axes[1, k]
        t_unit = si_unit(run["time"], "s")
        t = run["time"] * t_unit.factor
        top.plot(t, run["friction_limit"] * f_unit.factor, color="0.6", lw=0.6, alpha=0.6,
                 label="friction limit μ_s N")  # fmt: skip
        top.plot(t, run["drive_force"] * f_unit.factor, color="C0", lw=1.4,
                 label="spring force F = k_d (v_d t − x)")  # fmt: skip
        top.axhline(law.mu_kinetic * params.mass * params.g * f_unit.factor, color="0.3",
                    lw=0.8, ls=":", label="μ_k m g")  # fmt: skip
        low.plot(t, run["xdot"] * v_unit.factor, color="C1", lw=1.0)
        top.set_title("no normal vibration" if a == 0 else f"free vibration A = {a:g} y0",
                      fontsize=10)  # fmt: skip
        _mark_drop(top, run, t_unit.factor, f_unit)
        low.set_xlabel(t_unit.label("t − t_slip"))
        for ax in (top, low):
            ax.grid(True, lw=0.4, alpha=0.5)
    axes[0, 0].set_ylabel(f_unit.label("tangential force"))
    axes[1, 0].set_ylabel(v_unit.label("body velocity dx/dt"))
    axes[0, 0].legend(fontsize=7, loc="lower right")
    fig.suptitle(
        f"spring-driven stick–slip, last cycles: k_d = {drive.stiffness:.3g} N/m, v_d = "
        f"{drive.velocity * v_unit.factor:.3g} {v_unit.symbol}, μ_s = {law.mu_static:.3g}, "
        f"μ_k = {law.mu_kinetic:.3g}", fontsize=10,
    )  # fmt: skip
    return fig, _stick_slip_dataset(model, amplitudes, runs)


def _mark_drop(ax: Axes, run: dict[str, Any], t_factor: float, f_unit: Unit) -> None:
    """A double arrow of the mean force drop from the force at the first drawn slip's
    start, at the instant it sticks again, labelled with the drop; for irregular drops
    (standard deviation above 10 % of the mean) a note instead."""
    drop, spread = run["force_drop"], run["force_drop_std"]
    if not (np.isfinite(drop) and spread <= STICK_SLIP_REGULAR * abs(drop)):
        ax.text(0.03, 0.04, "no regular stick–slip: micro-slips near the minima of N,\n"
                f"force drops {drop * f_unit.factor:.2g} ± {spread * f_unit.factor:.2g} "
                f"{f_unit.symbol}", transform=ax.transAxes, fontsize=8, color="tab:red",
                bbox=_BOX)  # fmt: skip
        return
    t0, t1 = run["slip_start_time"] * t_factor, run["stick_start_time"] * t_factor
    high = np.interp(run["slip_start_time"], run["time"], run["drive_force"]) * f_unit.factor
    low = high - run["force_drop"] * f_unit.factor
    ax.plot([t0, t1], [high, high], color="tab:red", lw=0.8, ls=":")
    ax.annotate("", xy=(t1, low), xytext=(t1, high),
                arrowprops={"arrowstyle": "<->", "color": "tab:red", "lw": 1.2})  # fmt: skip
    ax.annotate(f"ΔF = {run['force_drop'] * f_unit.factor:.3g} {f_unit.symbol}",
                xy=(t1, 0.5 * (high + low)), xytext=(6, 0), textcoords="offset points",
                color="tab:red", fontsize=8, va="center",
                bbox=_BOX)  # fmt: skip


def _stick_slip_dataset(model: Model, amplitudes: np.ndarray, runs: list[dict]) -> xr.Dataset:
    """The runs one per ``case``, padded with NaN to the longest on ``sample``."""
    size = max(r["time"].size for r in runs)

    def pad(key: str) -> np.ndarray:
        out = np.full((len(runs), size), np.nan)
        for k, run in enumerate(runs):
            out[k, : run[key].size] = run[key]
        return out

    dims = ("case", "sample")
    series = {"time": ("s", "time t - t_slip from a slip start, established motion"),
              "drive_force": ("N", "spring force k_d (v_d t - x)"),
              "friction_limit": ("N", "friction limit mu_s N"),
              "xdot": ("m s-1", "body velocity"),
              "direction": ("1", "slip direction (0 stick; NaN: padding)")}  # fmt: skip
    data = {k: (dims, pad(k), {"units": u, "long_name": n}) for k, (u, n) in series.items()}
    scalars = {"force_drop": ("N", "mean force drop F(slip start) - F(slip end)"),
               "force_drop_std": ("N", "standard deviation of the force drop"),
               "period": ("s", "mean time between slip starts"),
               "slips_per_normal_period": ("1", "normal vibration period / period"),
               "slip_start_time": ("s", "start of the first slip drawn (time axis)"),
               "stick_start_time": ("s", "its end, where the force-drop arrow is")}  # fmt: skip
    for key, (unit, name) in scalars.items():
        values = np.array([r[key] for r in runs], dtype=float)
        data[key] = ("case", values, {"units": unit, "long_name": name})
    amp = {"units": "m", "long_name": "free normal vibration amplitude A = y0 - y_min"}
    ds = xr.Dataset(data, coords={"amplitude": ("case", amplitudes, amp)})
    ds.attrs.update(model.to_attrs())
    ds.attrs["title"] = "microslip: spring-driven stick-slip with and without normal vibration"
    return ds
