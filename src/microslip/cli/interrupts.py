"""Ctrl-C and SIGTERM in the command line: an exception at a safe point, never a half output.

While a command runs, SIGINT raises ``KeyboardInterrupt`` and SIGTERM raises
:class:`Terminated` (a ``KeyboardInterrupt``, so every cleanup that handles Ctrl-C also
handles ``kill``, ``timeout`` and batch schedulers). Inside :func:`uninterruptible`
(moving finished outputs into place) a signal is held back and raised when the block
ends, so the outputs are moved all or none. A signal that native code swallows (a
callback from LLVM while numba compiles) is sent again until it is raised. :data:`RUN`
records what the command has written, so that a late interrupt can say that those
outputs are complete.
"""

from __future__ import annotations

import contextlib
import gc
import os
import signal
import sys
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass, field

__all__ = [
    "RUN",
    "Terminated",
    "handling_signals",
    "ignore_unraisable",
    "interrupt_for",
    "release_quietly",
    "uninterruptible",
]

_SIGNALS = (signal.SIGINT, signal.SIGTERM)


class Terminated(KeyboardInterrupt):
    """SIGTERM received (exit status 143 = 128 + 15)."""


@dataclass
class RunRecord:
    """What the running command has finished: its complete outputs."""

    command: str = "?"
    written: list[str] = field(default_factory=list)
    signal: int | None = None  # the first SIGINT/SIGTERM received, raised or not


RUN = RunRecord()
_held: list[int] = []
_depth = [0]
# A signal swallowed by native code is sent again from a helper thread this long after,
# once the callback that swallowed it has returned (see ``_redeliver``).
REDELIVERY_DELAY_S = 0.05
_redelivery = threading.Lock()
_installed = [0]  # which handling_signals block has its handlers in place (0: none)
_blocks = [0]  # handling_signals blocks entered so far
_in_unraisable_hook = [False]


def interrupt_for(signum: int) -> KeyboardInterrupt:
    """The exception that stands for signal ``signum``."""
    return Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()


def _raise_for(signum: int) -> None:
    raise interrupt_for(signum)


def _handler(signum: int, frame) -> None:
    if RUN.signal is None:
        RUN.signal = signum
    if _depth[0]:
        _held.append(signum)  # raised when the uninterruptible block ends
        return
    if _in_unraisable_hook[0]:  # raised here it would be lost again: later
        _schedule_redelivery(signum)
        return
    _raise_for(signum)


def _redeliver(signum: int, block: int) -> None:
    time.sleep(REDELIVERY_DELAY_S)
    with _redelivery:  # only while the block whose signal it was still runs
        if _installed[0] == block:
            os.kill(os.getpid(), signum)


def _schedule_redelivery(signum: int) -> None:
    """Send ``signum`` again shortly, from a helper thread.

    An interrupt raised inside a callback from native code (llvmlite's object-cache
    callbacks while numba compiles) cannot propagate: it is printed as "Exception
    ignored" and lost, and the compile may well succeed, so the command would run to its
    end. Sent again, it is raised at the next point where Python code runs; if that is
    inside such a callback again, it is sent again."""
    threading.Thread(target=_redeliver, args=(signum, _installed[0]), daemon=True).start()


@contextlib.contextmanager
def handling_signals() -> Iterator[None]:
    """Install the SIGINT/SIGTERM handlers for the block (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {sig: signal.getsignal(sig) for sig in _SIGNALS}
    previous_hook = sys.unraisablehook
    _held.clear()
    _depth[0] = 0

    def unraisable(record) -> None:
        # Native code calling back into Python (llvmlite during a JIT compile) cannot
        # propagate our interrupt: it would print it as "Exception ignored", then either
        # fail (RUN.signal has the interrupt; the command line reports it in its own
        # line) or go on as if no signal had come. It is sent again instead.
        if record.exc_type is None or not issubclass(record.exc_type, KeyboardInterrupt):
            previous_hook(record)
            return
        _in_unraisable_hook[0] = True
        try:
            is_term = issubclass(record.exc_type, Terminated)
            _schedule_redelivery(signal.SIGTERM if is_term else signal.SIGINT)
        finally:
            _in_unraisable_hook[0] = False

    sys.unraisablehook = unraisable
    for sig in _SIGNALS:
        signal.signal(sig, _handler)
    outer = _installed[0]
    _blocks[0] += 1
    _installed[0] = _blocks[0]
    try:
        yield
    finally:
        with _redelivery:
            _installed[0] = outer
        for sig, old in previous.items():
            signal.signal(sig, old)
        sys.unraisablehook = previous_hook


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


def ignore_unraisable(_unraisable) -> None:
    """After an interrupt: objects cut off mid-construction (an interrupted JIT compile
    leaves half-built llvmlite objects) fail in ``__del__``; their "Exception ignored
    in ..." tracebacks would follow the one line already printed."""


_KEPT: list[BaseException] = []  # interrupts whose frames are never freed (``keep``)


def release_quietly(error: BaseException, *, keep: bool = False) -> None:
    """Free the frames of an interrupted command now, with those reports off; or, with
    ``keep``, never.

    The traceback of the interrupt holds the frames of the compile it cut short; freed at
    the end of the ``except`` clause, after the hooks of :func:`handling_signals` are
    gone, their half-built objects would print "Exception ignored" under the one line.
    Freeing them can also crash the process: LLVM objects cut off mid-construction were
    seen to segfault (exit -11 instead of 130, on a cold kernel cache). The console
    script therefore keeps them (``keep``) and leaves with ``os._exit``, which frees
    nothing; an in-process caller (tests) frees them here.
    """
    if keep:
        _KEPT.append(error)
        return
    previous = sys.unraisablehook
    sys.unraisablehook = ignore_unraisable
    try:
        error.__traceback__ = None
        error.__context__ = None
        gc.collect()
    finally:
        sys.unraisablehook = previous
