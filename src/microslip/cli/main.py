"""The ``microslip`` command: info, simulate, figures, map and sweep.

Every command takes the model's parameters as flags (one per Parameters field, SI
units) or from a TOML file (``--config``; flags win). Bad input ends with a one-line
error on standard error and exit status 2; outputs are written atomically.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

EXIT_USAGE = 2
EXIT_INTERRUPTED = 130

_PARAM_HELP = {
    "mass": "slider mass m [kg]",
    "g": "gravitational acceleration g [m/s^2]",
    "area": "nominal contact area S [m^2]",
    "c_n": "interface stiffness constant c_n [N/m^(2+m2)]",
    "m2": "interface exponent m2 = 1/m1 [-]",
    "mu": "friction coefficient mu [-]",
}


class CliError(ValueError):
    """An input error to report in one line."""


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (exit status 2, no usage dump)."""

    def error(self, message: str):  # type: ignore[override]
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _join_negative_numbers(argv: list[str]) -> list[str]:
    """Turn ``--flag -1e-7`` into ``--flag=-1e-7``: argparse takes "-1e-7" for an option."""
    joined: list[str] = []
    i = 0
    while i < len(argv):
        token = argv[i]
        if (
            token.startswith("--")
            and "=" not in token
            and i + 1 < len(argv)
            and argv[i + 1].startswith("-")
            and _is_number(argv[i + 1])
        ):
            joined.append(f"{token}={argv[i + 1]}")
            i += 2
            continue
        joined.append(token)
        i += 1
    return joined


def _is_number(text: str) -> bool:
    try:
        float(text.split(",")[0].split(":")[0])
    except ValueError:
        return False
    return True


# -- shared options ------------------------------------------------------------------------
def _add_model_options(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group("model parameters (SI; default: the paper's data)")
    for name, text in _PARAM_HELP.items():
        group.add_argument(f"--{name.replace('_', '-')}", dest=name, type=float, help=text)
    parser.add_argument("--config", type=Path, help="TOML file with [parameters] and options")


def _options(args: argparse.Namespace, command: str, names: set[str]) -> tuple[Any, dict]:
    """(Parameters, options) from config file then flags, flags winning."""
    from microslip.io.config import command_options, load_config, parameters_from_config
    from microslip.model.parameters import Parameters

    param_values: dict[str, Any] = {}
    options: dict[str, Any] = {}
    if args.config is not None:
        data = load_config(args.config)
        source = str(args.config)
        param_values.update(parameters_from_config(data, source))
        options.update(command_options(data, command, names, source))
    for name in Parameters.field_names():
        if getattr(args, name) is not None:
            param_values[name] = getattr(args, name)
    for name in names:
        value = getattr(args, name, None)
        if value is not None and value is not False:
            options[name] = value
    return Parameters(**param_values), options


def _finite(name: str):
    def convert(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name}: not a number: {text!r}") from None
        if not np.isfinite(value):
            raise argparse.ArgumentTypeError(f"{name}: must be finite, got {text!r}")
        return value

    return convert


# -- info -----------------------------------------------------------------------------------
def cmd_info(args: argparse.Namespace) -> int:
    params, _ = _options(args, "info", set())
    table = params.describe()
    if args.json:
        print(json.dumps(table, indent=2))
        return 0
    print("microslip model (Grudzinski & Kostek 2005)")
    for name, entry in table.items():
        print(f"  {name:22s} {entry['value']:<14.6g} {entry['unit']:12s} {entry['description']}")
    return 0


# -- simulate -------------------------------------------------------------------------------
_SIMULATE_OPTIONS = {
    "force", "amplitude", "initial_state", "duration", "method", "dt", "rtol", "atol",
    "samples", "save_every", "out", "plot",
}  # fmt: skip


def cmd_simulate(args: argparse.Namespace) -> int:
    import microslip as ms
    from microslip.io.output import DATASET_SUFFIXES, check_writable, write_dataset
    from microslip.simulation import DEFAULT_ATOL, DEFAULT_RTOL

    params, opts = _options(args, "simulate", _SIMULATE_OPTIONS)
    for required in ("force", "duration"):
        if required not in opts:
            raise CliError(f"--{required} is required (flag or [simulate] in --config)")
    out = check_writable(opts["out"], DATASET_SUFFIXES) if "out" in opts else None
    plot = check_writable(opts["plot"], (".png", ".pdf", ".svg")) if "plot" in opts else None
    initial_state = opts.get("initial_state")
    if isinstance(initial_state, str):
        try:
            initial_state = [float(v) for v in initial_state.split(",")]
        except ValueError:
            raise CliError(
                f"--initial-state: expected y,ydot,x,xdot, got {initial_state!r}"
            ) from None
    if "amplitude" not in opts and initial_state is None:
        raise CliError("give --amplitude or --initial-state")
    t_eval = None
    if "samples" in opts:
        samples = opts["samples"]
        if isinstance(samples, bool) or not isinstance(samples, int) or samples < 2:
            raise CliError(f"--samples must be an integer >= 2, got {samples!r}")
        t_eval = np.linspace(0.0, float(opts["duration"]), samples)
    started = time.perf_counter()
    result = ms.simulate(
        params,
        force=opts["force"],
        duration=opts["duration"],
        amplitude=opts.get("amplitude"),
        initial_state=initial_state,
        method=opts.get("method", "event"),
        dt=opts.get("dt"),
        rtol=opts.get("rtol", DEFAULT_RTOL),
        atol=opts.get("atol", DEFAULT_ATOL),
        t_eval=t_eval,
        save_every=opts.get("save_every", 1),
    )
    elapsed = time.perf_counter() - started
    kinds = [k for _, k in result.events]
    print(
        f"simulated {result.t[-1]:.6g} s with {result.method} in {elapsed:.3f} s: "
        f"x = {result.x[-1]:.6e} m, mean velocity x/t = {result.x[-1] / result.t[-1]:.6e} m/s, "
        f"{kinds.count('slip_start')} slip starts, {kinds.count('stick_start')} sticks, "
        f"{kinds.count('contact_lost')} losses of contact, {result.t.size} samples"
    )
    if out is not None:
        write_dataset(result.to_xarray(), out)
        print(f"wrote {out}")
    if plot is not None:
        from microslip.plotting.trajectory import write_trajectory_plot

        write_trajectory_plot(result, plot)
        print(f"wrote {plot}")
    return 0


# -- figures --------------------------------------------------------------------------------
ALL_FIGURES = ("fig2", "fig3", "fig4", "fig5", "fig6", "fig7")


def cmd_figures(args: argparse.Namespace) -> int:
    params, _ = _options(args, "figures", set())
    names = ALL_FIGURES if args.only is None else tuple(n.strip() for n in args.only.split(","))
    for name in names:
        if name not in ALL_FIGURES:
            raise CliError(f"--only: unknown figure {name!r}; known: {', '.join(ALL_FIGURES)}")
    out_dir = Path(args.out)
    if out_dir.exists() and not out_dir.is_dir():
        raise CliError(f"--out {str(out_dir)!r} exists and is not a directory")
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise CliError(f"--out {str(out_dir)!r}: cannot create directory: {error}") from None
    from microslip.io.output import check_writable

    check_writable(out_dir / "probe.png")
    from microslip.plotting.figures import write_figures

    started = time.perf_counter()
    paths = write_figures(out_dir, params, names, dpi=args.dpi, progress=_say(args.quiet))
    print(f"wrote {len(paths)} files to {out_dir} in {time.perf_counter() - started:.1f} s")
    return 0


def _say(quiet: bool):
    return (lambda message: None) if quiet else (lambda message: print(message, flush=True))


# -- map / sweep ------------------------------------------------------------------------
_SWEEP_OPTIONS = {
    "force", "amplitude", "param", "out", "plot", "method", "duration", "dt", "scheduler",
    "workers", "chunk", "quiet",
}  # fmt: skip


def _sweep_axes(specs: list[str]) -> dict[str, np.ndarray]:
    from microslip.io.ranges import parse_values

    axes: dict[str, np.ndarray] = {}
    for text in specs:
        name, sep, values = str(text).partition("=")
        name = name.strip()
        if not sep or not name:
            raise CliError(f"--param: expected NAME=RANGE, got {text!r}")
        if name in axes:
            raise CliError(f"--param: {name!r} given twice")
        axes[name] = parse_values(f"--param {name}", values)
    return axes


def cmd_sweep(args: argparse.Namespace) -> int:
    from microslip.io.output import check_writable, write_dataset
    from microslip.io.ranges import parse_values
    from microslip.sweeps import SweepSpec, run_sweep

    params, opts = _options(args, args.command, _SWEEP_OPTIONS)
    for required in ("force", "amplitude", "out"):
        if required not in opts:
            raise CliError(f"--{required} is required")
    forces = parse_values("--force", opts["force"])
    amplitudes = parse_values("--amplitude", opts["amplitude"])
    param_specs = opts.get("param", [])
    param_specs = [param_specs] if isinstance(param_specs, str) else list(param_specs)
    axes = _sweep_axes(param_specs) if args.command == "sweep" else {}
    out = check_writable(opts["out"], (".nc", ".zarr"))
    plot = check_writable(opts["plot"], (".png", ".pdf", ".svg")) if "plot" in opts else None
    if plot is not None:  # refuse a plot that cannot be drawn before computing anything
        from microslip.plotting.velocity_map import sweep_plot_kind

        sizes = {name: len(values) for name, values in axes.items()}
        try:
            sweep_plot_kind({**sizes, "force": len(forces), "amplitude": len(amplitudes)})
        except ValueError as error:
            raise CliError(str(error)) from None
    workers = opts.get("workers")
    if workers is not None and (not isinstance(workers, int) or workers < 1):
        raise CliError(f"--workers must be an integer >= 1, got {workers!r}")
    spec = SweepSpec.build(
        params, axes, forces, amplitudes,
        method=opts.get("method", "steady"),
        duration=opts.get("duration", 0.05),
        dt=opts.get("dt"),
        amplitude_chunk=opts.get("chunk"),
    )  # fmt: skip
    work_store = out.with_name(out.name + ".partial.zarr")
    quiet = bool(opts.get("quiet", False))
    started = time.perf_counter()
    try:
        ds = run_sweep(
            spec,
            store=work_store,
            scheduler=opts.get("scheduler"),
            workers=workers,
            progress=not quiet and sys.stderr.isatty(),
        )
    except KeyboardInterrupt:
        print(
            f"microslip: interrupted; finished chunks are kept in {work_store}; "
            "run the same command again to resume",
            file=sys.stderr,
        )
        return EXIT_INTERRUPTED
    write_dataset(ds, out)
    shutil.rmtree(work_store, ignore_errors=True)
    elapsed = time.perf_counter() - started
    v = ds["mean_velocity"].values
    finite = v[np.isfinite(v)]
    if not quiet:
        print(
            f"{spec.n_chunks} chunks, {v.size} points in {elapsed:.2f} s; "
            f"max v = {finite.max() if finite.size else float('nan'):.6e} m/s; wrote {out}"
        )
        if np.isinf(v).any():
            print(
                f"note: {int(np.isinf(v).sum())} points have F > mu m g "
                "(no steady state): stored as inf",
                file=sys.stderr,
            )
    if plot is not None:
        from microslip.plotting.velocity_map import write_velocity_map_plot

        write_velocity_map_plot(ds, plot, params)
        if not quiet:
            print(f"wrote {plot}")
    return 0


# -- parser ---------------------------------------------------------------------------------
def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="microslip",
        description="Sliding under dry friction driven by normal contact micro-vibrations "
        "(Grudzinski & Kostek 2005). SI units throughout.",
    )
    from microslip import __version__

    parser.add_argument("--version", action="version", version=f"microslip {__version__}")
    sub = parser.add_subparsers(
        dest="command", required=True, metavar="COMMAND", parser_class=_Parser
    )

    info = sub.add_parser("info", help="parameters and derived quantities (y0, K_n, f0, ...)")
    info.add_argument("--json", action="store_true", help="print JSON")
    _add_model_options(info)
    info.set_defaults(handler=cmd_info)

    sim = sub.add_parser("simulate", help="simulate one trajectory")
    sim.add_argument("--force", type=_finite("--force"), help="tangential force F [N] (< 0 pushes towards -x)")
    start = sim.add_mutually_exclusive_group()
    start.add_argument("--amplitude", type=_finite("--amplitude"), help="A = y0 - y_min [m]")
    start.add_argument(
        "--initial-state", dest="initial_state", help="y,ydot,x,xdot [m, m/s, m, m/s]"
    )
    sim.add_argument("--duration", type=_finite("--duration"), help="simulated time [s]")
    sim.add_argument("--method", choices=("event", "rk4"), help="integrator (default: event)")
    sim.add_argument("--dt", type=_finite("--dt"), help="RK4 step [s] (default T0/200)")
    sim.add_argument("--rtol", type=_finite("--rtol"), help="event method relative tolerance")
    sim.add_argument(
        "--atol", type=_finite("--atol"), help="event method absolute tolerance (natural units)"
    )
    sim.add_argument("--samples", type=int, help="output N evenly spaced samples")
    sim.add_argument("--save-every", dest="save_every", type=int, help="keep every n-th step")
    sim.add_argument("--out", help="write the trajectory (.nc or .csv)")
    sim.add_argument("--plot", help="plot the trajectory (.png/.pdf/.svg)")
    _add_model_options(sim)
    sim.set_defaults(handler=cmd_simulate)

    figs = sub.add_parser("figures", help="reproduce the paper's Figs. 2-7")
    figs.add_argument("--out", default="figures", help="output directory (default: figures)")
    figs.add_argument("--only", help=f"comma-separated subset of {','.join(ALL_FIGURES)}")
    figs.add_argument("--dpi", type=int, default=150, help="PNG resolution (default 150)")
    figs.add_argument("--quiet", action="store_true", help="no progress messages")
    _add_model_options(figs)
    figs.set_defaults(handler=cmd_figures)

    for name, text in (
        ("map", "mean sliding velocity over force x amplitude (Fig. 7)"),
        ("sweep", "mean sliding velocity over parameters x force x amplitude"),
    ):
        p = sub.add_parser(name, help=text)
        p.add_argument("--force", help="forces [N]: start:stop:count, a,b,c or one value")
        p.add_argument("--amplitude", help="amplitudes [m]: start:stop:count, a,b,c or one value")
        if name == "sweep":
            p.add_argument(
                "--param", action="append", help="NAME=RANGE for a Parameters field (repeatable)"
            )
        p.add_argument("--out", help="result file (.nc or .zarr); resumable")
        p.add_argument("--plot", help="draw the map (.png/.pdf/.svg)")
        p.add_argument("--method", choices=("steady", "time"), help="steady (default) or time")
        p.add_argument("--duration", type=_finite("--duration"), help="time method: span [s]")
        p.add_argument("--dt", type=_finite("--dt"), help="time method: RK4 step [s]")
        p.add_argument("--scheduler", help="Dask scheduler address tcp://HOST:PORT")
        p.add_argument("--workers", type=int, help="start a local Dask cluster of N workers")
        p.add_argument("--chunk", type=int, help="amplitudes per chunk")
        p.add_argument("--quiet", action="store_true", help="no progress bar or summary")
        _add_model_options(p)
        p.set_defaults(handler=cmd_sweep)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(_join_negative_numbers(sys.argv[1:] if argv is None else argv))
    try:
        return args.handler(args)
    except (ValueError, ConnectionError) as error:
        print(f"microslip {args.command}: error: {error}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as error:
        print(f"microslip {args.command}: error: {error}", file=sys.stderr)
        return EXIT_USAGE


def entry_point() -> None:
    sys.exit(main())


if __name__ == "__main__":
    entry_point()
