"""The map and sweep commands: mean sliding velocity over grids (Fig. 7 and sweeps).

Like every command, they validate everything before computing; the grid runs in a
resumable working store (``OUT.partial.zarr``) held under an exclusive lock.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from microslip.cli.commands import _check_method, _commit, _note, _output_path, _same_file
from microslip.cli.interrupts import RUN, interrupt_for
from microslip.cli.model_options import require_paper_tangential
from microslip.cli.options import CliError, Options, gather, refuse_underscores
from microslip.cli.timing import CommandTimer

# A run estimated at least this long [s] says so before it starts: a log (no progress bar
# off a terminal) then shows what to expect, and where a Ctrl-C leaves its work.
LONG_RUN_S = 60.0

#: Why map and sweep refuse a tangential part other than the paper's.
SWEEP_INSTEAD = (
    "map and sweep compute the mean velocity under the constant forces of --force with "
    "Coulomb friction, on a rigid contact (the paper's Sec. 4) or, with --method time, "
    "also a compliant one (--tangential spring or mindlin) and --friction static-kinetic: "
    "leave out --drive (and --friction stribeck), or "
    "use `microslip simulate` (any tangential part) or `microslip friction` (effective "
    "friction under a prescribed velocity)"
)


# -- map / sweep ------------------------------------------------------------------------
def _sweep_axes(opts: Options) -> dict[str, np.ndarray]:
    from microslip.io.ranges import parse_values

    axes: dict[str, np.ndarray] = {}
    for text in opts.get("param", []):
        name, sep, values = str(text).partition("=")
        name = name.strip()
        if not sep or not name:
            raise CliError(f"{opts.flag('param')}: expected NAME=RANGE, got {text!r}")
        if name in axes:
            raise CliError(f"{opts.flag('param')}: {name!r} given twice")
        if name in ("force", "amplitude"):
            raise CliError(f"{opts.flag('param')}: give {name} with --{name}, not --param")
        given = {**opts.param_origin, **opts.part_origin()}
        if name in given:
            raise CliError(
                f"{opts.flag('param')} {name}=... cannot be combined with "
                f"{given[name]}: both set {name}"
            )
        refuse_underscores(f"--param {name}", values)
        axes[name] = parse_values(f"--param {name}", values)
    return axes


def _check_scheduler(opts: Options) -> None:
    """A scheduler address must be HOST:PORT or tcp://HOST:PORT (refused at once, not
    after a connection timeout)."""
    if "scheduler" not in opts:
        return
    text = str(opts["scheduler"]).strip()
    address = text.removeprefix("tcp://")
    host, sep, port = address.rpartition(":")
    if not sep or not host or "/" in address or not port.isdigit() or not 0 < int(port) < 65536:
        raise CliError(
            f"{opts.flag('scheduler')}: expected HOST:PORT or tcp://HOST:PORT, got {text!r}"
        )


def cmd_sweep(args: argparse.Namespace) -> int:
    from microslip.budget import duration_text
    from microslip.io.output import (
        PLOT_SUFFIXES,
        OutputBatch,
        OutputError,
        check_writable,
        write_dataset,
    )
    from microslip.io.ranges import parse_values
    from microslip.sweeps import SweepSpec, run_sweep
    from microslip.sweeps.kernel_choice import allowed_parts
    from microslip.sweeps.store import exclusive_lock, remove_store

    opts = gather(args, args.command)
    params = opts.params
    axes = _sweep_axes(opts)
    # A swept part field needs no flag of its own: the model holds its first value.
    model = opts.model(
        {name: (float(values[0]), f"{opts.flag('param')} {name}=...")
         for name, values in axes.items() if "." in name}
    )  # fmt: skip
    method = _check_method(opts, ("steady", "time"), "steady")
    require_paper_tangential(
        model, opts.parts, args.command, instead=SWEEP_INSTEAD,
        allowed=allowed_parts(method),
    )  # fmt: skip
    forced = model.excitation is not None
    if forced and args.command == "map":
        raise CliError(
            "map draws v(F, A) of the free normal vibration; with an excitation use "
            "`microslip sweep --param excitation.frequency=... --force ...`"
        )
    if method == "steady":
        for name in ("duration", "dt"):
            opts.refuse(name, "with --method steady (the exact steady state has no time step)")
    opts.refuse_together(
        "workers", "scheduler", "--workers starts a local cluster, --scheduler uses a running one"
    )
    # A forced model starts from rest: the amplitude of a free vibration is optional.
    required = ("force", "out") if forced else ("force", "amplitude", "out")
    for name in required:
        if name not in opts:
            raise CliError(f"--{name} is required (flag or [{args.command}] in --config)")
    _check_scheduler(opts)
    forces = parse_values(opts.flag("force"), refuse_underscores(opts.flag("force"), opts["force"]))
    amplitudes = None
    if "amplitude" in opts:
        amplitudes = parse_values(
            opts.flag("amplitude"), refuse_underscores(opts.flag("amplitude"), opts["amplitude"])
        )
    overwrite = bool(opts.get("overwrite", False))
    out = check_writable(
        _output_path(opts, "out", args.config), (".nc", ".zarr"), overwrite=overwrite
    )
    plot = None
    if "plot" in opts:
        plot = check_writable(
            _output_path(opts, "plot", args.config), PLOT_SUFFIXES, overwrite=overwrite
        )
        if _same_file(out, plot):
            raise CliError(f"{opts.flag('out')} and {opts.flag('plot')} name the same file")
    if plot is not None:  # refuse a plot that cannot be drawn before computing anything
        from microslip.plotting.velocity_map import sweep_plot_kind

        sizes = {name: len(values) for name, values in axes.items()}
        try:
            if amplitudes is not None:
                sizes["amplitude"] = len(amplitudes)
            sweep_plot_kind({**sizes, "force": len(forces)})
        except ValueError as error:
            raise CliError(str(error)) from None
    workers = opts.get("workers")
    if workers is not None:
        from microslip.sweeps.runner import check_workers

        try:
            check_workers(workers)
        except ValueError as error:
            raise CliError(f"{opts.flag('workers')}: {error}") from None
    chunk = opts.get("chunk")
    if chunk is not None and chunk < 1:
        raise CliError(f"{opts.flag('chunk')} must be an integer >= 1, got {chunk!r}")
    spec = SweepSpec.build(
        params if model.is_paper else model, axes, forces, amplitudes,
        method=method, duration=opts.get("duration", 0.05), dt=opts.get("dt"),
        amplitude_chunk=chunk, backend=opts.get("backend", "cpu"),
    )  # fmt: skip
    seconds = spec.check_budget(allow_large=bool(opts.get("allow_large", False))).seconds
    work_store = out.with_name(out.name + ".partial.zarr")
    quiet = bool(opts.get("quiet", False))
    if not quiet and seconds >= LONG_RUN_S:
        _note(
            f"{spec.n_chunks} chunks, estimated to take about {duration_text(seconds)} "
            f"here; Ctrl-C keeps the finished chunks in {work_store} for a rerun to resume"
        )
    # One run per output at a time: a second one stops here at once (StoreBusyError).
    with (
        CommandTimer(args.command, quiet=quiet) as timer,
        exclusive_lock(out),
        OutputBatch(overwrite=overwrite) as batch,
    ):
        try:
            ds = run_sweep(
                spec,
                store=work_store,
                scheduler=opts.get("scheduler"),
                workers=workers,
                progress=not quiet and sys.stderr is not None and sys.stderr.isatty(),
            )
            batch.write(out, lambda tmp: write_dataset(ds, tmp, overwrite=False))
            if plot is not None:
                from microslip.plotting.velocity_map import write_velocity_map_plot

                batch.write(plot, lambda tmp: write_velocity_map_plot(ds, tmp, params))
            _commit(batch)
        except (ConnectionError, TimeoutError) as error:  # the scheduler, not the disk
            raise CliError(
                f"{opts.flag('scheduler') if 'scheduler' in opts else 'Dask'}: {error}"
                + (f"; finished chunks are kept in {work_store}" if work_store.exists() else "")
            ) from None
        except OSError as error:  # a full disk or a vanished directory while computing
            raise OutputError(
                f"cannot write {str(work_store)!r}: {error.strerror or error}; "
                "finished chunks are kept there for a rerun"
            ) from None
        except KeyboardInterrupt as interrupt:  # Ctrl-C or SIGTERM (keeps its kind)
            _interrupted(interrupt, work_store)
        except Exception:
            if RUN.signal is None:
                raise
            # An interrupt that native code swallowed (a callback from LLVM while numba
            # compiles), which then failed the compile: the same Ctrl-C, the same message.
            _interrupted(interrupt_for(RUN.signal), work_store)
        remove_store(work_store)
    v = ds["mean_velocity"].values
    finite = v[np.isfinite(v)]
    if not quiet:
        print(
            f"{spec.n_chunks} chunks, {v.size} points {timer.took()}; "
            f"max v = {finite.max() if finite.size else float('nan'):.6e} m/s; wrote {out}"
        )
        if np.isinf(v).any():
            _note(
                f"{int(np.isinf(v).sum())} points have F > mu m g (no steady state): stored as inf"
            )
        if plot is not None:
            print(f"wrote {plot}")
    return 0


def _interrupted(interrupt: KeyboardInterrupt, work_store: Path) -> None:
    """Raise ``interrupt`` (Ctrl-C or SIGTERM, keeping its kind) saying what is kept: the
    finished chunks in ``work_store`` for a rerun to resume, unless the outputs are
    already complete (then the chunks are removed) or there are none."""
    from microslip.sweeps.store import remove_store

    if RUN.written:  # the outputs are complete: the chunks are not needed
        remove_store(work_store)
        raise interrupt
    if not work_store.exists():
        raise interrupt
    raise type(interrupt)(
        f"finished chunks are kept in {work_store}; run the same command again to resume"
    ) from None
