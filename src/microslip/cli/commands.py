"""The commands: info, simulate, figures, map and sweep.

Each command validates everything (inputs, option combinations, every output path and
the work budget) before it computes anything, so a refused run leaves no file behind.
Outputs are written to temporaries and moved into place together at the end (Ctrl-C
and SIGTERM held back meanwhile), so a failed or interrupted run leaves none of them.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
import time
import uuid
from pathlib import Path

import numpy as np

from microslip.cli.interrupts import RUN, uninterruptible
from microslip.cli.options import CliError, Options, gather, refuse_underscores

ALL_FIGURES = ("fig2", "fig3", "fig4", "fig5", "fig6", "fig7")


def _note(message: str) -> None:
    print(f"microslip: note: {message}", file=sys.stderr)


def _output_path(opts: Options, name: str, config: object) -> Path:
    """Option ``name`` as a path: not empty, and not the ``--config`` file it was read with."""
    text = str(opts[name])
    if not text.strip():
        raise CliError(f"{opts.flag(name)}: empty path")
    path = Path(text)
    if config is not None and _same_file(path, Path(str(config))):
        raise CliError(f"{opts.flag(name)} {text!r} is the --config file; choose another output")
    return path


def _same_file(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:  # one of them does not exist
        return a.resolve() == b.resolve()


def _commit(batch) -> list[Path]:
    """Move every output into place with Ctrl-C held back; record them as complete."""
    with uninterruptible():
        written = batch.commit()
        RUN.written = [str(path) for path in written]
    return written


def _check_method(opts: Options, choices: tuple[str, ...], default: str) -> str:
    method = opts.get("method", default)
    if method not in choices:
        raise CliError(f"{opts.flag('method')} must be one of {', '.join(choices)}; got {method!r}")
    return method


# -- info -------------------------------------------------------------------------------
def cmd_info(args: argparse.Namespace) -> int:
    opts = gather(args, "info")
    table = opts.params.describe()
    if opts.get("json", False):
        print(json.dumps(table, indent=2))
        return 0
    print("microslip model (Grudzinski & Kostek 2005)")
    for name, entry in table.items():
        print(f"  {name:22s} {entry['value']:<14.6g} {entry['unit']:12s} {entry['description']}")
    return 0


# -- simulate ---------------------------------------------------------------------------
def _initial_state(opts: Options) -> list[float] | None:
    text = opts.get("initial_state")
    if text is None:
        return None
    refuse_underscores(opts.flag("initial_state"), text)
    try:
        return [float(v) for v in str(text).split(",")]
    except ValueError:
        raise CliError(
            f"{opts.flag('initial_state')}: expected y,ydot,x,xdot, got {text!r}"
        ) from None


def cmd_simulate(args: argparse.Namespace) -> int:
    import microslip as ms
    from microslip.budget import default_save_every
    from microslip.io.output import (
        DATASET_SUFFIXES,
        PLOT_SUFFIXES,
        OutputBatch,
        check_writable,
        write_dataset,
    )
    from microslip.simulation import DEFAULT_ATOL, DEFAULT_RTOL

    opts = gather(args, "simulate")
    params = opts.params
    for required in ("force", "duration"):
        if required not in opts:
            raise CliError(f"--{required} is required (flag or [simulate] in --config)")
    method = _check_method(opts, ("event", "rk4"), "event")
    if method == "event":
        opts.refuse("dt", "with --method event (it adapts its step; see --rtol/--atol)")
    else:
        for name in ("rtol", "atol"):
            opts.refuse(name, "with --method rk4 (a fixed step; see --dt)")
    opts.refuse_together("samples", "save_every", "both choose the output samples")
    opts.refuse_together("amplitude", "initial_state", "both set the initial state")
    overwrite = bool(opts.get("overwrite", False))
    allow_large = bool(opts.get("allow_large", False))
    out = plot = None
    if "out" in opts:
        out = _output_path(opts, "out", args.config)
        check_writable(out, DATASET_SUFFIXES, overwrite=overwrite)
    if "plot" in opts:
        plot = _output_path(opts, "plot", args.config)
        check_writable(plot, PLOT_SUFFIXES, overwrite=overwrite)
    if out is not None and plot is not None and _same_file(out, plot):
        raise CliError(f"{opts.flag('out')} and {opts.flag('plot')} name the same file")
    initial_state = _initial_state(opts)
    if "amplitude" not in opts and initial_state is None:
        raise CliError("give --amplitude or --initial-state")
    duration = opts["duration"]
    t_eval = None
    save_every = opts.get("save_every", 1)
    thinned = False
    if "samples" in opts:
        samples = opts["samples"]
        if samples < 2:
            raise CliError(f"{opts.flag('samples')} must be an integer >= 2, got {samples!r}")
        _check_samples(opts, samples, allow_large)
        if duration > 0:
            t_eval = np.linspace(0.0, float(duration), samples)
    elif "save_every" not in opts and duration > 0:
        # Without a choice of samples, keep the output within the default size (budget).
        save_every = default_save_every(
            params,
            duration=duration,
            method=method,
            dt=opts.get("dt"),
            rtol=opts.get("rtol", DEFAULT_RTOL),
        )
        thinned = save_every > 1
    started = time.perf_counter()
    result = ms.simulate(
        params,
        force=opts["force"],
        duration=duration,
        amplitude=opts.get("amplitude"),
        initial_state=initial_state,
        method=method,
        dt=opts.get("dt"),
        rtol=opts.get("rtol", DEFAULT_RTOL),
        atol=opts.get("atol", DEFAULT_ATOL),
        t_eval=t_eval,
        save_every=save_every,
        allow_large=allow_large,
    )
    elapsed = time.perf_counter() - started
    kinds = [k for _, k in result.events]
    # the slider's own displacement over the run: x(0) need not be 0 (--initial-state)
    span = float(result.t[-1])
    mean_v = (result.x[-1] - result.x[0]) / span if span > 0 else float("nan")
    print(
        f"simulated {span:.6g} s with {result.method} in {elapsed:.3f} s: "
        f"x = {result.x[-1]:.6e} m, mean velocity (x(T)-x(0))/T = {mean_v:.6e} m/s, "
        f"{kinds.count('slip_start')} slip starts, {kinds.count('stick_start')} sticks, "
        f"{kinds.count('contact_lost')} losses of contact, {result.t.size} samples"
    )
    if thinned:  # after the run: a refused run must print one line only
        _note(
            f"output thinned to 1 step in {save_every} ({result.t.size} samples); "
            "choose with --samples or --save-every"
        )
    with OutputBatch(overwrite=overwrite) as batch:
        if out is not None:
            data = result.to_xarray()
            batch.write(out, lambda tmp: write_dataset(data, tmp, overwrite=False))
        if plot is not None:
            from microslip.plotting.trajectory import write_trajectory_plot

            batch.write(plot, lambda tmp: write_trajectory_plot(result, tmp))
        for path in _commit(batch):
            print(f"wrote {path}")
    return 0


def _check_samples(opts: Options, samples: int, allow_large: bool) -> None:
    """Refuse a sample count whose output cannot fit in memory, before allocating it."""
    from microslip.budget import BYTES_PER_SAMPLE, MEMORY_FRACTION, available_memory

    need = float(samples) * BYTES_PER_SAMPLE
    limit = available_memory() * (1.0 if allow_large else MEMORY_FRACTION)
    if need > limit:
        more = "" if allow_large else " (--allow-large raises the limit to all of it)"
        raise CliError(
            f"{opts.flag('samples')} = {samples} is too large: ~{need:.3g} bytes of output, "
            f"{limit:.3g} bytes of memory allowed{more}"
        )


# -- figures ----------------------------------------------------------------------------
def cmd_figures(args: argparse.Namespace) -> int:
    from microslip.io.output import OutputBatch, OutputError, OutputExistsError, check_writable
    from microslip.plotting.figures import check_drawable

    opts = gather(args, "figures")
    only = opts.get("only")
    names = ALL_FIGURES if only is None else tuple(n.strip() for n in only.split(","))
    for name in names:
        if name not in ALL_FIGURES:
            raise CliError(
                f"{opts.flag('only')}: unknown figure {name!r}; known: {', '.join(ALL_FIGURES)}"
            )
    dpi = opts.get("dpi", 150)
    if not 10 <= dpi <= 2400:
        raise CliError(f"{opts.flag('dpi')} must be an integer in [10, 2400], got {dpi!r}")
    check_drawable(opts.params, names)  # μ = 0 and Figs. 4–7: refused before computing
    overwrite = bool(opts.get("overwrite", False))
    out_dir = _output_path(opts, "out", args.config) if "out" in opts else Path("figures")
    if "\\" in str(out_dir.absolute()):  # HDF5 cannot create figN.nc there
        raise OutputError(
            f"--out {str(out_dir)!r}: NetCDF files cannot be created under a path with a "
            "backslash; choose another directory"
        )
    if out_dir.exists() and not out_dir.is_dir():
        raise CliError(f"--out {str(out_dir)!r} exists and is not a directory")
    targets = [out_dir / f"{name}.{ext}" for name in names for ext in ("png", "nc")]
    existing = [t for t in targets if t.exists() or t.is_symlink()]
    if existing and not overwrite:  # all of them, before computing anything
        more = f" (and {len(existing) - 1} more)" if len(existing) > 1 else ""
        raise OutputExistsError(
            f"output {str(existing[0])!r} exists{more}; pass --overwrite to replace"
        )
    if args.config is not None and any(_same_file(t, Path(args.config)) for t in targets):
        raise CliError(f"--out {str(out_dir)!r} would replace the --config file")
    created = [d for d in (out_dir, *out_dir.parents) if not d.exists()][::-1]
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        _remove_empty(created)
        raise CliError(
            f"--out {str(out_dir)!r}: cannot create directory: {error.strerror}"
        ) from None
    try:
        for target in targets:
            check_writable(target, overwrite=overwrite)
        _write_figures(out_dir, opts, names, dpi, OutputBatch(overwrite=overwrite))
    except BaseException:  # also Ctrl-C: no directory of this run left behind, empty
        _remove_empty(created)
        raise
    return 0


def _write_figures(out_dir: Path, opts: Options, names, dpi: int, batch) -> list[Path]:
    """Draw into a hidden directory inside ``out_dir``; move the files out at the end."""
    from microslip.plotting.figures import write_figures
    from microslip.plotting.scales import FigureNotDrawable

    quiet = bool(opts.get("quiet", False))
    say = (lambda message: None) if quiet else (lambda message: print(message, flush=True))
    started = time.perf_counter()
    work = out_dir / f".figures.{uuid.uuid4().hex[:8]}.partial"
    try:
        with batch:
            try:
                paths = write_figures(work, opts.params, names, dpi=dpi, progress=say)
            except FigureNotDrawable as error:  # keep what its message says was written
                for path in error.written:
                    batch.stage(Path(path), out_dir / Path(path).name)
                error.written = tuple(_commit(batch))
                raise
            for path in paths:
                batch.stage(path, out_dir / path.name)
            written = _commit(batch)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(f"wrote {len(written)} files to {out_dir} in {time.perf_counter() - started:.1f} s")
    return written


def _remove_empty(directories: list[Path]) -> None:
    """Remove the directories this run created, deepest first, if they are still empty."""
    for directory in reversed(directories):
        try:
            directory.rmdir()
        except OSError:
            return


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
        if name in opts.param_origin:
            raise CliError(
                f"{opts.flag('param')} {name}=... cannot be combined with "
                f"{opts.param_origin[name]}: both set {name}"
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
    from microslip.io.output import (
        PLOT_SUFFIXES,
        OutputBatch,
        OutputError,
        check_writable,
        write_dataset,
    )
    from microslip.io.ranges import parse_values
    from microslip.sweeps import SweepSpec, run_sweep
    from microslip.sweeps.store import exclusive_lock, remove_store

    opts = gather(args, args.command)
    params = opts.params
    method = _check_method(opts, ("steady", "time"), "steady")
    if method == "steady":
        for name in ("duration", "dt"):
            opts.refuse(name, "with --method steady (the exact steady state has no time step)")
    opts.refuse_together(
        "workers", "scheduler", "--workers starts a local cluster, --scheduler uses a running one"
    )
    for required in ("force", "amplitude", "out"):
        if required not in opts:
            raise CliError(f"--{required} is required (flag or [{args.command}] in --config)")
    _check_scheduler(opts)
    forces = parse_values(opts.flag("force"), refuse_underscores(opts.flag("force"), opts["force"]))
    amplitudes = parse_values(
        opts.flag("amplitude"), refuse_underscores(opts.flag("amplitude"), opts["amplitude"])
    )
    axes = _sweep_axes(opts)
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
            sweep_plot_kind({**sizes, "force": len(forces), "amplitude": len(amplitudes)})
        except ValueError as error:
            raise CliError(str(error)) from None
    workers = opts.get("workers")
    if workers is not None and workers < 1:
        raise CliError(f"{opts.flag('workers')} must be an integer >= 1, got {workers!r}")
    chunk = opts.get("chunk")
    if chunk is not None and chunk < 1:
        raise CliError(f"{opts.flag('chunk')} must be an integer >= 1, got {chunk!r}")
    spec = SweepSpec.build(
        params, axes, forces, amplitudes,
        method=method, duration=opts.get("duration", 0.05), dt=opts.get("dt"),
        amplitude_chunk=chunk,
    )  # fmt: skip
    spec.check_budget(allow_large=bool(opts.get("allow_large", False)))
    work_store = out.with_name(out.name + ".partial.zarr")
    quiet = bool(opts.get("quiet", False))
    started = time.perf_counter()
    # One run per output at a time: a second one stops here at once (StoreBusyError).
    with exclusive_lock(out), OutputBatch(overwrite=overwrite) as batch:
        try:
            ds = run_sweep(
                spec,
                store=work_store,
                scheduler=opts.get("scheduler"),
                workers=workers,
                progress=not quiet and sys.stderr.isatty(),
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
            if RUN.written:  # the outputs are complete: the chunks are not needed
                remove_store(work_store)
                raise
            if not work_store.exists():
                raise
            raise type(interrupt)(
                f"finished chunks are kept in {work_store}; run the same command again to resume"
            ) from None
        remove_store(work_store)
    elapsed = time.perf_counter() - started
    v = ds["mean_velocity"].values
    finite = v[np.isfinite(v)]
    if not quiet:
        print(
            f"{spec.n_chunks} chunks, {v.size} points in {elapsed:.2f} s; "
            f"max v = {finite.max() if finite.size else float('nan'):.6e} m/s; wrote {out}"
        )
        if np.isinf(v).any():
            _note(
                f"{int(np.isinf(v).sum())} points have F > mu m g (no steady state): stored as inf"
            )
        if plot is not None:
            print(f"wrote {plot}")
    return 0
