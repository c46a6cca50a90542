"""The compile clock counts numba's compiles and loads apart from run time, each
outermost span once.

Each test compiles functions of its own (defined inside it, not cached), so that a
compile happens whatever the session compiled before; the load test caches a module of
its own in a temporary directory (numba's cache beside it, in __pycache__).
"""

from __future__ import annotations

import importlib
import io
import sys
import time

from numba import njit

from microslip.cli.timing import SHOWN_KERNEL_S, CommandTimer
from microslip.compile_clock import CompileClock


def _fresh_pair():
    """An outer function that calls an inner one, both not compiled yet."""

    @njit
    def inner(x):
        return 2.0 * x + 1.0

    @njit
    def outer(x):
        return inner(x) - 1.0

    return inner, outer


def test_nested_compile_counts_once_and_within_its_wall_time():
    inner, outer = _fresh_pair()
    firsts = []
    with CompileClock(lambda: firsts.append(True)) as clock:
        started = time.perf_counter()
        assert outer(1.5) == 3.0  # compiles outer, and inner inside that compile
        wall = time.perf_counter() - started
        assert clock.compiles == 1
        assert 0.0 < clock.seconds <= wall
        once = clock.seconds
        outer(2.0)  # compiled: nothing to add
        assert (clock.compiles, clock.seconds) == (1, once)
        inner(1.0)  # compiled inside outer's compile (same signature): nothing either
        assert (clock.compiles, clock.seconds) == (1, once)
        inner(1)  # a new signature: a second, separate compile
        assert clock.compiles == 2 and clock.seconds > once
    assert firsts == [True]  # told once, at the first compile only


def test_compiles_after_exit_are_not_counted():
    _, outer = _fresh_pair()
    with CompileClock() as clock:
        pass
    outer(1.0)
    assert (clock.compiles, clock.seconds) == (0, 0.0)


CACHED = """
from numba import njit


@njit(cache=True)
def cached(x):
    return 3.0 * x
"""


def _import_afresh(name):
    sys.modules.pop(name, None)
    return importlib.import_module(name)


def test_a_load_from_the_cache_is_timed_but_is_not_a_compile(tmp_path, monkeypatch):
    (tmp_path / "clock_probe.py").write_text(CACHED)
    monkeypatch.syspath_prepend(str(tmp_path))
    _import_afresh("clock_probe").cached(1.0)  # compiled and saved
    probe = _import_afresh("clock_probe")  # a new dispatcher: it loads from the cache
    with CompileClock() as clock:
        assert probe.cached(2.0) == 6.0
    assert sum(probe.cached.stats.cache_hits.values()) == 1
    assert clock.compiles == 0 and clock.seconds > 0.0


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_command_timer_takes_the_compile_out_of_the_run_time(monkeypatch):
    terminal = _Terminal()
    monkeypatch.setattr("sys.stderr", terminal)
    _, outer = _fresh_pair()
    with CommandTimer("map") as timer:
        outer(1.0)
        time.sleep(0.05)  # the run itself
    assert timer.compiled and timer.kernels >= SHOWN_KERNEL_S  # a compile of two functions
    run = timer.elapsed - timer.kernels
    assert 0.05 <= run < timer.elapsed
    assert timer.took(3) == f"in {run:.3f} s + {timer.kernels:.1f} s compiling kernels"
    note = terminal.getvalue().strip().splitlines()  # at a terminal: said once
    assert len(note) == 1 and note[0].startswith("microslip map: note: compiling kernels")


def test_no_note_off_a_terminal(capsys):
    """A log or a script's captured stderr gets the compile's time in the summary line
    only: its stderr keeps one line per failure."""
    _, outer = _fresh_pair()
    with CommandTimer("map") as timer:
        outer(1.0)
    assert timer.compiled
    assert capsys.readouterr().err == ""


def test_command_timer_names_a_load_as_a_load():
    timer = CommandTimer("map")
    timer.elapsed, timer.kernels, timer.compiled = 0.5, 0.42, False
    assert timer.took(3) == "in 0.080 s + 0.42 s loading compiled kernels"
    timer.kernels = 0.5 * SHOWN_KERNEL_S  # too short to be worth a word
    assert timer.took(3) == f"in {0.5 - timer.kernels:.3f} s"


def test_command_timer_without_a_compile_says_only_the_run_time(capsys):
    _, outer = _fresh_pair()
    outer(1.0)
    with CommandTimer("map") as timer:
        outer(2.0)
    assert (timer.kernels, timer.compiled) == (0.0, False)
    assert timer.took(2) == f"in {timer.elapsed:.2f} s"
    assert capsys.readouterr().err == ""


def test_quiet_command_timer_still_counts_but_says_nothing(monkeypatch):
    terminal = _Terminal()
    monkeypatch.setattr("sys.stderr", terminal)
    _, outer = _fresh_pair()
    with CommandTimer("map", quiet=True) as timer:
        outer(1.0)
    assert timer.compiled and timer.kernels > 0.0
    assert terminal.getvalue() == ""


def test_the_note_is_dropped_when_stderr_is_closed(capsys, monkeypatch):
    """`2>&-`: sys.stderr is None, and tqdm.write would then print to stdout."""
    _, outer = _fresh_pair()
    monkeypatch.setattr("sys.stderr", None)
    with CommandTimer("map") as timer:
        outer(1.0)
    assert timer.compiled
    assert capsys.readouterr().out == ""
