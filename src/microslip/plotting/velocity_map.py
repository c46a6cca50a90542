"""Fig. 7: the mean sliding velocity over tangential force and vibration amplitude,
and plots of any sweep of it (maps per swept parameter value, or curves)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from microslip.io.output import write_atomically
from microslip.model.parameters import Parameters
from microslip.plotting.scales import Unit, prefixed_unit

MAX_PANELS = 24  # maps in one sweep plot
MAX_CURVES = 12  # curves in one sweep plot
_INPUTS = ("force", "amplitude")
# Largest values of the paper's Fig. 7, plotted in N, µm and 10⁻⁴ m/s; other ranges move
# these units by SI prefixes (F, A) or decades (v) so the plotted numbers stay alike.
_PAPER_F, _PAPER_A, _PAPER_V = 0.95, 3.0e-7, 2.0e-4  # [N], [m], [m/s]
_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def _peak(values: np.ndarray) -> float:
    finite = np.abs(np.asarray(values, dtype=float))
    finite = finite[np.isfinite(finite)]
    return float(finite.max()) if finite.size else 0.0


def _map_units(ds: xr.Dataset | xr.DataArray) -> tuple[Unit, Unit, Unit]:
    """Plotted units of F, A and v for the values in ``ds`` (the paper's for Fig. 7)."""
    f_unit = prefixed_unit("N", 0, _peak(ds["force"].values) / _PAPER_F)
    a_unit = prefixed_unit("m", -6, _peak(ds["amplitude"].values) / _PAPER_A)
    v_peak = _peak(ds["mean_velocity"].values)
    shift = round(np.log10(v_peak / _PAPER_V)) if v_peak > 0 else 0
    exponent = -4 + int(shift)
    return f_unit, a_unit, Unit(10.0**-exponent, f"10{str(exponent).translate(_SUPERSCRIPT)} m/s")


def _map_values(v: xr.DataArray, v_unit: Unit) -> np.ndarray:
    """v(F, A) as an (amplitude, force) array in ``v_unit``, NaN where v is not finite."""
    values = v.transpose("amplitude", "force").values
    return np.where(np.isfinite(values), values, np.nan) * v_unit.factor


def _velocity_levels(values: np.ndarray) -> np.ndarray:
    """Contour levels (plotted velocity unit) from 0 to the largest finite value."""
    finite = values[np.isfinite(values)]
    top = finite.max() if finite.size and finite.max() > 0 else 1.0
    return MaxNLocator(nbins=20).tick_values(0.0, top)


def _map_friction(ds: xr.Dataset, params: Parameters) -> tuple[float, float]:
    """(μ_s, μ_k) [-] of a map: a StaticKinetic law's, as its result records them (a
    scalar coordinate where the field was swept, else the attributes), or ``params.mu``
    for both (Coulomb)."""
    if ds.attrs.get("friction") != "StaticKinetic":
        return params.mu, params.mu
    found = []
    for field in ("mu_static", "mu_kinetic"):
        name = f"friction.{field}"
        value = ds[name].values if name in ds.coords else ds.attrs[f"friction_{field}"]
        found.append(float(value))
    return found[0], found[1]


def _map_panel(ax, v: xr.DataArray, params: Parameters, levels: np.ndarray, units: tuple,
               mu: tuple[float, float]):  # fmt: skip
    """Filled contours of v(F, A) with the analytic no-sliding boundary
    F = μ_s S c_n max(y0 - A, 0)^m2, the contact-loss line A = y0 and F >= μ_k m g
    hatched, in ``units`` (F, A, v; see :func:`_map_units`); ``mu`` = (μ_s, μ_k) [-].
    Returns the contour set (for a colorbar)."""
    f_unit, a_unit, v_unit = units
    mu_static, mu_kinetic = mu
    amplitudes = v["amplitude"].values
    forces = v["force"].values * f_unit.factor
    amps = amplitudes * a_unit.factor
    filled = ax.contourf(forces, amps, _map_values(v, v_unit), levels=levels, cmap="viridis")
    amp_line = np.linspace(amplitudes.min(), amplitudes.max(), 400)
    static = params.replace(mu=mu_static)
    boundary = [static.motion_threshold(a) * f_unit.factor for a in amp_line]
    ax.plot(
        boundary, amp_line * a_unit.factor, color="white", lw=2.0,
        label="no-sliding boundary (analytic)",
    )  # fmt: skip
    ax.axhline(
        params.static_deflection * a_unit.factor, color="tab:red", lw=1.5, ls="--",
        label="A = y0 (loss of contact above)",
    )  # fmt: skip
    _mark_no_steady_state(
        ax, params.replace(mu=mu_kinetic), v["force"].values, f_unit.factor,
        "μ" if mu_static == mu_kinetic else "μ_k",
    )  # fmt: skip
    ax.set_xlim(forces.min(), forces.max())
    ax.set_ylim(amps.min(), amps.max())
    return filled


def velocity_map_figure(ds: xr.Dataset, params: Parameters | None = None) -> Figure:
    """(a) surface v(F, A) as in the paper; (b) filled contours with the analytic
    no-sliding boundary F = μ S c_n max(y0 - A, 0)^m2 (μ_s for StaticKinetic friction:
    :func:`_map_friction`) and the contact-loss line A = y0."""
    params = Parameters() if params is None else params
    v = ds["mean_velocity"]
    if set(v.dims) != {"force", "amplitude"}:
        raise ValueError(f"a velocity map needs dims (force, amplitude), got {v.dims}")
    units = f_unit, a_unit, v_unit = _map_units(ds)
    forces = ds["force"].values * f_unit.factor
    values = _map_values(v, v_unit)

    fig = Figure(figsize=(12.0, 5.2), layout="constrained")
    ax3 = fig.add_subplot(1, 2, 1, projection="3d")
    ff, aa = np.meshgrid(forces, ds["amplitude"].values * a_unit.factor)
    ax3.plot_surface(ff, aa, values, cmap="viridis", linewidth=0, antialiased=True)
    ax3.set_xlabel(f_unit.label("F"))
    ax3.set_ylabel(a_unit.label("A"))
    ax3.set_zlabel(v_unit.label("v"))
    ax3.view_init(elev=28, azim=-125)
    ax3.set_title("(a) mean sliding velocity v(F, A)")

    ax = fig.add_subplot(1, 2, 2)
    mu_static, mu_kinetic = _map_friction(ds, params)
    filled = _map_panel(ax, v, params, _velocity_levels(values), units, (mu_static, mu_kinetic))
    fig.colorbar(filled, ax=ax, label=v_unit.label("v"))
    ax.set_xlabel(f_unit.label("tangential force F"))
    ax.set_ylabel(a_unit.label("vibration amplitude A"))
    mg = params.mass * params.g * f_unit.factor
    if mu_static == mu_kinetic:
        friction = f"μ = {mu_kinetic:.3g}, F_t0 = μ m g = {mu_kinetic * mg:.3g} {f_unit.symbol}"
    else:
        friction = (
            f"μ_s = {mu_static:.3g}, μ_k = {mu_kinetic:.3g}, "
            f"μ_k m g = {mu_kinetic * mg:.3g} {f_unit.symbol}"
        )
    ax.set_title(f"(b) v(F, A); {friction}")
    y0_plot = params.static_deflection * a_unit.factor
    ax.text(0.05 * forces.max() + 0.95 * forces.min(), 0.08 * y0_plot, "no sliding", color="white")
    ax.legend(loc="upper right", fontsize=8, framealpha=0.8)
    return fig


def sweep_plot_kind(sizes: Mapping[str, int]) -> str:
    """How a sweep with these dimension sizes is drawn, or ValueError saying why it cannot.

    "map": the Fig. 7 layout (F and A vary, no swept parameter takes two values);
    "panels": one filled-contour map per value of one or two swept parameters;
    "curves": v against the one input that varies (F, else A, else the first swept
    parameter), one curve per combination of the other varying dimensions.
    """
    varying = [name for name, size in sizes.items() if size >= 2]
    params = [name for name in varying if name not in _INPUTS]
    if sizes.get("force", 1) >= 2 and sizes.get("amplitude", 1) >= 2:
        if not params:
            return "map"
        panels = math.prod(sizes[name] for name in params)
        if len(params) > 2 or panels > MAX_PANELS:
            raise ValueError(
                f"--plot: a sweep over {', '.join(params)} gives {panels} maps; at most 2 "
                f"swept parameters and {MAX_PANELS} maps can be drawn (plot a slice instead)"
            )
        return "panels"
    if not varying:
        raise ValueError("--plot: the sweep has a single point; there is nothing to draw")
    x_name = _curve_axis(varying)
    curves = math.prod(sizes[name] for name in varying) // sizes[x_name]
    if curves > MAX_CURVES:
        raise ValueError(
            f"--plot: v against {x_name} gives {curves} curves; at most "
            f"{MAX_CURVES} can be drawn (sweep fewer values or plot a slice instead)"
        )
    return "curves"


def _curve_axis(varying: list[str]) -> str:
    for name in _INPUTS:
        if name in varying:
            return name
    return varying[0]


def _params_at(ds: xr.Dataset, base: Parameters, selection: Mapping[str, int]) -> Parameters:
    """``base`` with the swept Parameters fields set to their values at ``selection``
    (indices); a swept part field ("damping.ratio") is the part's, not a parameter."""
    fields = set(Parameters.field_names())
    return base.replace(
        **{name: float(ds[name].values[i]) for name, i in selection.items() if name in fields}
    )


def _value_text(ds: xr.Dataset, name: str, index: int) -> str:
    """ "name = value unit" for one coordinate value (no unit for dimensionless fields)."""
    unit = ds[name].attrs.get("units", "")
    text = f"{name} = {float(ds[name].values[index]):.4g}"
    return text if unit in ("", "1") else f"{text} {unit}"


def _mark_no_steady_state(ax, params: Parameters, forces: np.ndarray, factor: float = 1.0,
                          mu_name: str = "μ") -> None:  # fmt: skip
    """Hatch F >= μ m g (``params.mu``, named ``mu_name`` in the legend), where the slider
    accelerates for ever (no mean velocity); ``forces`` [N], plotted times ``factor``."""
    limit = params.static_friction_force
    if limit < forces.max():
        ax.axvspan(max(limit, forces.min()) * factor, forces.max() * factor, facecolor="none",
                   hatch="//", edgecolor="0.6", linewidth=0.0,
                   label=f"F ≥ {mu_name} m g: no steady state")  # fmt: skip
        ax.axvline(limit * factor, color="0.3", lw=1.0, ls=":")


def _axis_label(ds: xr.Dataset, name: str) -> tuple[str, float]:
    """Axis label with unit, and the factor from SI to the plotted unit."""
    if name == "force":
        unit = prefixed_unit("N", 0, _peak(ds["force"].values) / _PAPER_F)
        return unit.label("tangential force F"), unit.factor
    if name == "amplitude":
        unit = prefixed_unit("m", -6, _peak(ds["amplitude"].values) / _PAPER_A)
        return unit.label("vibration amplitude A"), unit.factor
    return f"{name} [{ds[name].attrs.get('units', '1')}]", 1.0


def _panels_figure(ds: xr.Dataset, params: Parameters) -> Figure:
    """One map v(F, A) per value (combination) of the swept parameters, one color scale."""
    v = ds["mean_velocity"]
    swept = [d for d in v.dims if d not in _INPUTS and ds.sizes[d] >= 2]
    fixed = {d: 0 for d in v.dims if d not in _INPUTS and ds.sizes[d] == 1}
    n_cols = ds.sizes[swept[0]]
    n_rows = ds.sizes[swept[1]] if len(swept) == 2 else 1
    units = f_unit, a_unit, v_unit = _map_units(ds)
    levels = _velocity_levels(v.values * v_unit.factor)
    fig = Figure(figsize=(3.6 * n_cols + 1.2, 3.0 * n_rows + 0.6), layout="constrained")
    axes = fig.subplots(n_rows, n_cols, sharex=True, sharey=True, squeeze=False)
    for row in range(n_rows):
        for col in range(n_cols):
            selection = {**fixed, swept[0]: col}
            if len(swept) == 2:
                selection[swept[1]] = row
            ax = axes[row, col]
            at = _params_at(ds, params, selection)
            filled = _map_panel(
                ax, v.isel(selection), at, levels, units,
                _map_friction(ds.isel(selection), at),
            )  # fmt: skip
            ax.set_title(", ".join(_value_text(ds, d, selection[d]) for d in swept), fontsize=9)
            if row == n_rows - 1:
                ax.set_xlabel(f_unit.label("F"))
            if col == 0:
                ax.set_ylabel(a_unit.label("A"))
    fig.colorbar(filled, ax=axes, label=v_unit.label("v"))
    fig.suptitle(
        "mean sliding velocity v(F, A)\nwhite: no-sliding boundary; red dashed: A = y0; "
        "hatched: F ≥ μ m g (μ_k m g), no steady state",
        fontsize=10,
    )
    return fig


def _curves_figure(ds: xr.Dataset, params: Parameters) -> Figure:
    """v against the one varying input, one curve per combination of the others."""
    v = ds["mean_velocity"]
    varying = [d for d in v.dims if ds.sizes[d] >= 2]
    x_name = _curve_axis(varying)
    others = [d for d in varying if d != x_name]
    x_label, x_scale = _axis_label(ds, x_name)
    v_unit = prefixed_unit("m", -6, _peak(v.values) / _PAPER_V, "/s")
    fig = Figure(figsize=(7.5, 4.8), layout="constrained")
    ax = fig.add_subplot()
    for index in np.ndindex(*(ds.sizes[d] for d in others)):
        selection = {d: 0 for d in v.dims if d != x_name}
        selection.update(dict(zip(others, index, strict=True)))
        curve = v.isel(selection).values
        label = ", ".join(_value_text(ds, d, i) for d, i in zip(others, index, strict=True))
        ax.plot(ds[x_name].values * x_scale, curve * v_unit.factor, marker=".", label=label or None)
    ax.set_xlabel(x_label)
    ax.set_ylabel(v_unit.label("mean sliding velocity v"))
    fixed = [d for d in v.dims if ds.sizes[d] == 1]
    note = "points with F ≥ μ m g (no steady state) are not drawn"
    ax.set_title("; ".join([*(_value_text(ds, d, 0) for d in fixed), note]), fontsize=9)
    if others:
        ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return fig


def sweep_figure(ds: xr.Dataset | xr.DataArray, params: Parameters | None = None) -> Figure:
    """The picture of a sweep result (see :func:`sweep_plot_kind`).

    ``ds``: the Dataset of ``run_sweep``/``microslip sweep --out``, or the
    ``mean_velocity`` [m/s] DataArray of :func:`microslip.sweep`; ``params`` holds the
    fields that were not swept (paper's data by default).
    """
    params = Parameters() if params is None else params
    if isinstance(ds, xr.DataArray):
        ds = ds.to_dataset(name="mean_velocity")
    kind = sweep_plot_kind(dict(ds["mean_velocity"].sizes))
    if kind == "map":
        fixed = {d: 0 for d in ds["mean_velocity"].dims if d not in _INPUTS}
        return velocity_map_figure(ds.isel(fixed), _params_at(ds, params, fixed))
    if kind == "panels":
        return _panels_figure(ds, params)
    return _curves_figure(ds, params)


def write_velocity_map_plot(
    ds: xr.Dataset, path: str | Path, params: Parameters | None = None, dpi: int = 150
) -> Path:
    """Render :func:`sweep_figure` to ``path`` (PNG, PDF or SVG), atomically."""
    fig = sweep_figure(ds, params)
    suffix = Path(path).suffix
    return write_atomically(path, lambda tmp: fig.savefig(tmp, dpi=dpi, format=suffix.lstrip(".")))
