"""The ``microslip`` command line's argument parser: every command and its flags.

:func:`build_parser` builds it; :mod:`microslip.cli.main` runs a command line with
it. A usage error is one line on standard error and exit status :data:`EXIT_USAGE` (no
usage dump), and no flag may be abbreviated. ``--flag -1e-7`` is read as a value, not as
an option (:func:`join_negative_numbers`).
"""

from __future__ import annotations

import argparse

from microslip.cli.commands import (
    ALL_FIGURES,
    EXTENSION_FIGURES,
    cmd_figures,
    cmd_info,
    cmd_simulate,
)
from microslip.cli.friction_command import add_friction_command
from microslip.cli.model_options import add_part_options
from microslip.cli.options import finite, integer, path_text, real
from microslip.cli.response_command import cmd_response
from microslip.cli.sweep_command import cmd_sweep

__all__ = ["EXIT_USAGE", "build_parser", "join_negative_numbers", "one_line"]

EXIT_USAGE = 2

_PARAM_HELP = {
    "mass": "slider mass m [kg]",
    "g": "gravitational acceleration g [m/s^2]",
    "area": "nominal contact area S [m^2]",
    "c_n": "interface stiffness constant c_n [N/m^(2+m2)]",
    "m2": "interface exponent m2 = 1/m1 [-]",
    "mu": "friction coefficient mu [-]",
}


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (exit status 2, no usage dump) and no abbreviations
    (a prefix such as ``--forc`` would silently change meaning as flags are added)."""

    def __init__(self, *args, **kwargs) -> None:
        kwargs["allow_abbrev"] = False
        super().__init__(*args, **kwargs)

    def error(self, message: str):  # type: ignore[override]
        self.exit(EXIT_USAGE, f"{self.prog}: error: {one_line(message)} (see {self.prog} --help)\n")


def one_line(text: object) -> str:
    """``text`` on one line (runs of whitespace, newlines included, as one space)."""
    return " ".join(str(text).split())


def join_negative_numbers(argv: list[str]) -> list[str]:
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


def _add_model_options(parser: argparse.ArgumentParser, parts: bool = True) -> None:
    group = parser.add_argument_group("model parameters (SI; default: the paper's data)")
    for name, text in _PARAM_HELP.items():
        flag = f"--{name.replace('_', '-')}"
        # real, not finite(): Parameters names the field, its unit and the rule broken
        group.add_argument(flag, dest=name, type=real, help=text)
    if parts:
        add_part_options(parser)
        tables = "[parameters], [damping], [excitation], [tangential], [friction], [drive], options"
    else:
        tables = "[parameters] and options"
    parser.add_argument("--config", type=path_text, help=f"TOML file with {tables}")


def _add_output_options(parser: argparse.ArgumentParser, large: bool = True) -> None:
    parser.add_argument(
        "--overwrite",
        action="store_true",
        default=None,
        help="replace existing outputs (never a directory microslip did not write)",
    )
    if large:
        parser.add_argument(
            "--allow-large",
            dest="allow_large",
            action="store_true",
            default=None,
            help="run even when the up-front estimate exceeds the default work budget",
        )


def _flag(parser: argparse.ArgumentParser, name: str, **kwargs) -> None:
    """A store_true flag whose absence is None, so that a config value can stand."""
    parser.add_argument(name, action="store_true", default=None, **kwargs)


def _add_simulate(sub) -> None:
    sim = sub.add_parser("simulate", help="simulate one trajectory")
    sim.add_argument(
        "--force",
        type=finite,
        help="constant tangential force F [N] (< 0 pushes towards -x); required without "
        "--drive, refused with one (the drive sets the tangential loading)",
    )
    start = sim.add_mutually_exclusive_group()
    start.add_argument(
        "--amplitude",
        type=finite,
        help="A = y0 - y_min [m] (free vibration: required unless --initial-state; "
        "forced: default from rest at y0)",
    )
    start.add_argument(
        "--initial-state", dest="initial_state", help="y,ydot,x,xdot [m, m/s, m, m/s]"
    )
    sim.add_argument("--duration", type=finite, help="simulated time [s]")
    sim.add_argument("--method", choices=("event", "rk4"), help="integrator (default: event)")
    sim.add_argument("--dt", type=finite, help="rk4 only: step [s] (default T0/200)")
    sim.add_argument("--rtol", type=finite, help="event only: relative tolerance")
    sim.add_argument("--atol", type=finite, help="event only: absolute tolerance (natural units)")
    sim.add_argument("--samples", type=integer, help="output N evenly spaced samples")
    sim.add_argument(
        "--save-every",
        dest="save_every",
        type=integer,
        help="keep every n-th step (default: all, thinned to the default output size)",
    )
    sim.add_argument("--out", help="write the trajectory (.nc or .csv)")
    sim.add_argument("--plot", help="plot the trajectory (.png/.pdf/.svg)")
    _add_output_options(sim)
    _add_model_options(sim)
    sim.set_defaults(handler=cmd_simulate)


def _add_sweeps(sub) -> None:
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
        p.add_argument(
            "--method", choices=("steady", "time"),
            help="steady (default) or time (also takes --tangential spring or mindlin and "
            "--friction static-kinetic)",
        )  # fmt: skip
        p.add_argument("--duration", type=finite, help="time method: span [s]")
        p.add_argument("--dt", type=finite, help="time method: RK4 step [s]")
        p.add_argument(
            "--backend", choices=("cpu", "cuda"),
            help="time method (rigid, spring or mindlin contact): run the lanes on an NVIDIA GPU",
        )  # fmt: skip
        p.add_argument("--scheduler", help="Dask scheduler address tcp://HOST:PORT")
        p.add_argument("--workers", type=integer, help="start a local Dask cluster of N workers")
        p.add_argument("--chunk", type=integer, help="amplitudes per chunk")
        _flag(p, "--quiet", help="no progress bar, estimate note or summary")
        _add_output_options(p)
        _add_model_options(p)
        p.set_defaults(handler=cmd_sweep)


def _add_response(sub) -> None:
    resp = sub.add_parser(
        "response",
        help="forced-response curve of the normal motion (continuation, stability, folds)",
        description="Periodic orbits of the forced normal motion, continued from the orbit "
        "reached from rest at the first value to the second, through folds; Floquet "
        "stability, folds, period doubling and loss of contact. Needs --excitation.",
    )
    what = resp.add_mutually_exclusive_group()
    what.add_argument(
        "--frequencies", help="continue in excitation frequency F1:F2 [Hz] (from F1 to F2)"
    )
    what.add_argument(
        "--amplitudes",
        help="continue in excitation amplitude A1:A2 [N for harmonic-force, else m]",
    )
    resp.add_argument(
        "--max-points", dest="max_points", type=integer, help="at most N branch points"
    )
    resp.add_argument("--out", help="write the branch (.nc)")
    resp.add_argument(
        "--plot", help="draw the curve (.png/.pdf/.svg): stable solid, unstable dashed"
    )
    _add_output_options(resp, large=False)
    _add_model_options(resp)
    resp.set_defaults(handler=cmd_response)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="microslip",
        description="Sliding under dry friction driven by normal contact micro-vibrations "
        "(Grudzinski & Kostek 2005). SI units throughout.",
        epilog="Exit status: 0 success, 2 error (one line on stderr), 130 interrupted.",
    )
    from microslip import __version__

    parser.add_argument("--version", action="version", version=f"microslip {__version__}")
    sub = parser.add_subparsers(
        dest="command", required=True, metavar="COMMAND", parser_class=_Parser
    )

    info = sub.add_parser("info", help="parameters and derived quantities (y0, K_n, f0, ...)")
    _flag(info, "--json", help="print JSON")
    _add_model_options(info)
    info.set_defaults(handler=cmd_info)

    _add_simulate(sub)

    figs = sub.add_parser(
        "figures",
        help="reproduce the paper's Figs. 2-7 (--extensions: the figures of the extensions)",
    )
    figs.add_argument("--out", help="output directory (default: figures, or figures/ext)")
    figs.add_argument(
        "--only",
        help=f"comma-separated subset of {','.join(ALL_FIGURES)} "
        f"(with --extensions: of {','.join(EXTENSION_FIGURES)})",
    )
    figs.add_argument("--dpi", type=integer, help="PNG resolution (default 150)")
    _flag(
        figs,
        "--extensions",
        help="draw the extensions' figures instead: forced frequency response (several "
        "forcing levels, linear limit), v(F, f) map under a harmonic force, loss of contact "
        "in time (damping and excitation are fixed by each figure)",
    )
    _flag(figs, "--quiet", help="no progress messages")
    _add_output_options(figs, large=False)
    _add_model_options(figs, parts=False)
    figs.set_defaults(handler=cmd_figures)

    _add_response(sub)
    add_friction_command(sub, _add_model_options, _add_output_options)
    _add_sweeps(sub)
    return parser
