"""How long a command's computation took, the compile of its kernels counted apart.

On the first run of a source version the kernels compile (tens of seconds), and a
summary line that said "simulated 0.001 s in 37.1 s" would pass the compile off as the
run. :class:`CommandTimer` reads the compile time from
:class:`~microslip.compile_clock.CompileClock` and says, on standard error, when a
compile starts: nothing else shows for those seconds (a sweep's bar stands still).
"""

from __future__ import annotations

import sys
import time

__all__ = ["CommandTimer"]

# Compiles shorter than this are not worth a word (a small helper compiled on a warm
# cache); the first run of a source version compiles for tens of seconds.
SHOWN_COMPILE_S = 0.05


class CommandTimer:
    """Wall time [s] of the block it wraps, and the part of it spent compiling kernels.

    ``command`` names the command in the note printed when the first compile starts;
    ``quiet`` drops that note. Compiles in other processes (Dask workers) are not seen:
    they count as run time.
    """

    def __init__(self, command: str, quiet: bool = False) -> None:
        self.command = command
        self.quiet = quiet
        self.elapsed = 0.0
        self.compiling = 0.0
        self._started = 0.0
        self._clock = None

    def __enter__(self) -> CommandTimer:
        # Imported here: numba loads with it (seconds), and `import microslip.cli.main`
        # must stay light (tests/unit/test_import_layout.py).
        from microslip.compile_clock import CompileClock

        self._clock = CompileClock(None if self.quiet else self._say_compiling)
        self._clock.__enter__()
        self._started = time.perf_counter()
        return self

    def __exit__(self, *exc: object) -> None:
        self.elapsed = time.perf_counter() - self._started
        assert self._clock is not None
        self._clock.__exit__(*exc)
        self.compiling = min(self._clock.seconds, self.elapsed)

    def took(self, digits: int = 2) -> str:
        """The run time, the elapsed time less the compile ("in 0.004 s"), followed by
        the compile's where the block compiled ("+ 37.1 s compiling kernels")."""
        text = f"in {self.elapsed - self.compiling:.{digits}f} s"
        if self.compiling >= SHOWN_COMPILE_S:
            text += f" + {self.compiling:.1f} s compiling kernels"
        return text

    def _say_compiling(self) -> None:
        if sys.stderr is None:  # closed (`2>&-`): tqdm would write to stdout instead
            return
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
