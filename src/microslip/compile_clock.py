"""Time spent compiling kernels or loading them, told apart from the time running them.

The first run of a source version compiles microslip's kernels (numba): tens of seconds
on the development machine's two cores, ~20 s for a time map and more for a first
``simulate`` (docs/design.md, "Compile time"). Later runs load them from the kernel
cache (:mod:`microslip._jit_cache`): a fraction of a second, most of it numba's own
start-up on its first load. A command that reports how long it took must pass neither
off as the run (a 1 ms simulation "in 0.6 s"): the CLI counts them apart with a
:class:`CompileClock`, and at a terminal says when a compile starts, since nothing
else shows for those seconds.

numba does both under one process-wide lock, and tells of it by events: the clock adds
up the wall time during which any thread holds that lock or waits for it
(``numba:compiler_lock``; nested and concurrent spans count once), and counts numba's
compiles (``numba:compile``, fired for a compile and not for a load from the cache;
a kernel's compile compiles its callees inside it, and those are not counted again).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

from numba.core import event

from microslip import _jit_cache  # noqa: F401  (registers the cache before numba compiles)

__all__ = ["CompileClock"]

_LOCK = "numba:compiler_lock"
_COMPILE = "numba:compile"


class _Listener(event.Listener):
    """Start and end of numba's events of one kind, told to the clock."""

    def __init__(self, started: Callable[[], None], ended: Callable[[], None]) -> None:
        self._started = started
        self._ended = ended

    def on_start(self, event: event.Event) -> None:
        self._started()

    def on_end(self, event: event.Event) -> None:
        self._ended()


class CompileClock:
    """Wall time [s] numba spends on kernels while installed (a context manager).

    ``seconds`` is the wall time of the spans ended so far during which numba compiled
    or loaded kernels (held its compiler lock, or a thread waited for it); ``compiles``
    the number of outermost compiles among them (0: every kernel came from the cache).
    ``on_first_compile``, where given, is called once, at the start of the first
    compile, from the thread that compiles (a sweep's kernels compile in its worker
    threads): the place to say that a compile has begun.
    """

    def __init__(self, on_first_compile: Callable[[], None] | None = None) -> None:
        self.seconds = 0.0
        self.compiles = 0
        self._on_first_compile = on_first_compile
        self._holders = 0  # threads holding or waiting for the lock, with nesting
        self._since = 0.0
        self._compile_depth = 0
        self._lock = threading.Lock()
        self._listeners = (
            (_LOCK, _Listener(self._lock_started, self._lock_ended)),
            (_COMPILE, _Listener(self._compile_started, self._compile_ended)),
        )

    def __enter__(self) -> CompileClock:
        for kind, listener in self._listeners:
            event.register(kind, listener)
        return self

    def __exit__(self, *exc: object) -> None:
        for kind, listener in self._listeners:
            event.unregister(kind, listener)

    def _lock_started(self) -> None:
        with self._lock:
            if self._holders == 0:
                self._since = time.perf_counter()
            self._holders += 1

    def _lock_ended(self) -> None:
        with self._lock:
            if self._holders == 0:  # a span begun before the clock was installed
                return
            self._holders -= 1
            if self._holders == 0:
                self.seconds += time.perf_counter() - self._since

    def _compile_started(self) -> None:
        # Compiles run under numba's lock: the events of two threads never interleave.
        with self._lock:
            self._compile_depth += 1
            if self._compile_depth > 1:
                return
            first, self._on_first_compile = self._on_first_compile, None
        if first is not None:
            first()

    def _compile_ended(self) -> None:
        with self._lock:
            self._compile_depth -= 1
            if self._compile_depth == 0:
                self.compiles += 1
