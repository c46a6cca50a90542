"""``write_figures``: every figure of the paper (Figs. 2–7) with the data behind each,
and, by name, the extensions' figures (:mod:`microslip.plotting.extensions`)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from microslip.io.output import write_dataset
from microslip.model.parameters import Parameters
from microslip.plotting.scales import (
    FigureNotDrawable,
    combine_refusals,
    figure_scales,
    require_friction,
)

__all__ = [
    "EXTENSION_FIGURES",
    "FIG7_AMPLITUDES",
    "FIG7_FORCES",
    "check_drawable",
    "fig7_grid",
    "write_figure7",
    "write_figures",
]

# Figures of stick-slip under dry friction, driven by a fraction of mu m g (Sec. 4)
_NEED_FRICTION = (
    "fig4", "fig5", "fig6", "fig7", "forced_velocity_map", "contact_loss",
    "friction_master_curve", "mu_eff_map", "spring_stick_slip",
)  # fmt: skip

#: The extensions' figures (drawn by :func:`microslip.plotting.extensions.write_extension_figures`)
EXTENSION_FIGURES = (
    "forced_response", "forced_velocity_map", "contact_loss",
    "friction_master_curve", "mu_eff_map", "spring_stick_slip",
)  # fmt: skip


def check_drawable(params: Parameters, names: Sequence[str]) -> None:
    """Raise :class:`FigureNotDrawable` naming every figure of ``names`` that has no
    meaning for ``params``, before anything is computed (so a refused request costs
    nothing and writes nothing)."""
    refused: list[FigureNotDrawable] = []
    for name in names:
        if name in _NEED_FRICTION:
            try:
                require_friction(params, name)
            except FigureNotDrawable as error:
                refused.append(error)
    if refused:
        raise combine_refusals(refused, [])


# Fig. 7 grid for the paper's data: F below μ m g = 0.981 N, A up to past loss of contact
# (y0 = 0.225 µm). Other data: F times μ m g and A times y0 relative to the paper's.
FIG7_FORCES = np.linspace(0.05, 0.95, 181)  # [N]
FIG7_AMPLITUDES = np.linspace(0.0, 3.0e-7, 151)  # [m]


def fig7_grid(params: Parameters) -> tuple[np.ndarray, np.ndarray]:
    """Forces [N] and amplitudes [m] of the Fig. 7 map for ``params``.

    The paper's grid, with F scaled by μ m g and A by y0, so that it covers the same
    part of the map (F/(μ m g) from 0.05 to 0.97, A/y0 from 0 to 1.33).
    FigureNotDrawable for μ = 0, where every F > 0 accelerates the slider for ever.
    """
    require_friction(params, "fig7")
    scales = figure_scales(params)
    return FIG7_FORCES * scales.force_ratio, FIG7_AMPLITUDES * scales.length_ratio


def write_figure7(out_dir: Path, params: Parameters, dpi: int = 150) -> list[Path]:
    """fig7.png and fig7.nc: the mean-velocity map v(F, A), exact steady state."""
    from microslip.plotting.velocity_map import write_velocity_map_plot
    from microslip.sweeps import SweepSpec, run_sweep

    forces, amplitudes = fig7_grid(params)
    spec = SweepSpec.build(params, None, forces, amplitudes, amplitude_chunk=amplitudes.size)
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
    """Write ``NAME.png`` and ``NAME.nc`` for each requested figure into ``out_dir``
    (the paper's ``figN``, or the names of :data:`EXTENSION_FIGURES`).

    Returns the files written. A figure that has no meaning for ``params`` (Figs. 4–7
    for μ = 0) is skipped; after the others are written, :class:`FigureNotDrawable`
    (a ValueError) names each skipped figure and why, with the written files in its
    ``written`` attribute.
    """
    from microslip.plotting.paper import write_paper_figures

    params = Parameters() if params is None else params
    out_dir = Path(out_dir)
    say = progress or (lambda message: None)
    paths: list[Path] = []
    refused: list[FigureNotDrawable] = []
    extensions = tuple(n for n in names if n in EXTENSION_FIGURES)
    if extensions:
        from microslip.plotting.extensions import write_extension_figures

        paths += write_extension_figures(out_dir, params, extensions, dpi=dpi, progress=say)
        names = tuple(n for n in names if n not in EXTENSION_FIGURES)
    time_domain = tuple(n for n in names if n != "fig7")
    if time_domain:
        try:
            paths += write_paper_figures(
                out_dir, params, figures=time_domain, dpi=dpi, progress=say
            )
        except FigureNotDrawable as error:
            paths += error.written
            refused.append(error)
    if "fig7" in names:
        say("fig7: mean sliding velocity map v(F, A)")
        try:
            paths += write_figure7(out_dir, params, dpi=dpi)
        except FigureNotDrawable as error:
            say(f"fig7: not drawn: {error.reason}")
            refused.append(error)
    if refused:
        raise combine_refusals(refused, paths)
    return paths
