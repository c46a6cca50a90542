"""Figures 2–6 of Grudziński & Kostek (2005), redrawn from the model, with their data.

For other parameters than the paper's, the drive F = 0.5 N, the amplitudes, the time
windows and the units of every axis follow the parameter set's own scales (μ m g, y0,
T0; :mod:`microslip.plotting.scales`), so each figure shows the same phenomena; a figure
that has no meaning for a parameter set (Figs. 4–6 for μ = 0) raises
:class:`FigureNotDrawable`, and :func:`write_paper_figures` still writes the others.
Figs. 2–3 are drawn in :mod:`~microslip.plotting.paper_free`, Figs. 4–6 in
:mod:`~microslip.plotting.paper_stick_slip`.

Each ``figureN(params)`` returns a :class:`matplotlib.figure.Figure` (Agg canvas, no
pyplot state) and the :class:`xarray.Dataset` behind it (SI units, every variable and
coordinate with a ``units`` attribute). :func:`write_paper_figures` writes them as
``figN.png`` and ``figN.nc``, each file atomically.

Sign conventions follow :class:`microslip.SimulationResult`: y > 0 is penetration (the
slider's descent), |R| is the compressive reaction, and F_t is signed as in (2.5), so
the friction force opposing forward sliding is negative; the plots show its magnitude
|F_t| against the drive F as the paper does. The data are stored in SI units; the
plots use scaled units (µm, ms, mm/s, …) that are written on every axis.

Layout (panel letters as in the paper's captions and text):

- Fig. 2: (a) load–deflection characteristic |R|(y) with the working point C and the
  range each vibration covers; (b) y(t), (c) ẏ(t) of the free vibrations with
  A = y0/3, 2y0/3, y0; (d) their phase portraits.
- Fig. 3: the largest contact-keeping free vibration, A = y0: (a) y(t), (b) |R|(t) and
  F_t = μ|R|(t), from 0 to 3 m g.
- Fig. 4: F = 0.5 N, columns 1–4 for A = 0, y0/3, 2y0/3, y0; rows (a) y, (b) ẏ, (c) ÿ,
  (d) |R|, (e) friction against F (columns 1–4), (f) x, (g) ẋ, (h) ẍ (columns 1′–4′).
- Fig. 5: the two largest amplitudes of Fig. 4: (a), (b) F and the friction force
  against t (thin: potential static friction μ|R| while sticking); (c) friction against
  ẋ while sliding; (d), (e) ẋ(t); (f) the x–ẋ phase plane while sliding, x counted
  from each release so that the steady cycles fall on one limit-cycle arch.
- Fig. 6: A = 1.3 y0 (momentary loss of contact), F = 0.5 N: (a) y, (b) ẏ, (c) phase
  portrait, (d) |R|, (e) friction against F, (f) x, (g) ẋ, (h) ẍ.
"""

from __future__ import annotations

import numbers
from collections.abc import Callable, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # no display; figures are built with matplotlib.figure.Figure

import xarray as xr
from matplotlib.figure import Figure

from microslip.io.output import write_atomically, write_dataset
from microslip.model.parameters import Parameters
from microslip.plotting.paper_free import figure2, figure3
from microslip.plotting.paper_stick_slip import figure4, figure5, figure6
from microslip.plotting.scales import (
    PAPER_FORCE,
    FigureNotDrawable,
    combine_refusals,
)

__all__ = [
    "FIGURES",
    "PAPER_FORCE",
    "FigureNotDrawable",
    "figure2",
    "figure3",
    "figure4",
    "figure5",
    "figure6",
    "write_paper_figures",
]


# -- writing ---------------------------------------------------------------------------

FIGURES: dict[str, Callable[[Parameters], tuple[Figure, xr.Dataset]]] = {
    "fig2": figure2,
    "fig3": figure3,
    "fig4": figure4,
    "fig5": figure5,
    "fig6": figure6,
}


def write_paper_figures(
    out_dir: str | Path,
    params: Parameters | None = None,
    *,
    figures: Sequence[str] = ("fig2", "fig3", "fig4", "fig5", "fig6"),
    dpi: int = 150,
    progress: Callable[[str], None] | None = None,
) -> list[Path]:
    """Write ``figN.png`` and ``figN.nc`` (its data, SI units) for each requested figure.

    Parameters
    ----------
    out_dir : path
        Output directory (created if missing).
    params : Parameters, optional
        Model constants; the paper's data by default.
    figures : sequence of {"fig2", ..., "fig6"}
        Which figures to write.
    dpi : int
        Resolution of the PNG files [dots per inch].
    progress : callable, optional
        Called with a short message as each figure is computed and written.

    Returns
    -------
    list of Path
        The files written, PNG then NetCDF for each figure, in the order requested.
        Each file is written to a temporary name and renamed, so no partial file is
        left behind on error.

    Raises
    ------
    FigureNotDrawable
        After writing every other figure, when some figure has no meaning for
        ``params`` (e.g. Figs. 4–6 for μ = 0); its ``written`` holds the files written.
    """
    params = Parameters() if params is None else params
    if not isinstance(params, Parameters):
        raise ValueError(f"params must be a microslip.Parameters, got {type(params).__name__}")
    if isinstance(figures, str):
        figures = (figures,)
    unknown = [name for name in figures if name not in FIGURES]
    if unknown:
        raise ValueError(f"unknown figure {unknown[0]!r}; known: {', '.join(FIGURES)}")
    if isinstance(dpi, bool) or not isinstance(dpi, numbers.Integral) or dpi <= 0:
        raise ValueError(f"dpi must be a positive integer, got {dpi!r}")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    refused: list[FigureNotDrawable] = []
    for name in figures:
        if progress is not None:
            progress(f"{name}: computing")
        try:
            fig, ds = FIGURES[name](params)
        except FigureNotDrawable as error:  # say so at the end; draw the others first
            refused.append(error)
            if progress is not None:
                progress(f"{name}: not drawn: {error.reason}")
            continue
        png = out / f"{name}.png"
        nc = out / f"{name}.nc"
        write_atomically(png, lambda tmp, fig=fig: fig.savefig(tmp, format="png", dpi=dpi))
        write_dataset(ds, nc)
        written += [png, nc]
        if progress is not None:
            progress(f"{name}: wrote {png.name}, {nc.name}")
    if refused:
        raise combine_refusals(refused, written)
    return written
