"""Write ``api/index.rst``: the API reference, autosummary tables of the public names.

The list is read from the package itself (``microslip.__all__`` and the ``__all__`` of
the plotting modules) when the docs are built, so a name added to the public API is
documented without editing the docs; the names are grouped by the module that defines
them. Called from ``conf.py`` before Sphinx reads the sources; the page is not kept in git
(docs/.gitignore).
"""

from __future__ import annotations

import importlib
import inspect
from pathlib import Path

# (title, one-line description, test on (name, object, defining module))
_GROUPS = [
    (
        "Errors",
        "Raised by the analyses; each is a ``ValueError`` with a one-line message.",
        lambda name, obj, module: inspect.isclass(obj) and issubclass(obj, Exception),
    ),
    (
        "Model: constants and parts",
        "The paper's constants and the optional parts a :class:`~microslip.Model` "
        "composes (see :doc:`../design`).",
        lambda name, obj, module: module.startswith("microslip.model"),
    ),
    (
        "Simulation",
        "Time integration with located switching (:doc:`../theory/numerics`).",
        lambda name, obj, module: module in ("microslip.simulation", "microslip.results"),
    ),
    (
        "Sweeps",
        "Mean velocity over grids, in process or on a Dask cluster (:doc:`../howto/resume_sweep`).",
        lambda name, obj, module: module.startswith("microslip.sweeps"),
    ),
    (
        "Analyses",
        "Free vibration, exact steady state, periodic orbits and continuation "
        "(:doc:`../theory/index`).",
        lambda name, obj, module: True,
    ),
]

_PLOTTING = [
    ("microslip.plotting", "The paper's figures and sweep plots."),
    ("microslip.plotting.response", "The forced-response curve."),
    ("microslip.plotting.extensions", "The extension figures (``make figures-ext``)."),
    ("microslip.plotting.trajectory", "A quick look at one simulated trajectory."),
]


_INTRO = [
    "Generated from the docstrings (numpy style) of the installed package. Every quantity",
    "is in SI units; the docstrings state the unit of each argument and result. The",
    "public names are imported lazily: ``import microslip`` loads numba, xarray and dask",
    "only when a name that needs them is first used. The command line is described in",
    ":doc:`../cli`.",
]


def _table(module: str, names: list[str]) -> list[str]:
    lines = [f".. currentmodule:: {module}", "", ".. autosummary::", "   :toctree: generated", ""]
    return lines + [f"   {name}" for name in names] + [""]


def _defining_module(package, name: str) -> str:
    exports = getattr(package, "_EXPORTS", {})
    if name in exports:
        return exports[name]
    return getattr(getattr(package, name), "__module__", "") or ""


def api_text() -> str:
    """The reST of the generated API page."""
    import microslip

    names = [name for name in microslip.__all__ if not name.startswith("__")]
    remaining = sorted(names, key=str.lower)
    lines = [".. This file is written by docs/_ext/api_pages.py at build time; do not edit.", ""]
    lines += ["API reference", "=" * 13, "", *_INTRO, ""]
    lines += ["Public names: ``import microslip as ms``", "-" * 41, ""]
    for title, description, test in _GROUPS:
        chosen = []
        for name in remaining:
            obj = getattr(microslip, name)
            if test(name, obj, _defining_module(microslip, name)):
                chosen.append(name)
        remaining = [name for name in remaining if name not in chosen]
        if chosen:
            lines += [title, "~" * len(title), "", description, ""]
            lines += _table("microslip", chosen)
    lines += ["Plotting", "-" * 8, ""]
    lines += [
        "Every function returns a :class:`matplotlib.figure.Figure` (no pyplot state) and, for "
        "the paper's figures, the :class:`xarray.Dataset` behind it (SI units).",
        "",
    ]
    for module_name, description in _PLOTTING:
        module = importlib.import_module(module_name)
        public = getattr(module, "__all__", None) or [
            name for name, obj in vars(module).items()
            if inspect.isfunction(obj) and obj.__module__ == module_name
            and not name.startswith("_")
        ]  # fmt: skip
        callables = [
            name for name in public
            if inspect.isfunction(getattr(module, name)) or inspect.isclass(getattr(module, name))
        ]  # fmt: skip
        title = f"``{module_name}``"
        lines += [title, "~" * len(title), "", description, ""]
        lines += _table(module_name, sorted(callables, key=str.lower))
    return "\n".join(lines) + "\n"


def write_api_page(srcdir: str | Path) -> Path:
    """Write ``api/index.rst`` under ``srcdir`` when its text changed (keeps Sphinx's
    incremental build incremental)."""
    path = Path(srcdir) / "api" / "index.rst"
    path.parent.mkdir(exist_ok=True)  # api/ holds only generated files (not in git)
    text = api_text()
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")
    return path
