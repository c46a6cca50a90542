"""Global attributes of every file microslip writes (CF conventions, Sec. 2.6 of CF-1.10).

Importable from any layer: it needs only the standard library, and reads
``microslip.__version__`` lazily so that importing it never pulls in the package.
"""

from __future__ import annotations

import contextlib
import shlex
import sys
from collections.abc import Iterator
from datetime import datetime, timezone
from pathlib import Path

__all__ = [
    "CONVENTIONS",
    "REFERENCES",
    "cf_attributes",
    "cf_static_attributes",
    "command_line",
    "running",
]

CONVENTIONS = "CF-1.10"
REFERENCES = (
    "K. Grudzinski and R. Kostek, Influence of normal micro-vibrations in contact on "
    "sliding motion of solid body, Journal of Theoretical and Applied Mechanics 43(1), 2005"
)


_running: list[list[str]] = []  # command lines set by running(), innermost last


@contextlib.contextmanager
def running(argv: list[str]) -> Iterator[None]:
    """Record ``argv`` as the command line for ``history`` while the block runs.

    The CLI uses this so that ``microslip.cli.main.main([...])`` called from Python
    records its own arguments, not those of the host program.
    """
    _running.append(list(argv))
    try:
        yield
    finally:
        _running.pop()


def command_line(argv: list[str] | None = None) -> str:
    """The command that is running, quoted for a shell, program name without its directory."""
    if argv is None:
        argv = _running[-1] if _running else sys.argv
    argv = list(argv)
    if not argv:
        return "python"
    return shlex.join([Path(argv[0]).name, *argv[1:]])


def cf_static_attributes(title: str) -> dict[str, str]:
    """The CF global attributes that do not depend on the run: ``Conventions``, ``title``,
    ``source`` ("microslip X.Y.Z") and ``references`` (the paper).

    In-memory Datasets carry these, so that two computations of the same result are
    ``identical``; ``history`` is added when a file is written.
    """
    from microslip import __version__

    return {
        "Conventions": CONVENTIONS,
        "title": str(title),
        "source": f"microslip {__version__}",
        "references": REFERENCES,
    }


def cf_attributes(title: str) -> dict[str, str]:
    """CF global attributes for a file titled ``title``.

    :func:`cf_static_attributes` plus ``history``: the UTC ISO timestamp, then the command
    line from ``sys.argv``.
    """
    stamp = datetime.now(timezone.utc).replace(microsecond=0).isoformat()
    return {**cf_static_attributes(title), "history": f"{stamp}: {command_line()}"}
