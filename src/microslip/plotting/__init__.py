"""Plots of the model: the paper's Figs. 2–6 with the data behind them."""

from microslip.plotting.paper import (
    FIGURES,
    figure2,
    figure3,
    figure4,
    figure5,
    figure6,
    write_paper_figures,
)

__all__ = [
    "FIGURES",
    "figure2",
    "figure3",
    "figure4",
    "figure5",
    "figure6",
    "write_paper_figures",
]
