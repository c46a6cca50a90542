"""Check a built HTML site the way a browser would load it: links, anchors and images.

Every ``.html`` file under the site root is parsed (standard library only). For every
local reference it checks what a reader's browser would need:

- ``<a href>`` and ``<link href>``: the target file exists (a directory means its
  ``index.html``), and a ``#fragment`` names an ``id`` (or ``name``) in the target page;
- ``<img src>`` / ``srcset`` and ``<script src>``: the file exists and is not empty; an
  image starts like a PNG, JPEG, GIF, WebP or SVG file.

External references (``http:``, ``https:``, ``mailto:``, ``data:``) are not followed: the
site must work offline. Used by ``make docs-check`` and by
``tests/integration/test_docs.py``::

    python tools/docs/check_site.py docs/_build/html
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass, field
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

_EXTERNAL = ("http", "https", "mailto", "data", "javascript", "ftp", "tel")
_IMAGE_MAGIC = (b"\x89PNG\r\n\x1a\n", b"\xff\xd8\xff", b"GIF87a", b"GIF89a", b"RIFF")


@dataclass
class Page:
    """What one HTML file defines and references."""

    ids: set[str] = field(default_factory=set)
    links: list[tuple[str, int]] = field(default_factory=list)  # (href, line)
    images: list[tuple[str, int]] = field(default_factory=list)  # (src, line)
    scripts: list[tuple[str, int]] = field(default_factory=list)


class _Parser(HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.page = Page()

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = {name: value for name, value in attrs if value is not None}
        line = self.getpos()[0]
        for key in ("id", "name") if tag in ("a", "span", "div", "section") else ("id",):
            if key in a:
                self.page.ids.add(a[key])
        if tag in ("a", "link", "area") and "href" in a:
            if tag == "link" and a.get("rel", "") in ("preconnect", "dns-prefetch"):
                return
            self.page.links.append((a["href"], line))
        if tag in ("img", "source"):
            if "src" in a:
                self.page.images.append((a["src"], line))
            for part in a.get("srcset", "").split(","):
                if part.strip():
                    self.page.images.append((part.strip().split()[0], line))
        if tag == "script" and "src" in a:
            self.page.scripts.append((a["src"], line))


def parse(path: Path) -> Page:
    parser = _Parser()
    parser.feed(path.read_text(encoding="utf-8", errors="replace"))
    parser.close()
    return parser.page


def _is_external(ref: str) -> bool:
    scheme = urlsplit(ref).scheme.lower()
    return (bool(scheme) and scheme in _EXTERNAL) or ref.startswith("//")


def _resolve(page: Path, ref: str) -> tuple[Path, str]:
    """(target file, fragment) of a local reference from ``page``."""
    parts = urlsplit(ref)
    target = page if not parts.path else (page.parent / unquote(parts.path))
    target = target.resolve()
    if target.is_dir():
        target = target / "index.html"
    return target, unquote(parts.fragment)


def _looks_like_image(path: Path) -> bool:
    head = path.read_bytes()[:512]
    if path.suffix.lower() == ".svg":
        return b"<svg" in head or b"<?xml" in head
    return head.startswith(_IMAGE_MAGIC)


@dataclass
class Report:
    root: Path
    pages: int = 0
    links: int = 0
    images: int = 0
    problems: list[str] = field(default_factory=list)
    images_by_page: dict[str, int] = field(default_factory=dict)  # distinct image files shown

    @property
    def ok(self) -> bool:
        return not self.problems


def check_site(root: str | Path) -> Report:
    """Check every HTML file under ``root``; the problems name the page, line and target."""
    root = Path(root).resolve()
    report = Report(root)
    if not (root / "index.html").is_file():
        report.problems.append(f"{root}: no index.html")
        return report
    pages = {path: parse(path) for path in sorted(root.rglob("*.html"))}
    report.pages = len(pages)
    cache: dict[Path, Page] = dict(pages)
    for path, page in pages.items():
        where = path.relative_to(root)
        for ref, line in page.links:
            if _is_external(ref) or ref in ("", "#"):
                continue
            report.links += 1
            target, fragment = _resolve(path, ref)
            if not target.is_file():
                report.problems.append(f"{where}:{line}: link {ref!r}: {target} does not exist")
                continue
            if fragment and target.suffix == ".html":
                if target not in cache:
                    cache[target] = parse(target)
                if fragment not in cache[target].ids:
                    report.problems.append(
                        f"{where}:{line}: link {ref!r}: no id {fragment!r} in "
                        f"{target.relative_to(root) if target.is_relative_to(root) else target}"
                    )
        shown: set[Path] = set()
        for ref, line in page.images:
            if _is_external(ref):
                if not ref.startswith("data:"):
                    report.problems.append(f"{where}:{line}: image {ref!r} is not in the site")
                continue
            report.images += 1
            target, _ = _resolve(path, ref)
            if not target.is_file():
                report.problems.append(f"{where}:{line}: image {ref!r}: {target} does not exist")
            elif target.stat().st_size == 0:
                report.problems.append(f"{where}:{line}: image {ref!r} is empty")
            elif not _looks_like_image(target):
                report.problems.append(f"{where}:{line}: image {ref!r} is not an image file")
            else:
                shown.add(target)
        report.images_by_page[where.as_posix()] = len(shown)
        for ref, line in page.scripts:
            if _is_external(ref):
                report.problems.append(f"{where}:{line}: script {ref!r} needs the network")
                continue
            target, _ = _resolve(path, ref)
            if not target.is_file() or target.stat().st_size == 0:
                report.problems.append(f"{where}:{line}: script {ref!r} missing or empty")
    return report


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("site", help="root of the built HTML site (contains index.html)")
    args = parser.parse_args(argv)
    report = check_site(args.site)
    for problem in report.problems:
        print(problem)
    print(
        f"{report.pages} pages, {report.links} local links, {report.images} images: "
        f"{len(report.problems)} problems"
    )
    return 0 if report.ok else 1


if __name__ == "__main__":
    sys.exit(main())
