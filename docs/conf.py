"""Sphinx configuration of the microslip documentation (``make docs``).

Everything works offline: no intersphinx, MathJax served from the build itself
(``sphinx-mathjax-offline``), the gallery (``examples/``) and the tutorial
(``docs/tutorial/tutorial.py``, jupytext percent format, executed by myst-nb) run at
build time on the installed microslip.
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))

import matplotlib  # noqa: E402

matplotlib.use("Agg")  # before sphinx-gallery checks the backend

from api_pages import write_api_page  # noqa: E402

import microslip  # noqa: E402

write_api_page(HERE)

# -- project -----------------------------------------------------------------------------
project = "microslip"
author = "microslip contributors"
copyright = "2026, microslip contributors"
release = microslip.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "plain_docstrings",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",
    "sphinx.ext.viewcode",
    "myst_nb",
    "sphinx_gallery.gen_gallery",
    "sphinxarg.ext",
]

source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
root_doc = "index"
templates_path = ["_templates"]
exclude_patterns = [
    "_build",
    "_ext",
    "_templates",
    "conf.py",
    ".gitignore",
    "**/.ipynb_checkpoints",
    "jupyter_execute",
    # sphinx-gallery copies each example's source and notebook next to its page
    "auto_examples/**/*.py",
    "auto_examples/**/*.ipynb",
    "auto_examples/**/*.zip",
    "auto_examples/**/*.json",
    "auto_examples/**/*.md5",
]
suppress_warnings = ["config.cache"]  # sphinx-gallery's conf holds callables
nitpicky = False

# -- HTML --------------------------------------------------------------------------------
html_theme = "furo"
html_title = f"microslip {release}"
html_static_path = ["_static"]
html_css_files = ["microslip.css"]
html_show_sourcelink = False
html_theme_options = {"navigation_with_keys": True}

# -- API reference (numpy-style docstrings) ------------------------------------------------
autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_typehints_format = "short"
autodoc_preserve_defaults = True
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_ivar = True  # Attributes sections as field lists: no duplicate object entries
napoleon_use_rtype = False

# -- MyST and notebooks --------------------------------------------------------------------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
myst_dmath_double_inline = True
nb_custom_formats = {".py": ["jupytext.reads", {"fmt": "py:percent"}]}
nb_execution_mode = "force"  # the tutorial runs at every build
nb_execution_timeout = 600
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_execution_in_temp = True  # its output files land in a temporary directory
nb_merge_streams = True

# -- gallery -------------------------------------------------------------------------------
sphinx_gallery_conf = {
    "examples_dirs": ["../examples"],
    "gallery_dirs": ["auto_examples"],
    "filename_pattern": r"plot_",
    "ignore_pattern": r"__init__\.py|_common\.py",
    "subsection_order": ["../examples/paper", "../examples/extensions"],
    "within_subsection_order": "FileNameSortKey",
    "image_scrapers": ("figure_scraper.scrape_figures", "matplotlib"),
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
    "remove_config_comments": True,
    "download_all_examples": False,
    "show_signature": False,
    "min_reported_time": 1,
    "write_computation_times": False,  # its pages load jQuery from a CDN: the site is offline
}
