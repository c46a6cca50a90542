"""Figures of the extensions (docs/design.md): the forced normal contact and sliding on it.

Drawn by ``microslip figures --extensions`` (``make figures-ext``), each with the data
behind it as ``NAME.png`` and ``NAME.nc``:

- ``forced_response``: frequency response of the normal motion under a harmonic force
  P0 sin(2π f t), Kelvin–Voigt damping ζ = 0.03, for P0 = 0.05, 0.2, 0.5 and 1 N
  (the paper's m g = 9.81 N), f from 0.6 f0 to 1.4 f0: stable branches solid, unstable
  dashed, folds circled, contact loss under a red band; the linear oscillator limit
  P0/sqrt((K_n − m ω²)² + (c ω)²), c = 2 ζ sqrt(K_n m), dotted in the same colours.
- ``forced_velocity_map``: mean sliding velocity v(F, f) over the tangential force
  (0.05 to 0.95 μ m g, 19 values) and the excitation frequency (0.5 to 1.5 f0, 21
  values), P0 = 0.5 N, ζ = 0.03, exact steady state on the orbit reached from rest.
- ``contact_loss``: a time history from rest under a strong harmonic force (P0 = 2 N
  at f = f0, ζ = 0.03, F = 0.5 N): y, the normal force N and ẋ against time over eight
  excitation periods, the flight phases (N = 0) shaded.
- ``friction_master_curve``: the friction-reduction master curve of the flat punch
  (m2 = 1, prescribed penetration N = N0 (1 + β cos ωt), tangential spring k_t = K_n,
  prescribed velocity v): (1 − μ_eff/μ)/β against ṽ = k_t v/(μ max|dN/dt|) for
  β = 0.25 to 0.9 (they collapse onto the closed form D(ṽ), drawn) and β = 1.5, 3 (loss
  of contact: they do not).
- ``mu_eff_map``: μ_eff/μ of the same flat punch over drive speed (0.03 to 3 v_c of
  β = 1) × penetration amplitude (Δ/δ_m from 0.05 to 1.45), the critical speed ṽ = 1
  and the loss of contact Δ = δ_m drawn in.
- ``spring_stick_slip``: stick–slip driven by a spring (k_d = 1e-3 K_n) under
  static/kinetic friction (μ_s = 1.5 μ, μ_k = μ), without and with the paper's free
  normal vibration: drive force, friction limit μ_s N and body velocity against time,
  the force drops marked (2 (μ_s − μ_k) m g without vibration).

The last three are drawn by :mod:`microslip.plotting.friction` and
:mod:`microslip.plotting.stick_slip`.

For other parameters the forces scale with m g (P0) and μ m g (F), the frequencies
with f0, so each figure shows the same phenomena. The grids are small on purpose: each
figure takes a few seconds once the kernels are compiled.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # no display; figures are built with matplotlib.figure.Figure

import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from microslip.io.output import write_atomically, write_dataset
from microslip.model.composition import Model
from microslip.model.damping import Viscous, damping_coefficient
from microslip.model.excitation import HarmonicForce
from microslip.model.parameters import Parameters
from microslip.plotting.friction import master_curve_figure, mu_eff_map_figure
from microslip.plotting.response import draw_branch, fold_indices, legend_handles
from microslip.plotting.scales import PAPER, figure_scales, require_friction
from microslip.plotting.stick_slip import spring_stick_slip_figure
from microslip.results import FLIGHT

__all__ = [
    "EXTENSION_FIGURES",
    "FORCING_LEVELS",
    "contact_loss_figure",
    "forced_response_figure",
    "forced_velocity_map_figure",
    "linear_amplitude",
    "write_extension_figures",
]

FORCING_LEVELS = (0.05, 0.2, 0.5, 1.0)  # P0 [N] for the paper's m g = 9.81 N
RESPONSE_RATIO = 0.03  # ζ of the frequency-response figure
RESPONSE_SPAN = (0.6, 1.4)  # f/f0
MAP_FORCING = 0.5  # P0 [N] of the v(F, f) map (paper's m g)
MAP_FREQUENCIES = np.linspace(0.5, 1.5, 21)  # f/f0
MAP_FORCES = np.linspace(0.05, 0.95, 19)  # F/(μ m g)
LOSS_FORCING = 2.0  # P0 [N] (paper's m g): at resonance, flights of ~1/5 of each period
LOSS_FREQUENCY = 1.0  # f/f0
LOSS_RATIO = 0.03
LOSS_PERIODS = 8  # excitation periods simulated


def _weight_ratio(params: Parameters) -> float:
    return params.mass * params.g / (PAPER.mass * PAPER.g)


def linear_amplitude(params: Parameters, ratio: float, force: float, frequency) -> np.ndarray:
    """Linear-oscillator amplitude P0/sqrt((K_n − m ω²)² + (c ω)²) [m] (MODEL.md identity 3,
    docs/model-facts.md): the small-forcing limit of the forced response."""
    k, m = params.contact_stiffness, params.mass
    c = damping_coefficient(params, ratio)
    w = 2.0 * math.pi * np.asarray(frequency, dtype=float)
    return force / np.sqrt((k - m * w * w) ** 2 + (c * w) ** 2)


# -- (a) frequency response ----------------------------------------------------------------
def forced_response_figure(params: Parameters) -> tuple[Figure, xr.Dataset]:
    """Frequency responses for several forcing levels, with the linear limit drawn in."""
    from microslip.analysis.forced_response import forced_response

    f0 = params.natural_frequency
    y0 = params.static_deflection
    span = (RESPONSE_SPAN[0] * f0, RESPONSE_SPAN[1] * f0)
    branches = []
    for level in FORCING_LEVELS:
        force = level * _weight_ratio(params)
        model = Model(params, Viscous(RESPONSE_RATIO), HarmonicForce(force, span[0]))
        branches.append(forced_response(model, frequencies=span, max_points=1000))
    fig = Figure(figsize=(8.0, 5.5), layout="constrained")
    ax = fig.subplots()
    kinds: set[str] = set()
    fine = np.linspace(*span, 400)
    for k, (level, ds) in enumerate(zip(FORCING_LEVELS, branches, strict=True)):
        color = f"C{k}"
        kinds |= draw_branch(ax, ds, x="frequency", x_factor=1.0 / f0, y_factor=1.0 / y0,
                             color=color)  # fmt: skip
        linear = linear_amplitude(params, RESPONSE_RATIO, level * _weight_ratio(params), fine)
        ax.plot(fine / f0, linear / y0, color=color, lw=0.9, ls=":")
    ax.set_xlabel("f / f0 [-]")
    ax.set_ylabel("amplitude (y_max − y_min)/2 / y0 [-]")
    ax.set_ylim(bottom=0.0)
    top = ax.secondary_xaxis("top", functions=(lambda r: r * f0, lambda f: f / f0))
    top.set_xlabel("excitation frequency f [Hz]")
    right = ax.secondary_yaxis("right", functions=(lambda r: r * y0 * 1e6, lambda a: a / y0 / 1e6))
    right.set_ylabel("amplitude [µm]")
    levels = [
        Line2D([], [], color=f"C{k}", label=f"P0 = {level * _weight_ratio(params):.3g} N")
        for k, level in enumerate(FORCING_LEVELS)
    ]
    linear = Line2D([], [], color="0.3", ls=":", label="linear oscillator")
    ax.legend(handles=[*levels, linear, *legend_handles(kinds)], fontsize=8, loc="upper left")
    ax.grid(True, lw=0.4, alpha=0.5)
    fig.suptitle(f"forced normal response, harmonic force, viscous damping ζ = {RESPONSE_RATIO}")
    return fig, _stack_branches(params, branches)


def _stack_branches(params: Parameters, branches: list[xr.Dataset]) -> xr.Dataset:
    """The branches one after the other on dim ``point`` (``branch`` numbers them), the
    folds as indices into the whole, and the linear limit at every point."""
    folds, offset = [], 0
    for ds in branches:
        folds += [offset + i for i in fold_indices(ds)]
        offset += ds.sizes["point"]
    data = xr.concat(
        [ds.assign(branch=("point", np.full(ds.sizes["point"], k))) for k, ds in
         enumerate(branches)],
        dim="point", combine_attrs="drop_conflicts",
    )  # fmt: skip
    data["branch"].attrs.update(units="1", long_name="forcing level (0 = smallest)")
    linear = linear_amplitude(
        params, RESPONSE_RATIO, data["excitation_amplitude"].values, data["frequency"].values
    )
    data["linear_amplitude"] = (
        "point",
        linear,
        {"units": "m", "long_name": "linear oscillator amplitude P0/|K_n - m w^2 + i c w|"},
    )
    data.attrs["folds"] = np.array(folds, dtype=np.int64)
    data.attrs["title"] = "microslip: forced normal response for several forcing levels"
    return data


# -- (b) v(F, f) map -----------------------------------------------------------------------
def forced_velocity_map_figure(params: Parameters) -> tuple[Figure, xr.Dataset]:
    """Mean sliding velocity over tangential force × excitation frequency."""
    import microslip as ms

    require_friction(params, "forced_velocity_map")
    f0 = params.natural_frequency
    mu_mg = params.static_friction_force
    force = MAP_FORCING * _weight_ratio(params)
    model = Model(params, Viscous(RESPONSE_RATIO), HarmonicForce(force, f0))
    frequencies = MAP_FREQUENCIES * f0
    forces = MAP_FORCES * mu_mg
    v = ms.sweep(model, {"excitation.frequency": frequencies}, force=forces)
    freq_dim = next(d for d in v.dims if d != "force" and v.sizes[d] == frequencies.size)
    v = v.squeeze(drop=True).transpose(freq_dim, "force")
    values = np.asarray(v.values, dtype=float)
    fig = Figure(figsize=(7.5, 5.0), layout="constrained")
    ax = fig.subplots()
    scale, unit = _velocity_unit(values)
    mesh = ax.pcolormesh(frequencies / f0, forces / mu_mg, values.T * scale, shading="nearest",
                         cmap="viridis")  # fmt: skip
    fig.colorbar(mesh, ax=ax, label=f"mean sliding velocity v [{unit}]")
    ax.set_xlabel("f / f0 [-]")
    ax.set_ylabel("F / (μ m g) [-]")
    top = ax.secondary_xaxis("top", functions=(lambda r: r * f0, lambda f: f / f0))
    top.set_xlabel("excitation frequency f [Hz]")
    right = ax.secondary_yaxis("right", functions=(lambda r: r * mu_mg, lambda f: f / mu_mg))
    right.set_ylabel("tangential force F [N]")
    fig.suptitle(
        f"v(F, f): harmonic force P0 = {force:.3g} N, viscous damping ζ = {RESPONSE_RATIO}"
    )
    ds = v.to_dataset(name="mean_velocity")
    ds["mean_velocity"].attrs.setdefault("units", "m s-1")
    ds.attrs.update(model.to_attrs())
    ds.attrs["title"] = "microslip: mean sliding velocity under a harmonic normal force"
    return fig, ds


def _velocity_unit(values: np.ndarray) -> tuple[float, str]:
    finite = np.abs(values[np.isfinite(values)])
    top = float(finite.max()) if finite.size and finite.max() > 0 else 1e-3
    exponent = min(max(3 * math.floor(math.log10(top) / 3), -9), 0)
    return 10.0 ** (-exponent), {-9: "nm/s", -6: "µm/s", -3: "mm/s", 0: "m/s"}[exponent]


# -- (c) loss of contact in time -----------------------------------------------------------
def contact_loss_figure(params: Parameters) -> tuple[Figure, xr.Dataset]:
    """y, N and ẋ against time under a forcing stronger than the weight, flights shaded."""
    import microslip as ms

    require_friction(params, "contact_loss")
    f0 = params.natural_frequency
    frequency = LOSS_FREQUENCY * f0
    force = LOSS_FORCING * _weight_ratio(params)
    model = Model(params, Viscous(LOSS_RATIO), HarmonicForce(force, frequency))
    drive = figure_scales(params).drive
    duration = LOSS_PERIODS / frequency
    # Dense samples (the event method's own steps are a few per period: a polygon).
    samples = np.linspace(0.0, duration, 200 * LOSS_PERIODS + 1)
    result = ms.simulate(model, force=drive, duration=duration, t_eval=samples)
    t_ms = result.t * 1e3
    flight = np.asarray(result.state) == FLIGHT  # δ <= 0 or N_raw <= 0
    fig = Figure(figsize=(8.0, 7.5), layout="constrained")
    axes = fig.subplots(3, 1, sharex=True)
    y0 = params.static_deflection
    axes[0].plot(t_ms, result.y * 1e6, lw=1.1)
    axes[0].axhline(y0 * 1e6, color="0.5", lw=0.8, ls="--", label="y0 (static)")
    axes[0].axhline(0.0, color="0.5", lw=0.8, ls=":", label="surface, y = 0")
    axes[0].set_ylabel("y [µm]")
    axes[0].legend(fontsize=8, loc="upper right")
    axes[1].plot(t_ms, result.N, lw=1.1, label="N")
    axes[1].axhline(params.mass * params.g, color="0.5", lw=0.8, ls="--", label="m g")
    axes[1].set_ylabel("normal force N [N]")
    axes[1].legend(fontsize=8, loc="upper right")
    axes[2].plot(t_ms, result.xdot * 1e3, lw=1.1)
    axes[2].set_ylabel("ẋ [mm/s]")
    axes[2].set_xlabel("t [ms]")
    for ax in axes:
        _shade(ax, t_ms, flight)
    fig.suptitle(
        f"loss of contact: P0 = {force:.3g} N at f = {frequency:.4g} Hz, ζ = {LOSS_RATIO}, "
        f"F = {drive:.3g} N (shaded: flight, N = 0)"
    )
    return fig, result.to_xarray()


def _shade(ax, t: np.ndarray, mask: np.ndarray) -> None:
    edges = np.diff(np.r_[0, mask.astype(np.int8), 0])
    for first, last in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1,
                           strict=True):  # fmt: skip
        ax.axvspan(t[first], t[last], color="tab:orange", alpha=0.2, lw=0)


# -- registry -------------------------------------------------------------------------------
FIGURES: dict[str, Callable[[Parameters], tuple[Figure, xr.Dataset]]] = {
    "forced_response": forced_response_figure,
    "forced_velocity_map": forced_velocity_map_figure,
    "contact_loss": contact_loss_figure,
    "friction_master_curve": master_curve_figure,
    "mu_eff_map": mu_eff_map_figure,
    "spring_stick_slip": spring_stick_slip_figure,
}
EXTENSION_FIGURES = tuple(FIGURES)


def write_extension_figures(
    out_dir: str | Path,
    params: Parameters | None = None,
    names: Sequence[str] = EXTENSION_FIGURES,
    *,
    dpi: int = 150,
    progress: Callable[[str], None] | None = None,
) -> list[Path]:
    """Write ``NAME.png`` and ``NAME.nc`` for each extension figure into ``out_dir``."""
    params = Parameters() if params is None else params
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    for name in names:
        fig, ds = FIGURES[name](params)
        png, nc = out_dir / f"{name}.png", out_dir / f"{name}.nc"
        write_atomically(png, lambda tmp, fig=fig: fig.savefig(tmp, dpi=dpi, format="png"))
        write_dataset(ds, nc)
        written += [png, nc]
        if progress is not None:
            progress(f"{name}: wrote {png.name}, {nc.name}")
    return written
