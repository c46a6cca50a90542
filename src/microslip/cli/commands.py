"""The commands: info, simulate, figures, map and sweep.

Each command validates everything (inputs, option combinations, every output path and
the work budget) before it computes anything, so a refused run leaves no file behind.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from microslip.cli.options import CliError, Options, gather

ALL_FIGURES = ("fig2", "fig3", "fig4", "fig5", "fig6", "fig7")


def _note(message: str) -> None:
    print(f"microslip: note: {message}", file=sys.stderr)


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
    try:
        return [float(v) for v in str(text).split(",")]
    except ValueError:
        raise CliError(
            f"{opts.flag('initial_state')}: expected y,ydot,x,xdot, got {text!r}"
        ) from None


def cmd_simulate(args: argparse.Namespace) -> int:
    import microslip as ms
    from microslip.budget import default_save_every
    from microslip.io.output import DATASET_SUFFIXES, PLOT_SUFFIXES, check_writable, write_dataset
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
    out = (
        check_writable(opts["out"], DATASET_SUFFIXES, overwrite=overwrite)
        if "out" in opts
        else None
    )
    plot = (
        check_writable(opts["plot"], PLOT_SUFFIXES, overwrite=overwrite) if "plot" in opts else None
    )
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
    print(
        f"simulated {result.t[-1]:.6g} s with {result.method} in {elapsed:.3f} s: "
        f"x = {result.x[-1]:.6e} m, mean velocity x/t = {result.x[-1] / result.t[-1]:.6e} m/s, "
        f"{kinds.count('slip_start')} slip starts, {kinds.count('stick_start')} sticks, "
        f"{kinds.count('contact_lost')} losses of contact, {result.t.size} samples"
    )
    if thinned:  # after the run: a refused run must print one line only
        _note(
            f"output thinned to 1 step in {save_every} ({result.t.size} samples); "
            "choose with --samples or --save-every"
        )
    if out is not None:
        write_dataset(result.to_xarray(), out, overwrite=overwrite)
        print(f"wrote {out}")
    if plot is not None:
        from microslip.plotting.trajectory import write_trajectory_plot

        write_trajectory_plot(result, plot)
        print(f"wrote {plot}")
    return 0


# -- figures ----------------------------------------------------------------------------
def cmd_figures(args: argparse.Namespace) -> int:
    from microslip.io.output import OutputExistsError, check_writable

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
    overwrite = bool(opts.get("overwrite", False))
    out_dir = Path(opts.get("out", "figures"))
    if out_dir.exists() and not out_dir.is_dir():
        raise CliError(f"--out {str(out_dir)!r} exists and is not a directory")
    targets = [out_dir / f"{name}.{ext}" for name in names for ext in ("png", "nc")]
    existing = [t for t in targets if t.exists() or t.is_symlink()]
    if existing and not overwrite:  # all of them, before computing anything
        more = f" (and {len(existing) - 1} more)" if len(existing) > 1 else ""
        raise OutputExistsError(
            f"output {str(existing[0])!r} exists{more}; pass --overwrite to replace"
        )
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise CliError(
            f"--out {str(out_dir)!r}: cannot create directory: {error.strerror}"
        ) from None
    for target in targets:
        check_writable(target, overwrite=overwrite)
    from microslip.plotting.figures import write_figures

    quiet = bool(opts.get("quiet", False))
    say = (lambda message: None) if quiet else (lambda message: print(message, flush=True))
    started = time.perf_counter()
    paths = write_figures(out_dir, opts.params, names, dpi=dpi, progress=say)
    print(f"wrote {len(paths)} files to {out_dir} in {time.perf_counter() - started:.1f} s")
    return 0


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
        axes[name] = parse_values(f"--param {name}", values)
    return axes


def cmd_sweep(args: argparse.Namespace) -> int:
    from microslip.io.output import PLOT_SUFFIXES, OutputError, check_writable, write_dataset
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
    forces = parse_values(opts.flag("force"), opts["force"])
    amplitudes = parse_values(opts.flag("amplitude"), opts["amplitude"])
    axes = _sweep_axes(opts)
    overwrite = bool(opts.get("overwrite", False))
    out = check_writable(opts["out"], (".nc", ".zarr"), overwrite=overwrite)
    plot = (
        check_writable(opts["plot"], PLOT_SUFFIXES, overwrite=overwrite) if "plot" in opts else None
    )
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
    with exclusive_lock(out):
        try:
            ds = run_sweep(
                spec,
                store=work_store,
                scheduler=opts.get("scheduler"),
                workers=workers,
                progress=not quiet and sys.stderr.isatty(),
            )
            write_dataset(ds, out, overwrite=overwrite)
        except OSError as error:  # a full disk or a vanished directory while computing
            raise OutputError(
                f"cannot write {str(work_store)!r}: {error.strerror or error}; "
                "finished chunks are kept there for a rerun"
            ) from None
        except KeyboardInterrupt:
            raise KeyboardInterrupt(
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
        from microslip.plotting.velocity_map import write_velocity_map_plot

        write_velocity_map_plot(ds, plot, params)
        if not quiet:
            print(f"wrote {plot}")
    return 0
