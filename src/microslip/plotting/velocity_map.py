"""Fig. 7: the mean sliding velocity over tangential force and vibration amplitude."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from microslip.io.output import write_atomically
from microslip.model.parameters import Parameters


def velocity_map_figure(ds: xr.Dataset, params: Parameters | None = None) -> Figure:
    """(a) surface v(F, A) as in the paper; (b) filled contours with the analytic
    no-sliding boundary F = μ S c_n max(y0 - A, 0)^m2 and the contact-loss line A = y0."""
    params = Parameters() if params is None else params
    v = ds["mean_velocity"]
    if set(v.dims) != {"force", "amplitude"}:
        raise ValueError(f"a velocity map needs dims (force, amplitude), got {v.dims}")
    v = v.transpose("amplitude", "force")
    forces = ds["force"].values
    amps_um = ds["amplitude"].values * 1e6
    values = np.where(np.isfinite(v.values), v.values, np.nan) * 1e4  # [1e-4 m/s]
    y0_um = params.static_deflection * 1e6

    fig = Figure(figsize=(12.0, 5.2), layout="constrained")
    ax3 = fig.add_subplot(1, 2, 1, projection="3d")
    ff, aa = np.meshgrid(forces, amps_um)
    ax3.plot_surface(ff, aa, values, cmap="viridis", linewidth=0, antialiased=True)
    ax3.set_xlabel("F [N]")
    ax3.set_ylabel("A [µm]")
    ax3.set_zlabel("v [10⁻⁴ m/s]")
    ax3.view_init(elev=28, azim=-125)
    ax3.set_title("(a) mean sliding velocity v(F, A)")

    ax = fig.add_subplot(1, 2, 2)
    top = np.nanmax(values) if np.isfinite(np.nanmax(values)) and np.nanmax(values) > 0 else 1.0
    levels = MaxNLocator(nbins=20).tick_values(0.0, top)
    filled = ax.contourf(forces, amps_um, values, levels=levels, cmap="viridis")
    fig.colorbar(filled, ax=ax, label="v [10⁻⁴ m/s]")
    amp_line = np.linspace(0.0, amps_um.max(), 400)
    boundary = [params.motion_threshold(a * 1e-6) for a in amp_line]
    ax.plot(boundary, amp_line, color="white", lw=2.0, label="no-sliding boundary (analytic)")
    ax.axhline(y0_um, color="tab:red", lw=1.5, ls="--", label="A = y0 (loss of contact above)")
    ax.set_xlim(forces.min(), forces.max())
    ax.set_ylim(amps_um.min(), amps_um.max())
    ax.set_xlabel("tangential force F [N]")
    ax.set_ylabel("vibration amplitude A [µm]")
    ax.set_title(
        f"(b) v(F, A); μ = {params.mu:.3g}, F_t0 = μ m g = {params.static_friction_force:.3g} N"
    )
    ax.text(0.05 * forces.max() + 0.95 * forces.min(), 0.08 * y0_um, "no sliding", color="white")
    ax.legend(loc="upper right", fontsize=8, framealpha=0.8)
    return fig


def write_velocity_map_plot(
    ds: xr.Dataset, path: str | Path, params: Parameters | None = None, dpi: int = 150
) -> Path:
    """Render :func:`velocity_map_figure` to ``path`` (PNG, PDF or SVG), atomically."""
    fig = velocity_map_figure(ds, params)
    suffix = Path(path).suffix
    return write_atomically(path, lambda tmp: fig.savefig(tmp, dpi=dpi, format=suffix.lstrip(".")))
