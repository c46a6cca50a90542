"""Ctrl-C and SIGTERM in the command line: an exception at a safe point, never a half output.

While a command runs, SIGINT raises ``KeyboardInterrupt`` and SIGTERM raises
:class:`Terminated` (a ``KeyboardInterrupt``, so every cleanup that handles Ctrl-C also
handles ``kill``, ``timeout`` and batch schedulers). Inside :func:`uninterruptible`
(moving finished outputs into place) a signal is held back and raised when the block
ends, so the outputs are moved all or none. :data:`RUN` records what the command has
written, so that a late interrupt can say that those outputs are complete.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
from dataclasses import dataclass, field

__all__ = ["RUN", "Terminated", "handling_signals", "uninterruptible"]

_SIGNALS = (signal.SIGINT, signal.SIGTERM)


class Terminated(KeyboardInterrupt):
    """SIGTERM received (exit status 143 = 128 + 15)."""


@dataclass
class RunRecord:
    """What the running command has finished: its complete outputs."""

    command: str = "?"
    written: list[str] = field(default_factory=list)


RUN = RunRecord()
_held: list[int] = []
_depth = [0]


def _raise_for(signum: int) -> None:
    if signum == signal.SIGTERM:
        raise Terminated()
    raise KeyboardInterrupt()


def _handler(signum: int, frame) -> None:
    if _depth[0]:
        _held.append(signum)  # raised when the uninterruptible block ends
        return
    _raise_for(signum)


@contextlib.contextmanager
def handling_signals() -> Iterator[None]:
    """Install the SIGINT/SIGTERM handlers for the block (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {sig: signal.getsignal(sig) for sig in _SIGNALS}
    _held.clear()
    _depth[0] = 0
    for sig in _SIGNALS:
        signal.signal(sig, _handler)
    try:
        yield
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)


@contextlib.contextmanager
def uninterruptible() -> Iterator[None]:
    """Hold Ctrl-C/SIGTERM back for the block; raise the first one when it ends."""
    _depth[0] += 1
    try:
        yield
    finally:
        _depth[0] -= 1
        if not _depth[0] and _held:
            signum = _held[0]
            _held.clear()
            _raise_for(signum)
