"""The documentation builds with no warning, and the site works the way a reader uses it.

The docs (docs/, examples/) are copied to a scratch directory and built there exactly as
``make docs`` builds them (``sphinx-build -W --keep-going``): the gallery examples and
the tutorial run on the installed microslip. The built site is then checked from its HTML
files, without a browser (tools/docs/check_site.py): every local link and ``#anchor``
resolves, every image is a non-empty image file of the site, no script needs the
network. ``make docs-check`` adds screenshots in headless Chromium
(tools/docs/screenshots.py), which CI does not install.
"""

from __future__ import annotations

import importlib.util
import re
import shutil
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BUILD_TIMEOUT_S = 600
# What the build writes into the source tree: never copied, so the build starts clean.
_GENERATED = {"_build", "auto_examples", "generated", "jupyter_execute", "__pycache__"}


def _load_checker():
    spec = importlib.util.spec_from_file_location("check_site", ROOT / "tools/docs/check_site.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["check_site"] = module  # dataclasses look their module up by name
    spec.loader.exec_module(module)
    return module


check_site = _load_checker()


def _ignore(directory: str, names: list[str]) -> list[str]:
    skip = [name for name in names if name in _GENERATED]
    if Path(directory).name == "api" and "index.rst" in names:
        skip.append("index.rst")  # written by docs/_ext/api_pages.py
    return skip


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> dict:
    """Build the docs from a clean copy; the HTML root and the build's output."""
    work = tmp_path_factory.mktemp("docs")
    shutil.copytree(ROOT / "docs", work / "docs", ignore=_ignore)
    shutil.copytree(ROOT / "examples", work / "examples", ignore=_ignore)
    for name in ("CHANGELOG.md", "CITATION.cff", "LICENSE"):  # included by docs pages
        shutil.copy2(ROOT / name, work / name)
    html = work / "html"
    result = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-b", "html",
         "-d", str(work / "doctrees"), str(work / "docs"), str(html)],
        capture_output=True, text=True, timeout=BUILD_TIMEOUT_S, cwd=work,
    )  # fmt: skip
    return {"html": html, "result": result, "output": result.stdout + result.stderr}


class _Text(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.parts: list[str] = []
        self._skip = 0

    def handle_starttag(self, tag, attrs):
        self._skip += tag in ("script", "style")

    def handle_endtag(self, tag):
        self._skip -= tag in ("script", "style")

    def handle_data(self, data):
        if not self._skip:
            self.parts.append(data)


def text_of(path: Path) -> str:
    parser = _Text()
    parser.feed(path.read_text(encoding="utf-8"))
    return " ".join(" ".join(parser.parts).split())


# -- the checker itself can fail -------------------------------------------------------------
def test_checker_finds_broken_links_anchors_and_images(tmp_path):
    (tmp_path / "img").mkdir()
    (tmp_path / "img" / "ok.png").write_bytes(b"\x89PNG\r\n\x1a\n" + b"0" * 32)
    (tmp_path / "img" / "empty.png").write_bytes(b"")
    (tmp_path / "img" / "text.png").write_text("not an image")
    (tmp_path / "page.html").write_text('<html><body><h1 id="top">t</h1></body></html>')
    (tmp_path / "index.html").write_text(
        "<html><body>"
        '<a href="page.html#top">ok</a> <a href="page.html#nowhere">bad anchor</a>'
        '<a href="missing.html">missing</a> <a href="#here">self</a><p id="here"></p>'
        '<a href="https://example.org">external</a>'
        '<img src="img/ok.png"><img src="img/empty.png"><img src="img/text.png">'
        '<img src="img/gone.png"><script src="https://cdn.example.org/x.js"></script>'
        "</body></html>"
    )
    report = check_site.check_site(tmp_path)
    problems = "\n".join(report.problems)
    assert "nowhere" in problems and "missing.html" in problems
    assert "empty.png" in problems and "text.png" in problems and "gone.png" in problems
    assert "needs the network" in problems
    assert len(report.problems) == 6, problems
    assert report.images_by_page["index.html"] == 1


# -- the build ---------------------------------------------------------------------------------
def test_docs_build_without_warnings(site):
    result = site["result"]
    tail = site["output"][-4000:]
    assert result.returncode == 0, tail
    assert "build succeeded" in site["output"], tail
    # -W turns every Sphinx warning into a failure; this also catches one printed by an
    # example or the tutorial in Sphinx's format (the kernel's own log lines are not)
    assert not re.search(r"(WARNING|ERROR): ", site["output"]), tail


def test_every_link_anchor_and_image_resolves_offline(site):
    report = check_site.check_site(site["html"])
    assert report.pages > 50 and report.images >= 20
    assert report.ok, "\n".join(report.problems[:40])


def test_mathjax_is_served_by_the_site(site):
    html = site["html"]
    assert (html / "_static" / "mathjax" / "tex-chtml.js").stat().st_size > 10_000
    page = (html / "theory" / "steady_sliding.html").read_text(encoding="utf-8")
    assert "_static/mathjax/tex-chtml.js" in page
    assert r"\min_{0 \le s \le t} G(s)" in page  # an equation handed to MathJax


# A line each example prints from its own computation, beside the paper's statement.
_PRINTED = {
    2: "f0 = 1485.0 Hz",
    3: "max |R| = 3.0000 m g",
    4: "A = 0.000 y0: threshold 0.981 N -> stays",
    5: "per cycle",
    6: "in flight: max |R| = 0.0 N",
    7: "v == 0 wherever F < threshold: True",
}


def test_gallery_has_one_example_per_paper_figure_with_images(site):
    html = site["html"]
    report = check_site.check_site(html)
    for figure in range(2, 8):
        pages = sorted((html / "auto_examples" / "paper").glob(f"plot_fig{figure}_*.html"))
        assert len(pages) == 1, (figure, pages)
        key = pages[0].relative_to(html).as_posix()
        assert report.images_by_page[key] >= 1, key
        text = text_of(pages[0])
        assert "The paper’s figure" in text or "The paper's figure" in text
        assert _PRINTED[figure] in text, (figure, _PRINTED[figure])  # the example ran
    for name in ("plot_forced_response", "plot_friction_under_excitation"):
        key = f"auto_examples/extensions/{name}.html"
        assert report.images_by_page[key] >= 2, key


def test_every_public_name_has_an_api_page(site):
    import microslip

    generated = site["html"] / "api" / "generated"
    for name in microslip.__all__:
        if name.startswith("__"):
            continue
        page = generated / f"microslip.{name}.html"
        assert page.is_file(), name
        doc = (getattr(microslip, name).__doc__ or "").strip().splitlines()
        assert doc, f"microslip.{name} has no docstring"
        first_words = " ".join(doc[0].split()[:3]).rstrip(".,:")
        assert first_words.split()[0] in text_of(page), (name, first_words)


def test_cli_page_lists_every_command_and_flag(site):
    import argparse

    from microslip.cli.parser import build_parser

    text = text_of(site["html"] / "cli.html")
    parser = build_parser()
    commands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    assert set(commands.choices) >= {"info", "simulate", "figures", "map", "sweep", "response"}
    for name, sub in commands.choices.items():
        assert f"microslip {name}" in text, name
        for action in sub._actions:
            for flag in action.option_strings:
                if flag.startswith("--") and flag != "--help":
                    assert flag in text, (name, flag)


def test_tutorial_ran_in_the_build(site):
    page = site["html"] / "tutorial" / "tutorial.html"
    report = check_site.check_site(site["html"])
    assert report.images_by_page["tutorial/tutorial.html"] >= 4
    text = text_of(page)
    assert "identical to the in-process sweep: True" in text
    assert "scheduler: tcp://127.0.0.1:" in text


def test_theory_and_howto_pages_are_in_the_site(site):
    html = site["html"]
    for page in (
        "theory/paper_model", "theory/free_vibration", "theory/steady_sliding",
        "theory/extensions", "theory/periodic_orbits", "theory/numerics",
        "theory/friction_reduction", "theory/stick_slip_drive",
        "howto/choose_method", "howto/resume_sweep", "howto/read_netcdf", "howto/add_law",
        "design", "model-facts", "changelog", "citing",
    ):  # fmt: skip
        assert (html / f"{page}.html").is_file(), page
    numerics = text_of(html / "theory" / "numerics.html")
    assert "order 2" in numerics
