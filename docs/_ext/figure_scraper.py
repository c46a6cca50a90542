"""A sphinx-gallery image scraper for ``matplotlib.figure.Figure`` objects.

microslip's plotting functions return :class:`matplotlib.figure.Figure` objects that
pyplot does not manage (no global figure state), so sphinx-gallery's own matplotlib
scraper, which asks pyplot for its open figures, would not see them. This scraper looks
at the example's global variables after each code block and saves every Figure it has
not saved before, in the order the variables were created. Figures made with pyplot are
left to the matplotlib scraper, listed after this one.
"""

from __future__ import annotations

import weakref
from pathlib import PurePosixPath
from typing import Any

from matplotlib.figure import Figure
from sphinx_gallery.scrapers import figure_rst

_SAVED: weakref.WeakSet[Figure] = weakref.WeakSet()
DPI = 110  # pixels per inch of the gallery images (the library's figures are 7-12 in wide)


def _titles(fig: Figure) -> str:
    titles = []
    if fig._suptitle is not None:
        titles.append(fig._suptitle.get_text())
    titles += [ax.get_title() for ax in fig.axes if ax.get_title()]
    return ", ".join(titles)


def scrape_figures(block: Any, block_vars: dict[str, Any], gallery_conf: dict[str, Any]) -> str:
    """Save the example's new Figure objects and return the reST that shows them."""
    new = []
    for value in list(block_vars["example_globals"].values()):
        candidates = value if isinstance(value, (tuple, list)) else (value,)
        for item in candidates:
            if isinstance(item, Figure) and item not in _SAVED and item not in new:
                new.append(item)
    paths, titles = [], []
    for fig, path in zip(new, block_vars["image_path_iterator"], strict=False):
        path = PurePosixPath(path)
        fig.savefig(path, dpi=DPI, format="png")
        _SAVED.add(fig)
        paths.append(path)
        titles.append(_titles(fig))
    if not paths:
        return ""
    return figure_rst(paths, gallery_conf["src_dir"], "; ".join(t for t in titles if t))
