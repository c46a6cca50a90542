"""Figures of friction under normal vibration (docs/theory/friction_reduction.md).

- :func:`friction_curve_figure`, :func:`friction_map_figure`: μ_eff/μ_k of an
  :func:`~microslip.analysis.effective_friction.effective_friction_curve` or
  ``effective_friction_map`` Dataset against the drive speed v (log axis), with the
  critical speed ṽ = 1 drawn in (``microslip friction --plot``).
- :func:`master_curve_figure`: the friction-reduction master curve of the flat punch.
- :func:`mu_eff_map_figure`: μ_eff/μ over drive speed × penetration amplitude.

Spring-driven stick–slip is drawn by :mod:`microslip.plotting.stick_slip`.

The flat punch (:func:`flat_punch`) is the parameter set with m2 = 1, S = 1 m² and
c_n = K_n of the given one (same contact stiffness K_n, same f0, N linear in δ), under a
prescribed penetration δ = δ_m + Δ cos ωt with δ_m = y0 (N0 = m g, β = Δ/δ_m, f = f0),
a tangential spring k_t = K_n and a prescribed velocity v. Then
ṽ = k_t v/(μ max|dN/dt|) = v / v_c, v_c = μ m g β ω / k_t, and for β <= 1
μ_eff/μ = 1 − β D(ṽ), D of
:func:`~microslip.analysis.flat_punch.flat_punch_reduction`.

Fast settings (each figure a few seconds once the kernels are compiled): the master
curve has 43 values of ṽ (40 up to 1, three past it) for β = 0.25, 0.5, 0.75, 0.9 and,
with loss of contact, β = 1.5 and 3; the μ_eff map 15 amplitudes Δ/δ_m from 0.05 to 1.45
× 25 speeds from 0.03 to 3 v_c(β = 1), log-spaced. Every axis carries its unit, moved
by SI prefixes (:func:`microslip.plotting.scales.prefixed_unit`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from microslip.model.composition import Model
from microslip.model.drive import PrescribedVelocity
from microslip.model.excitation import PrescribedPenetration
from microslip.model.parameters import Parameters
from microslip.model.tangential import TangentialSpring
from microslip.plotting.scales import Unit, prefixed_unit, require_friction

__all__ = [
    "MAP_BETAS",
    "MAP_SPEEDS",
    "MASTER_BETAS",
    "MASTER_LOSS_BETAS",
    "MASTER_V_TILDE",
    "critical_speed",
    "critical_velocity",
    "flat_punch",
    "flat_punch_model",
    "friction_curve_figure",
    "friction_map_figure",
    "master_curve_figure",
    "mu_eff_map_figure",
    "si_unit",
]

# β = Δ/δ_m without loss of contact; not β = 1, where δ grazes 0 once per period
MASTER_BETAS = (0.25, 0.5, 0.75, 0.9)
MASTER_LOSS_BETAS = (1.5, 3.0)  # β > 1: the contact opens in every period
MASTER_V_TILDE = np.r_[np.linspace(0.025, 1.0, 40), 1.1, 1.25, 1.5]  # ṽ [-]
MAP_BETAS = np.linspace(0.05, 1.45, 15)  # Δ/δ_m [-] (not 1: a grazing contact)
MAP_SPEEDS = np.geomspace(0.03, 3.0, 25)  # v / v_c(β = 1) [-]

_SI_BASES = {"m": ("m", ""), "N": ("N", ""), "Hz": ("Hz", ""), "s": ("s", ""),
             "m s-1": ("m", "/s"), "m/s": ("m", "/s"), "N m-1": ("N", "/m")}  # fmt: skip
_CRITICAL = {"color": "tab:red", "lw": 1.4, "ls": "--"}


# -- units and the critical speed ------------------------------------------------------
def si_unit(values: Any, units: str) -> Unit:
    """The plotted unit of ``values`` given in the SI ``units``: the SI prefix that puts
    the largest |value| between 1 and 1000 (units without a prefix table: as given)."""
    if units in ("", "1", "-"):
        return Unit(1.0, "-")
    if units not in _SI_BASES:
        return Unit(1.0, units)
    base, suffix = _SI_BASES[units]
    finite = np.abs(np.asarray(values, dtype=float))
    finite = finite[np.isfinite(finite) & (finite > 0)]
    peak = float(finite.max()) if finite.size else 1.0
    # prefixed_unit rounds log10(ratio)/3 to the nearest integer: dividing by 10^1.5
    # makes that the floor, so the plotted peak lies in [1, 1000)
    return prefixed_unit(base, 0, peak / 10**1.5, suffix)


def critical_velocity(ds: xr.Dataset) -> xr.DataArray:
    """v_c = v/ṽ [m/s], where ṽ = 1 (the drive speed above which the contact point never
    sticks), from ``ds["velocity"]`` and ``ds["v_tilde"]`` (ṽ ∝ v along "velocity");
    NaN where ṽ is not finite (no normal vibration)."""
    vt = ds["v_tilde"]
    ratio = (ds["velocity"] / vt).where(np.isfinite(vt) & (vt > 0))
    out = ratio.median("velocity")
    return out.assign_attrs(units="m s-1", long_name="critical drive speed v_c (v_tilde = 1)")


def flat_punch(params: Parameters) -> Parameters:
    """The flat punch of ``params``: m2 = 1, S = 1 m², c_n = K_n [N/m] (same m, g, μ, K_n
    and f0; N = K_n δ)."""
    return params.replace(m2=1.0, area=1.0, c_n=params.contact_stiffness)


def critical_speed(params: Parameters, beta: float) -> float:
    """v_c = μ m g β ω / k_t [m/s] of :func:`flat_punch_model` (ω = 2π f0, k_t = K_n)."""
    flat = flat_punch(params)
    omega = flat.natural_angular_frequency
    return params.mu * params.mass * params.g * beta * omega / flat.contact_stiffness


def flat_punch_model(params: Parameters, beta: float, velocity: float | None = None) -> Model:
    """Flat punch under δ = y0 (1 + β cos 2π f0 t), k_t = K_n, driven at ``velocity``
    [m/s] (default: v_c of β = 1)."""
    flat = flat_punch(params)
    mean = flat.static_deflection
    velocity = critical_speed(params, 1.0) if velocity is None else velocity
    return Model(
        flat,
        excitation=PrescribedPenetration(mean=mean, amplitude=beta * mean,
                                         frequency=flat.natural_frequency),
        tangential=TangentialSpring(stiffness=flat.contact_stiffness),
        drive=PrescribedVelocity(velocity=velocity),
    )  # fmt: skip


def _draw_critical(ax: Axes, vc: float, factor: float, label: str | None = None) -> None:
    if math.isfinite(vc) and vc > 0:
        ax.axvline(vc * factor, **_CRITICAL, label=label)


# -- μ_eff curve and map of any effective-friction Dataset ---------------------------------
def friction_curve_figure(ds: xr.Dataset) -> Figure:
    """μ_eff/μ_k and the stick fraction against the drive speed v (log axis), ṽ on the top
    axis, the critical speed ṽ = 1 dashed (``ds``: ``effective_friction_curve``)."""
    v = np.asarray(ds["velocity"].values, dtype=float)
    unit = si_unit(v, "m s-1")
    vc = float(critical_velocity(ds))
    fig = Figure(figsize=(7.5, 6.0), layout="constrained")
    ax, low = fig.subplots(2, 1, sharex=True, height_ratios=(2, 1))
    ax.plot(v * unit.factor, ds["ratio"].values, marker=".", label="μ_eff / μ_k")
    ax.axhline(1.0, color="0.5", lw=0.8, ls=":", label="no vibration: μ_eff = μ_k")
    _draw_critical(ax, vc, unit.factor, f"ṽ = 1: v_c = {vc * unit.factor:.4g} {unit.symbol}")
    ax.set_xscale("log")
    ax.set_ylabel("μ_eff / μ_k [-]")
    ax.legend(fontsize=8, loc="lower right")
    if math.isfinite(vc) and vc > 0:
        scale = vc * unit.factor
        top = ax.secondary_xaxis("top", functions=(lambda x: x / scale, lambda r: r * scale))
        top.set_xlabel("ṽ = v / v_c [-]")
    if "stick_fraction" in ds:
        low.plot(v * unit.factor, ds["stick_fraction"].values, marker=".", color="C1")
    _draw_critical(low, vc, unit.factor)
    low.set_ylabel("stick fraction [-]")
    low.set_xlabel(unit.label("drive speed v"))
    for a in (ax, low):
        a.grid(True, which="both", lw=0.4, alpha=0.5)
    fig.suptitle(_title(ds, "effective friction μ_eff = <F_t>/<N>"), fontsize=10)
    return fig


def _edges(values: np.ndarray, log: bool) -> np.ndarray:
    """Cell edges around ``values`` (geometric midpoints on a log axis)."""
    x = np.log(values) if log else np.asarray(values, dtype=float)
    if x.size == 1:
        mid = np.array([x[0] - 0.5, x[0] + 0.5])
    else:
        inner = 0.5 * (x[1:] + x[:-1])
        mid = np.r_[2 * x[0] - inner[0], inner, 2 * x[-1] - inner[-1]]
    return np.exp(mid) if log else mid


def friction_map_figure(ds: xr.Dataset) -> Figure:
    """μ_eff/μ_k over (second axis, drive speed v) with the ṽ = 1 line (``ds``:
    ``effective_friction_map``, dims (name, "velocity"))."""
    ratio = ds["ratio"]
    name = next(d for d in ratio.dims if d != "velocity")
    v = np.asarray(ds["velocity"].values, dtype=float)
    y = np.asarray(ds[name].values, dtype=float)
    v_unit = si_unit(v, "m s-1")
    y_unit = si_unit(y, str(ds[name].attrs.get("units", "")))
    y_log = bool(y.size > 2 and np.all(y > 0) and y.max() / y.min() > 100.0)
    fig = Figure(figsize=(7.5, 5.2), layout="constrained")
    ax = fig.subplots()
    y_edges = _edges(y * y_unit.factor, y_log)
    if y.min() >= 0.0:  # a nonnegative quantity: no cell below 0
        y_edges[0] = max(y_edges[0], 0.0)
    mesh = ax.pcolormesh(
        _edges(v * v_unit.factor, True), y_edges, ratio.transpose(name, "velocity").values,
        cmap="viridis", shading="flat",
    )  # fmt: skip
    fig.colorbar(mesh, ax=ax, label="μ_eff / μ_k [-]")
    vc = critical_velocity(ds).values
    drawn = np.isfinite(vc)
    if drawn.any():  # v_c linear in y between the rows (exact where v_c ∝ y), fine on log v
        fine = np.linspace(0.0, drawn.sum() - 1.0, 20 * (drawn.sum() - 1) + 1)
        rows = np.arange(drawn.sum())
        line_v, line_y = np.interp(fine, rows, vc[drawn]), np.interp(fine, rows, y[drawn])
        ax.plot(line_v * v_unit.factor, line_y * y_unit.factor, color="white", lw=2.0,
                label="ṽ = 1 (critical speed)")  # fmt: skip
    ax.set_xscale("log")
    if y_log:
        ax.set_yscale("log")
    ax.set_xlim(_edges(v * v_unit.factor, True)[[0, -1]])
    ax.set_ylim(y_edges[0], y_edges[-1])
    ax.set_xlabel(v_unit.label("drive speed v"))
    ax.set_ylabel(y_unit.label(name))
    ax.legend(fontsize=8, loc="upper left", framealpha=0.8)
    fig.suptitle(_title(ds, "μ_eff / μ_k; left of the white line (ṽ < 1) friction is reduced"),
                 fontsize=10)  # fmt: skip
    return fig


def _title(ds: xr.Dataset, text: str) -> str:
    parts = [ds.attrs.get(slot) for slot in ("excitation", "tangential", "friction")]
    named = ", ".join(str(p) for p in parts if p not in (None, "none"))
    return f"{text} ({named})" if named else text


# -- the flat punch: master curve and μ_eff map -------------------------------------------
def master_curve_figure(params: Parameters) -> tuple[Figure, xr.Dataset]:
    """(1 − μ_eff/μ)/β against ṽ for the flat punch: β <= 1 collapse onto D(ṽ) (drawn as
    a line), β > 1 (loss of contact) do not."""
    from microslip.analysis.effective_friction import effective_friction_curve
    from microslip.analysis.flat_punch import flat_punch_reduction

    require_friction(params, "friction_master_curve")
    betas = np.array(MASTER_BETAS + MASTER_LOSS_BETAS)
    rows = {"velocity": [], "ratio": [], "mu_eff": [], "stick_fraction": []}
    for beta in betas:
        velocities = MASTER_V_TILDE * critical_speed(params, beta)
        curve = effective_friction_curve(flat_punch_model(params, beta), velocities)
        rows["velocity"].append(velocities)
        for key in ("ratio", "mu_eff", "stick_fraction"):
            rows[key].append(np.asarray(curve[key].values, dtype=float))
    arr = {key: np.array(value) for key, value in rows.items()}
    reduction = (1.0 - arr["ratio"]) / betas[:, None]
    closed = np.asarray(flat_punch_reduction(MASTER_V_TILDE), dtype=float)

    fig = Figure(figsize=(7.5, 5.0), layout="constrained")
    ax = fig.subplots()
    fine = np.linspace(0.0, MASTER_V_TILDE[-1], 600)
    ax.plot(fine, flat_punch_reduction(fine), color="k", lw=1.2, label="closed form D(ṽ)")
    for k, beta in enumerate(betas):
        lost = beta > 1.0
        ax.plot(MASTER_V_TILDE, reduction[k], ls="--" if lost else "none", lw=0.9,
                marker="x" if lost else "o", ms=4 if lost else 9 - 1.5 * k, mfc="none",
                color=f"C{k}",
                label=f"β = {beta:g}" + (" (loss of contact)" if lost else ""))  # fmt: skip
    ax.axvline(1.0, **_CRITICAL)
    ax.set_xlabel("ṽ = k_t v / (μ max|dN/dt|) [-]")
    ax.set_ylabel("(1 − μ_eff/μ) / β [-]")
    ax.legend(fontsize=8)
    ax.grid(True, lw=0.4, alpha=0.5)
    fig.suptitle("friction-reduction master curve: flat punch, N = N0 (1 + β cos ωt), "
                 "tangential spring, prescribed velocity", fontsize=10)  # fmt: skip

    flat = flat_punch(params)
    dims = ("beta", "v_tilde")
    one = {"units": "1"}
    ds = xr.Dataset(
        {
            "velocity": (dims, arr["velocity"], {"units": "m s-1", "long_name": "drive speed v"}),
            "ratio": (dims, arr["ratio"], {**one, "long_name": "mu_eff / mu"}),
            "mu_eff": (dims, arr["mu_eff"], {**one, "long_name": "effective friction <F_t>/<N>"}),
            "stick_fraction": (dims, arr["stick_fraction"],
                               {**one, "long_name": "time fraction the contact point sticks"}),
            "reduction": (dims, reduction, {**one, "long_name": "(1 - mu_eff/mu) / beta"}),
            "closed_form": ("v_tilde", closed, {**one, "long_name": "D(v_tilde), closed form"}),
        },
        coords={
            "beta": ("beta", betas, {**one, "long_name": "penetration amplitude / mean"}),
            "v_tilde": ("v_tilde", MASTER_V_TILDE,
                        {**one, "long_name": "k_t v / (mu max|dN/dt|)"}),
        },
    )  # fmt: skip
    ds.attrs.update(flat_punch_model(params, 1.0).to_attrs())
    ds.attrs.pop("drive_velocity", None)  # each point has its own (``velocity``)
    ds.attrs.pop("excitation_amplitude", None)  # beta * excitation_mean
    ds.attrs["critical_speed_beta_1"] = critical_speed(params, 1.0)
    ds.attrs["title"] = "microslip: friction-reduction master curve of the flat punch"
    ds.attrs["flat_punch_y0"] = flat.static_deflection
    return fig, ds


def mu_eff_map_figure(params: Parameters) -> tuple[Figure, xr.Dataset]:
    """μ_eff/μ of the flat punch over drive speed × penetration amplitude Δ, with ṽ = 1
    and the loss of contact Δ = δ_m drawn in."""
    from microslip.analysis.effective_friction import effective_friction_map

    require_friction(params, "mu_eff_map")
    model = flat_punch_model(params, 1.0)
    mean = model.excitation.mean
    velocities = MAP_SPEEDS * critical_speed(params, 1.0)
    ds = effective_friction_map(model, velocities, "excitation.amplitude", MAP_BETAS * mean)
    ds["excitation.amplitude"].attrs["units"] = "m"
    ds["critical_velocity"] = critical_velocity(ds)
    fig = friction_map_figure(ds)
    ax = fig.axes[0]
    a_unit = si_unit(ds["excitation.amplitude"].values, "m")
    ax.axhline(mean * a_unit.factor, color="tab:red", lw=1.4, ls="--",
               label="Δ = δ_m (loss of contact above)")  # fmt: skip
    ax.set_ylabel(a_unit.label("penetration amplitude Δ"))
    ax.legend(fontsize=8, loc="upper left", framealpha=0.8)
    right = ax.secondary_yaxis("right", functions=(lambda a: a / (mean * a_unit.factor),
                                                   lambda b: b * mean * a_unit.factor))  # fmt: skip
    right.set_ylabel("β = Δ / δ_m [-]")
    fig.suptitle(f"μ_eff / μ of the flat punch, δ = δ_m + Δ cos 2πft, f = "
                 f"{model.excitation.frequency:.4g} Hz, k_t = {model.tangential.stiffness:.3g} "
                 "N/m", fontsize=10)  # fmt: skip
    ds.attrs["title"] = "microslip: effective friction of the flat punch, speed x amplitude"
    return fig, ds
