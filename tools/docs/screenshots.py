"""Look at the built site in a real browser: headless Chromium screenshots of key pages.

For each page (the index, a gallery example, an API page, a theory page with equations,
the tutorial) Chromium loads the file, runs its scripts (MathJax typesets the
equations), and

- writes a screenshot ``NAME.png`` to ``--out``, which must not be blank (a page whose
  styles or images failed shows as nearly uniform);
- dumps the DOM after the scripts ran: the equations of a theory page must have been
  typeset by MathJax (``mjx-container`` elements), and every ``<img>`` of the page must
  point to a file of the site.

Chromium is not a Python package: on Debian, ``apt-get install chromium``. Without it
this script fails with a message saying so (``make docs-check``); CI does not run it:
tests/integration/test_docs.py checks the same links and images from the HTML files
without a browser.

    python tools/docs/screenshots.py docs/_build/html --out docs/_build/screenshots
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
PAGES = {
    "index": "index.html",
    "gallery_fig7": "auto_examples/paper/plot_fig7_velocity_map.html",
    "gallery_index": "auto_examples/index.html",
    "api_simulate": "api/generated/microslip.simulate.html",
    "theory_steady_sliding": "theory/steady_sliding.html",
    "tutorial": "tutorial/tutorial.html",
}
MATH_PAGES = ("theory_steady_sliding",)
SIZE = (1280, 1800)  # window width, height [px]


def find_browser() -> str:
    for name in BROWSERS:
        path = shutil.which(name)
        if path:
            return path
    raise SystemExit(
        "screenshots: no Chromium found (tried " + ", ".join(BROWSERS) + "); on Debian: "
        "apt-get install chromium"
    )


def _run(browser: str, args: list[str], timeout: float = 90.0) -> subprocess.CompletedProcess:
    with tempfile.TemporaryDirectory() as profile:
        command = [
            browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
            "--no-first-run", "--allow-file-access-from-files", f"--user-data-dir={profile}",
            "--virtual-time-budget=8000", f"--window-size={SIZE[0]},{SIZE[1]}", *args,
        ]  # fmt: skip
        return subprocess.run(command, capture_output=True, text=True, timeout=timeout)


def screenshot(browser: str, url: str, out: Path) -> None:
    result = _run(browser, [f"--screenshot={out}", url])
    if not out.is_file() or out.stat().st_size == 0:
        raise RuntimeError(f"no screenshot of {url}: {result.stderr.strip()[-500:]}")


def dump_dom(browser: str, url: str) -> str:
    return _run(browser, ["--dump-dom", url]).stdout


def blankness(png: Path) -> float:
    """Standard deviation of the screenshot's grey levels (0 for a uniform image)."""
    import matplotlib.image

    pixels = np.asarray(matplotlib.image.imread(png), dtype=float)
    grey = pixels[..., :3].mean(axis=-1) if pixels.ndim == 3 else pixels
    return float(grey.std())


def check(site: Path, out: Path) -> list[str]:
    browser = find_browser()
    out.mkdir(parents=True, exist_ok=True)
    problems = []
    for name, page in PAGES.items():
        path = (site / page).resolve()
        if not path.is_file():
            problems.append(f"{page}: not in the site")
            continue
        url = path.as_uri()
        png = out / f"{name}.png"
        screenshot(browser, url, png)
        spread = blankness(png)
        if spread < 0.02:
            problems.append(f"{page}: the screenshot is nearly blank (grey std {spread:.3f})")
        dom = dump_dom(browser, url)
        if "</html>" not in dom:
            problems.append(f"{page}: the browser returned no DOM")
            continue
        for src in re.findall(r'<img[^>]*\ssrc="([^"]+)"', dom):
            if src.startswith(("data:", "http:", "https:")):
                continue
            if not (path.parent / src.split("#")[0].split("?")[0]).resolve().is_file():
                problems.append(f"{page}: image {src!r} does not resolve")
        if name in MATH_PAGES and "mjx-container" not in dom:
            problems.append(f"{page}: MathJax typeset no equation (no mjx-container)")
        print(f"{name}: {png} (grey std {spread:.3f})")
    return problems


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("site", type=Path, help="root of the built HTML site")
    parser.add_argument("--out", type=Path, default=Path("docs/_build/screenshots"))
    args = parser.parse_args(argv)
    problems = check(args.site, args.out)
    for problem in problems:
        print(problem)
    print(f"{len(PAGES)} pages looked at in Chromium: {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
