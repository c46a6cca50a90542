"""Let microslip's plain-text docstrings render as written.

The docstrings are written to be read with ``help()``: absolute values as ``|F|`` and
``μ|R|``, star-arguments as ``*axes``. In reStructuredText ``|F|`` is a substitution
reference and a lone ``*`` starts emphasis, so Sphinx would fail on them. After napoleon
has turned the numpy sections into reST, this hook escapes every ``|`` and every ``*``
that does not open or close a complete ``*emphasis*`` / ``**strong**`` pair, outside
inline literals, roles and interpreted text (anything between backticks).
"""

from __future__ import annotations

import re
from typing import Any

_BACKTICKS = re.compile(r"(``.+?``|`[^`]+`)")
_PAIRED = re.compile(r"\*\*[^\s*](?:[^*]*?[^\s*])?\*\*|\*[^\s*](?:[^*]*?[^\s*])?\*")
_TABLE_BORDER = re.compile(r"^\s*[=+\-| ]+$")


def _escape_stars(text: str) -> str:
    out, last = [], 0
    for match in _PAIRED.finditer(text):
        out.append(text[last : match.start()].replace("*", r"\*"))
        out.append(match.group(0))
        last = match.end()
    out.append(text[last:].replace("*", r"\*"))
    return "".join(out)


def escape_line(line: str) -> str:
    """``line`` with bare ``|`` and unpaired ``*`` escaped outside backtick spans."""
    if _TABLE_BORDER.match(line) and "|" in line:
        return line  # a grid-table border
    parts = _BACKTICKS.split(line)
    for i in range(0, len(parts), 2):  # even parts lie outside backticks
        text = re.sub(r"(?<!\\)\|", r"\\|", parts[i])
        parts[i] = _escape_stars(text)
    return "".join(parts)


def _process(app: Any, what: str, name: str, obj: Any, options: Any, lines: list[str]) -> None:
    if not name.startswith("microslip"):
        return
    in_literal_block = False
    for i, line in enumerate(lines):
        stripped = line.strip()
        if in_literal_block:
            if stripped and not line.startswith((" ", "\t")):
                in_literal_block = False
            else:
                continue
        lines[i] = escape_line(line)
        if stripped.endswith("::") and not stripped.startswith(".."):
            in_literal_block = True


def setup(app: Any) -> dict[str, Any]:
    app.setup_extension("sphinx.ext.napoleon")
    app.connect("autodoc-process-docstring", _process, priority=600)  # after napoleon (500)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
