"""The forced-response curve (``microslip response --plot``): a branch of periodic orbits.

Amplitude (y_max − y_min)/2 [m] (right axis: divided by the static deflection y0)
against the continuation parameter (frequency [Hz], top axis f/f0; or the excitation
amplitude): stable orbits solid, unstable dashed, folds as open circles, stretches
where the contact is lost under a wide red band, period-doubling points as crosses.
The Dataset is the one of :func:`microslip.analysis.forced_response.forced_response`.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from microslip.io.output import write_atomically
from microslip.model.parameters import Parameters

__all__ = [
    "continuation_variable",
    "draw_branch",
    "fold_indices",
    "length_unit",
    "model_parameters",
    "response_figure",
    "write_response_plot",
]

_PREFIX = {-12: "p", -9: "n", -6: "µ", -3: "m", 0: ""}


def fold_indices(ds: Any) -> list[int]:
    """The point indices of the folds listed in ``ds.attrs["folds"]`` (NetCDF stores a
    list attribute as an array, a one-element list as a scalar, an empty one not at all)."""
    folds = ds.attrs.get("folds", [])
    return [int(i) for i in np.atleast_1d(np.asarray(folds, dtype=np.int64)).ravel()]


def model_parameters(ds: Any) -> Parameters | None:
    """The Parameters recorded in ``ds.attrs`` (``param_<field>``), None if absent."""
    values = {
        name: float(ds.attrs[f"param_{name}"])
        for name in Parameters.field_names()
        if f"param_{name}" in ds.attrs
    }
    return Parameters(**values) if len(values) == len(Parameters.field_names()) else None


def continuation_variable(ds: Any) -> str:
    """ "frequency" or "excitation_amplitude": the variable that changes along the branch."""
    for name in ("frequency", "excitation_amplitude"):
        values = np.asarray(ds[name].values, dtype=float)
        if values.size > 1 and np.ptp(values) > 0.0:
            return name
    return "frequency"


def length_unit(values: np.ndarray) -> tuple[float, str]:
    """(factor, symbol) plotting lengths [m] as numbers of about 1 to 1000."""
    top = float(np.nanmax(np.abs(values))) if np.size(values) else 0.0
    exponent = 3 * math.floor(math.log10(top) / 3) if top > 0 and math.isfinite(top) else -6
    exponent = min(max(exponent, -12), 0)
    return 10.0 ** (-exponent), f"{_PREFIX[exponent]}m"


def _runs(mask: np.ndarray) -> list[tuple[int, int, bool]]:
    """(first, last, value) of each run of equal values in ``mask``."""
    runs, start = [], 0
    for i in range(1, mask.size + 1):
        if i == mask.size or mask[i] != mask[start]:
            runs.append((start, i - 1, bool(mask[start])))
            start = i
    return runs


def draw_branch(
    ax: Axes, ds: Any, *, x: str, x_factor: float = 1.0, y_factor: float = 1.0,
    color: str = "C0", marks: bool = True,
) -> set[str]:  # fmt: skip
    """Draw one branch on ``ax``; returns the kinds of marks drawn ("fold", "lost", ...).

    Each run of equally stable points is drawn to the next point, so the curve is
    continuous and its style changes at the point where the stability does.
    """
    xs = np.asarray(ds[x].values, dtype=float) * x_factor
    ys = np.asarray(ds["amplitude"].values, dtype=float) * y_factor
    stable = np.asarray(ds["stable"].values, dtype=bool)
    drawn: set[str] = set()
    for first, last, is_stable in _runs(stable):
        stop = min(last + 2, xs.size)
        ax.plot(xs[first:stop], ys[first:stop], color=color, lw=1.4, ls="-" if is_stable else "--")
        drawn.add("stable" if is_stable else "unstable")
    if not marks:
        return drawn
    lost = np.asarray(ds["contact_lost"].values, dtype=bool)
    if lost.any():
        band = np.where(lost | np.r_[False, lost[:-1]], ys, np.nan)
        ax.plot(xs, band, color="tab:red", lw=7, alpha=0.25, solid_capstyle="butt", zorder=1)
        drawn.add("lost")
    folds = fold_indices(ds)
    if folds:
        ax.plot(xs[folds], ys[folds], "o", mfc="none", mec="k", ms=7, mew=1.2, zorder=4)
        drawn.add("fold")
    if "period_doubling" in ds:
        doubling = np.asarray(ds["period_doubling"].values, dtype=bool)
        if doubling.any():
            ax.plot(xs[doubling], ys[doubling], "x", color="tab:purple", ms=5, zorder=4)
            drawn.add("doubling")
    return drawn


_LEGEND = {
    "stable": Line2D([], [], color="0.2", ls="-", label="stable"),
    "unstable": Line2D([], [], color="0.2", ls="--", label="unstable"),
    "fold": Line2D([], [], ls="none", marker="o", mfc="none", mec="k", label="fold"),
    "lost": Line2D([], [], color="tab:red", lw=7, alpha=0.25, label="contact lost"),
    "doubling": Line2D([], [], ls="none", marker="x", color="tab:purple", label="period doubling"),
}


def legend_handles(kinds: set[str]) -> list[Line2D]:
    """Proxy artists for the kinds of marks drawn, in a fixed order."""
    return [handle for name, handle in _LEGEND.items() if name in kinds]


def response_figure(ds: Any) -> Figure:
    """The forced-response curve of one branch (see the module docstring)."""
    x = continuation_variable(ds)
    factor, symbol = length_unit(np.asarray(ds["amplitude"].values, dtype=float))
    fig = Figure(figsize=(7.5, 5.0), layout="constrained")
    ax = fig.subplots()
    kinds = draw_branch(ax, ds, x=x, y_factor=factor)
    x_unit = ds[x].attrs.get("units", "Hz" if x == "frequency" else "")
    label = "excitation frequency f" if x == "frequency" else "excitation amplitude"
    ax.set_xlabel(f"{label} [{x_unit}]")
    ax.set_ylabel(f"amplitude (y_max − y_min)/2 [{symbol}]")
    ax.set_ylim(bottom=0.0)
    params = model_parameters(ds)
    if params is not None:
        y0 = params.static_deflection * factor
        right = ax.secondary_yaxis("right", functions=(lambda a: a / y0, lambda r: r * y0))
        right.set_ylabel("amplitude / y0 [-]")
        if x == "frequency":
            f0 = params.natural_frequency
            top = ax.secondary_xaxis("top", functions=(lambda f: f / f0, lambda r: r * f0))
            top.set_xlabel("f / f0 [-]")
    ax.legend(handles=legend_handles(kinds), loc="best", fontsize=8)
    ax.grid(True, lw=0.4, alpha=0.5)
    excitation = ds.attrs.get("excitation", "")
    if excitation:  # the part names recorded by Model.to_attrs
        fig.suptitle(
            f"forced response: excitation {excitation}, damping {ds.attrs.get('damping', 'none')}"
        )
    return fig


def write_response_plot(ds: Any, path: str | Path, dpi: int = 150) -> Path:
    """Draw :func:`response_figure` to ``path`` (.png/.pdf/.svg), atomically."""
    fig = response_figure(ds)
    suffix = Path(path).suffix.lstrip(".")
    return write_atomically(path, lambda tmp: fig.savefig(tmp, dpi=dpi, format=suffix))
