"""Reading a drawn figure back in the figure tests."""

import numpy as np


def curves(ax, text: str = "") -> list:
    """The data lines of an axes (not the reference lines), those labelled with ``text``."""
    return [
        line
        for line in ax.get_lines()
        if np.size(line.get_xdata()) > 2 and text in str(line.get_label())
    ]
