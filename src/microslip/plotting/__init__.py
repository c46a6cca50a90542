"""Plots of the model: the paper's Figs. 2–7 with the data behind them, and sweep plots."""

from microslip.plotting.paper import (
    FIGURES,
    figure2,
    figure3,
    figure4,
    figure5,
    figure6,
    write_paper_figures,
)
from microslip.plotting.scales import FigureNotDrawable
from microslip.plotting.velocity_map import sweep_figure, velocity_map_figure

__all__ = [
    "FIGURES",
    "FigureNotDrawable",
    "figure2",
    "figure3",
    "figure4",
    "figure5",
    "figure6",
    "sweep_figure",
    "velocity_map_figure",
    "write_paper_figures",
]
