"""Time spent compiling kernels, told apart from the time spent running them.

The first run of a source version compiles microslip's kernels (numba): tens of seconds
on the development machine's two cores, ~20 s for a time map and more for a first
``simulate`` (docs/design.md, "Compile time"). Later runs load them from the kernel
cache (:mod:`microslip._jit_cache`) in well under a second. A command that reports how
long it took must not pass the compile off as the run: the CLI counts the two apart with
a :class:`CompileClock`, and says when a compile starts, since nothing else shows for
those seconds.

The clock listens to numba's ``numba:compile`` events, which numba fires for a compile
and not for a load from the cache. It counts the wall time of each outermost compile
only: a kernel's compile compiles its callees inside it, and those nested events are
not added again. numba compiles under one process-wide lock, so the events of two
threads never interleave.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

from numba.core import event

from microslip import _jit_cache  # noqa: F401  (registers the cache before numba compiles)

__all__ = ["CompileClock"]

_COMPILE = "numba:compile"


class _Listener(event.Listener):
    """Start and end of numba's compiles, told to the clock."""

    def __init__(self, clock: CompileClock) -> None:
        self._clock = clock

    def on_start(self, event: event.Event) -> None:
        self._clock._started()

    def on_end(self, event: event.Event) -> None:
        self._clock._ended()


class CompileClock:
    """Wall time [s] spent in numba compiles while installed (a context manager).

    ``seconds`` is the total of the outermost compiles ended so far, ``compiles`` their
    number. ``on_first_compile``, where given, is called once, at the start of the first
    compile, from the thread that compiles (a sweep's kernels compile in its worker
    threads): the place to say that a compile has begun.
    """

    def __init__(self, on_first_compile: Callable[[], None] | None = None) -> None:
        self.seconds = 0.0
        self.compiles = 0
        self._on_first_compile = on_first_compile
        self._depth = 0
        self._since = 0.0
        self._lock = threading.Lock()
        self._listener = _Listener(self)

    def __enter__(self) -> CompileClock:
        event.register(_COMPILE, self._listener)
        return self

    def __exit__(self, *exc: object) -> None:
        event.unregister(_COMPILE, self._listener)

    def _started(self) -> None:
        with self._lock:
            self._depth += 1
            if self._depth > 1:
                return
            self._since = time.perf_counter()
            first, self._on_first_compile = self._on_first_compile, None
        if first is not None:
            first()

    def _ended(self) -> None:
        with self._lock:
            self._depth -= 1
            if self._depth == 0:
                self.seconds += time.perf_counter() - self._since
                self.compiles += 1
