"""The compile clock counts numba's compiles apart from run time, each outermost once.

Each test compiles functions of its own (defined inside it, not cached), so that a
compile happens whatever the session compiled before.
"""

from __future__ import annotations

import time

from numba import njit

from microslip.cli.timing import SHOWN_COMPILE_S, CommandTimer
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


def test_command_timer_takes_the_compile_out_of_the_run_time(capsys):
    _, outer = _fresh_pair()
    with CommandTimer("map") as timer:
        outer(1.0)
        time.sleep(0.05)  # the run itself
    assert timer.compiling >= SHOWN_COMPILE_S  # a numba compile of two functions
    run = timer.elapsed - timer.compiling
    assert 0.05 <= run < timer.elapsed
    assert timer.took(3) == (f"in {run:.3f} s + {timer.compiling:.1f} s compiling kernels")
    note = capsys.readouterr().err.strip().splitlines()
    assert len(note) == 1 and note[0].startswith("microslip map: note: compiling kernels")


def test_command_timer_without_a_compile_says_only_the_run_time(capsys):
    _, outer = _fresh_pair()
    outer(1.0)
    with CommandTimer("map") as timer:
        outer(2.0)
    assert timer.compiling == 0.0
    assert timer.took(2) == f"in {timer.elapsed:.2f} s"
    assert capsys.readouterr().err == ""


def test_quiet_command_timer_still_counts_but_says_nothing(capsys):
    _, outer = _fresh_pair()
    with CommandTimer("map", quiet=True) as timer:
        outer(1.0)
    assert timer.compiling > 0.0
    assert capsys.readouterr().err == ""


def test_the_note_is_dropped_when_stderr_is_closed(capsys, monkeypatch):
    """`2>&-`: sys.stderr is None, and tqdm.write would then print to stdout."""
    _, outer = _fresh_pair()
    monkeypatch.setattr("sys.stderr", None)
    with CommandTimer("map") as timer:
        outer(1.0)
    assert timer.compiling > 0.0
    assert capsys.readouterr().out == ""
