"""``write_figures``: every figure of the paper (Figs. 2–7) with the data behind each."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from microslip.io.output import write_dataset
from microslip.model.parameters import Parameters

# Fig. 7 grid: the paper's range of F below μ m g and of A up to past loss of contact.
FIG7_FORCES = np.linspace(0.05, 0.95, 181)  # [N]
FIG7_AMPLITUDES = np.linspace(0.0, 3.0e-7, 151)  # [m]


def write_figure7(out_dir: Path, params: Parameters, dpi: int = 150) -> list[Path]:
    """fig7.png and fig7.nc: the mean-velocity map v(F, A), exact steady state."""
    from microslip.plotting.velocity_map import write_velocity_map_plot
    from microslip.sweeps import SweepSpec, run_sweep

    spec = SweepSpec.build(
        params, None, FIG7_FORCES, FIG7_AMPLITUDES, amplitude_chunk=FIG7_AMPLITUDES.size
    )
    ds = run_sweep(spec)
    return [
        write_dataset(ds, out_dir / "fig7.nc"),
        write_velocity_map_plot(ds, out_dir / "fig7.png", params, dpi=dpi),
    ]


def write_figures(
    out_dir: str | Path,
    params: Parameters | None = None,
    names: Sequence[str] = ("fig2", "fig3", "fig4", "fig5", "fig6", "fig7"),
    *,
    dpi: int = 150,
    progress: Callable[[str], None] | None = None,
) -> list[Path]:
    """Write ``figN.png`` and ``figN.nc`` for each requested figure into ``out_dir``."""
    from microslip.plotting.paper import write_paper_figures

    params = Parameters() if params is None else params
    out_dir = Path(out_dir)
    say = progress or (lambda message: None)
    paths: list[Path] = []
    time_domain = tuple(n for n in names if n != "fig7")
    if time_domain:
        paths += write_paper_figures(out_dir, params, figures=time_domain, dpi=dpi, progress=say)
    if "fig7" in names:
        say("fig7: mean sliding velocity map v(F, A)")
        paths += write_figure7(out_dir, params, dpi=dpi)
    return paths
