"""The ``microslip`` command: info, simulate, response, friction, figures, map and sweep.

Every command takes the model's parameters as flags (one per Parameters field, SI
units) or from a TOML file (``--config``; flags win); every command but ``figures`` also
takes the model's parts (``--damping``, ``--excitation``, ``--tangential``,
``--friction``, ``--drive`` and their fields, or the tables of the same names; see
:mod:`microslip.cli.model_options`).
Outputs are written atomically and an existing output is replaced only with
``--overwrite``.

Exit status: 0 success; 2 any failure (bad input, refused output, full disk, a busy
output, an unexpected internal error), always as one line on standard error, never a
traceback (set ``MICROSLIP_DEBUG=1`` to see it); 130 interrupted (Ctrl-C) and 143
terminated (SIGTERM), one line, no output of the interrupted run (a map's finished
chunks are kept for a rerun, and the line says so); an interrupt after every output was
written says so.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import warnings

from microslip.cli.interrupts import (
    RUN,
    Terminated,
    handling_signals,
    interrupt_for,
    release_quietly,
)
from microslip.cli.options import CliError
from microslip.cli.parser import EXIT_USAGE, build_parser, join_negative_numbers, one_line
from microslip.metadata import running

__all__ = [
    "EXIT_INTERRUPTED",
    "EXIT_TERMINATED",
    "EXIT_USAGE",
    "CliError",
    "build_parser",
    "entry_point",
    "main",
]

EXIT_INTERRUPTED = 130
EXIT_TERMINATED = 143


def _fail(command: str, message: str, status: int = EXIT_USAGE) -> int:
    try:
        print(f"microslip {command}: {one_line(message)}", file=sys.stderr, flush=True)
    except (OSError, ValueError):  # stderr closed or on a full device: the status still says
        pass
    return status


def _interrupted(command: str, interrupt: KeyboardInterrupt) -> int:
    """One line for Ctrl-C (130) or SIGTERM (143), saying what was kept."""
    what = "terminated (SIGTERM)" if isinstance(interrupt, Terminated) else "interrupted"
    status = EXIT_TERMINATED if isinstance(interrupt, Terminated) else EXIT_INTERRUPTED
    if RUN.written:
        detail = f" after writing {', '.join(RUN.written)} (complete)"
    elif str(interrupt):
        detail = f"; no output written; {interrupt}"
    else:
        detail = "; no output written"
    return _fail(command, f"{what}{detail}", status)


def _warning_line(command: str):
    def show(message, category, filename, lineno, file=None, line=None) -> None:
        kind = "warning" if category in (UserWarning, RuntimeWarning) else category.__name__
        print(f"microslip {command}: {kind}: {one_line(str(message))}", file=sys.stderr)

    return show


def main(argv: list[str] | None = None, *, exiting: bool = False) -> int:
    """Run the command line ``argv`` (default ``sys.argv[1:]``); returns the exit status.

    ``exiting``: the caller ends the process at once with ``os._exit`` after an
    interrupt (the console script), so the interrupted frames are kept, never freed
    (:func:`~microslip.cli.interrupts.release_quietly`)."""
    debug = os.environ.get("MICROSLIP_DEBUG", "") not in ("", "0")
    command = "?"
    try:
        argv = sys.argv[1:] if argv is None else list(argv)
        RUN.command, RUN.written, RUN.signal = "?", [], None
        # `microslip -- info`: "--" ends the options; the command still follows it
        words = argv[1:] if argv[:1] == ["--"] else argv
        args, extra = build_parser().parse_known_args(join_negative_numbers(words))
        command = RUN.command = args.command
        if extra:  # reported by the command's parser, which knows its own flags
            return _fail(
                command,
                f"error: unrecognized arguments: {' '.join(extra)} "
                f"(see microslip {command} --help)",
            )
        with (
            handling_signals(),
            running(["microslip", *argv]),
            warnings.catch_warnings(),
        ):
            # `running`: the `history` of the files written. Warnings (a damaged chunk
            # recomputed, F > mu m g, ...) are one line each, like errors.
            warnings.showwarning = _warning_line(command)
            return args.handler(args)
    except SystemExit as stop:  # argparse: --help, --version or a usage error (printed)
        return stop.code if isinstance(stop.code, int) else int(stop.code is not None)
    except BrokenPipeError:  # `microslip info | head -1`: the reader has all it wanted
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # no second error while flushing at exit
        return 0
    except KeyboardInterrupt as interrupt:  # also SIGTERM (Terminated)
        status = _interrupted(command, interrupt)
        release_quietly(interrupt, keep=exiting)
        return status
    except Exception as error:
        if RUN.signal is not None:  # an interrupt that native code swallowed, then failed
            status = _interrupted(command, interrupt_for(RUN.signal))
            release_quietly(error, keep=exiting)
            return status
        if debug:
            raise
        return _fail(command, _error_text(error))


def _error_text(error: Exception) -> str:
    """The one line for a failure: the user's error, or a bug to report."""
    if isinstance(error, (ValueError, ConnectionError, TimeoutError)):
        return f"error: {error}"
    if isinstance(error, MemoryError):
        return "error: out of memory; use a smaller problem"
    if isinstance(error, OSError):
        where = f" ({error.filename})" if error.filename else ""
        return f"error: {error.strerror or error}{where}"
    return (
        f"internal error: {type(error).__name__}: {error}; please report it "
        "(MICROSLIP_DEBUG=1 shows the traceback)"
    )


def _leave_now(status: int) -> None:
    """End the process with ``status`` at once: the streams flushed, nothing else run or
    freed (no destructors, garbage collection or atexit handlers)."""
    with contextlib.suppress(OSError, ValueError):
        sys.stdout.flush()
        sys.stderr.flush()
    os._exit(status)


def _late_signal(signum: int, frame) -> None:
    """Ctrl-C/SIGTERM after the command returned (while Python shuts down)."""
    _leave_now(_interrupted(RUN.command, interrupt_for(signum)))


def entry_point() -> None:
    status = main(exiting=True)
    if status == 0:
        for sig in (signal.SIGINT, signal.SIGTERM):
            signal.signal(sig, _late_signal)
    elif status in (EXIT_INTERRUPTED, EXIT_TERMINATED):
        # The outputs are settled (committed or removed) and the line is printed; leave
        # without freeing what an interrupted compile half-built (release_quietly).
        _leave_now(status)
    sys.exit(status)


if __name__ == "__main__":
    entry_point()
