"""A quick-look plot of one simulated trajectory (``microslip simulate --plot``)."""

from __future__ import annotations

from pathlib import Path

from matplotlib.figure import Figure

from microslip.io.output import write_atomically
from microslip.results import SimulationResult


def trajectory_figure(result: SimulationResult) -> Figure:
    """Four panels against t [ms]: y, forces (|F_t|, μ|R|, F), x and ẋ."""
    t_ms = result.t * 1e3
    fig = Figure(figsize=(8.0, 8.0), layout="constrained")
    axes = fig.subplots(4, 1, sharex=True)
    axes[0].plot(t_ms, result.y * 1e6, lw=1.0)
    axes[0].axhline(0.0, color="0.6", lw=0.8, ls=":")
    axes[0].set_ylabel("y [µm]")
    axes[1].plot(t_ms, result.friction_limit, lw=0.8, color="0.5", label="μ|R| (limit)")
    axes[1].plot(t_ms, abs(result.Ft), lw=1.2, label="|F_t|")
    axes[1].axhline(result.force, color="k", lw=1.0, ls="--", label="F")
    axes[1].set_ylabel("force [N]")
    axes[1].legend(loc="upper right", fontsize=8)
    axes[2].plot(t_ms, result.x * 1e6, lw=1.2)
    axes[2].set_ylabel("x [µm]")
    axes[3].plot(t_ms, result.xdot * 1e3, lw=1.0)
    axes[3].set_ylabel("ẋ [mm/s]")
    axes[3].set_xlabel("t [ms]")
    fig.suptitle(f"F = {result.force:g} N, method = {result.method}")
    return fig


def write_trajectory_plot(result: SimulationResult, path: str | Path, dpi: int = 150) -> Path:
    fig = trajectory_figure(result)
    suffix = Path(path).suffix.lstrip(".")
    return write_atomically(path, lambda tmp: fig.savefig(tmp, dpi=dpi, format=suffix))
