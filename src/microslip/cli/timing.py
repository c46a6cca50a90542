"""How long a command's computation took, its kernels' compile or load counted apart.

On the first run of a source version the kernels compile (tens of seconds), and a
summary line that said "simulated 0.001 s in 37.1 s" would pass the compile off as the
run; on later runs loading them from the cache (a fraction of a second, most of it
numba's own start-up) would still be most of a short run's time. :class:`CommandTimer`
reads both from :class:`~microslip.compile_clock.CompileClock` and, at a terminal,
says on standard error when a compile starts: nothing else shows for those seconds (a
sweep's bar stands still).
"""

from __future__ import annotations

import sys
import time

__all__ = ["CommandTimer"]

# Kernel time shorter than this is not worth a word; the first run of a source version
# compiles for tens of seconds, and a load from the cache takes ~0.3-1 s here.
SHOWN_KERNEL_S = 0.05


class CommandTimer:
    """Wall time [s] of the block it wraps, and the part of it numba spent compiling its
    kernels or loading them from the cache (``kernels``; ``compiled``: whether any was
    compiled).

    ``command`` names the command in the note printed, at a terminal, when the first
    compile starts; ``quiet`` drops that note. Kernels compiled or loaded in other processes (Dask
    workers) are not seen: that time counts as run time.
    """

    def __init__(self, command: str, quiet: bool = False) -> None:
        self.command = command
        self.quiet = quiet
        self.elapsed = 0.0
        self.kernels = 0.0
        self.compiled = False
        self._started = 0.0
        self._clock = None

    def __enter__(self) -> CommandTimer:
        # Imported here: numba loads with it (seconds), and `import microslip.cli.main`
        # must stay light (tests/unit/test_import_layout.py).
        from microslip.compile_clock import CompileClock

        self._clock = CompileClock(self._say_compiling if self._announces() else None)
        self._clock.__enter__()
        self._started = time.perf_counter()
        return self

    def __exit__(self, *exc: object) -> None:
        self.elapsed = time.perf_counter() - self._started
        assert self._clock is not None
        self._clock.__exit__(*exc)
        self.kernels = min(self._clock.seconds, self.elapsed)
        self.compiled = self._clock.compiles > 0

    def took(self, digits: int = 2) -> str:
        """The run time, the elapsed time less the kernels' ("in 0.004 s"), followed by
        theirs: "+ 37.1 s compiling kernels" where the block compiled any, else
        "+ 0.42 s loading compiled kernels"."""
        text = f"in {self.elapsed - self.kernels:.{digits}f} s"
        if self.kernels >= SHOWN_KERNEL_S:
            if self.compiled:
                text += f" + {self.kernels:.1f} s compiling kernels"
            else:
                text += f" + {self.kernels:.2f} s loading compiled kernels"
        return text

    def _announces(self) -> bool:
        """Whether to say that a compile starts: for a person at a terminal, as the
        progress bar; a log has the compile's time in the summary line, and a scripted
        run's stderr keeps its one line per failure (a closed stderr is None)."""
        try:
            return not self.quiet and sys.stderr is not None and sys.stderr.isatty()
        except (AttributeError, OSError, ValueError):  # no isatty, or a closed file
            return False

    def _say_compiling(self) -> None:
        from tqdm import tqdm  # clears and redraws a sweep's bar around the line

        from microslip._jit_cache import cache_dir

        try:
            tqdm.write(
                f"microslip {self.command}: note: compiling kernels for these sources "
                f"(once, tens of seconds; later runs load them from {cache_dir()})",
                file=sys.stderr,
            )
        except (OSError, ValueError):  # stderr closed or full: the compile goes on
            pass
