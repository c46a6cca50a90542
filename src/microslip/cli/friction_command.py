"""``microslip friction``: the effective friction coefficient under normal vibration.

The body is driven at a prescribed velocity v (``PrescribedVelocity``, added by the
command when no ``--drive`` is given); μ_eff = <F_t>/<N> over the steady motion against
v (``--velocities``), or a map over v and one more quantity (``--axis NAME=RANGE``: a
model field by dotted name, ``excitation.amplitude``, ``tangential.stiffness``, ... or
``amplitude``, the free-vibration amplitude A [m]). Computed by
:mod:`microslip.analysis.effective_friction` (docs/theory/friction_reduction.md),
written to NetCDF (``--out``) and drawn (``--plot``). Like every command, it checks
everything (the model at both ends of each range, the outputs) before computing.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import Any

import numpy as np

from microslip.cli.commands import _output_path, _same_file, write_outputs
from microslip.cli.options import CliError, Options, finite, gather, parse_range
from microslip.cli.timing import CommandTimer

__all__ = ["add_friction_command", "cmd_friction", "summary_lines"]

KINEMATIC = "prescribed-velocity"
FREE_AMPLITUDE = "amplitude"  # the axis name of the free-vibration amplitude A [m]


def add_friction_command(
    sub: Any,
    add_model_options: Callable[[argparse.ArgumentParser], None],
    add_output_options: Callable[..., None],
) -> None:
    """The ``friction`` sub-command (the model and output flags are main's)."""
    p = sub.add_parser(
        "friction",
        help="effective friction mu_eff = <F_t>/<N> against a prescribed sliding velocity",
        description="Effective friction coefficient mu_eff = <F_t>/<N> of a body driven at "
        "a prescribed velocity v over a vibrating contact, against v (a curve) or against v "
        "and one more quantity (--axis: a map). The drive is --drive prescribed-velocity, "
        "added when no --drive is given; its velocity is the --velocities axis. Options in "
        "a --config file go in [effective-friction] ([friction] is the friction law).",
    )
    p.add_argument(
        "--velocities",
        help="sliding velocities v [m s-1]: start:stop:count, start:stop:count:log "
        "(evenly spaced in log10), a,b,c or one value",
    )
    p.add_argument(
        "--axis",
        help="NAME=RANGE: a second axis, NAME a model field by dotted name "
        "(excitation.amplitude, tangential.stiffness, damping.ratio, mu, ...) or amplitude "
        "(free-vibration amplitude A [m]); RANGE as for --velocities",
    )
    p.add_argument(
        "--amplitude",
        type=finite,
        help="free-vibration amplitude A = y0 - y_min [m] (a model without excitation)",
    )
    p.add_argument("--out", help="write the curve or map (.nc)")
    p.add_argument("--plot", help="draw mu_eff/mu with the critical v_tilde = 1 (.png/.pdf/.svg)")
    add_output_options(p, large=False)
    add_model_options(p)
    p.set_defaults(handler=cmd_friction)


def _kinematic_drive(opts: Options) -> None:
    """Make the drive a prescribed velocity (the command's own, when none is given)."""
    drive = opts.parts["drive"]
    if not drive.given:
        drive.kind, drive.kind_origin = KINEMATIC, "microslip friction"
    elif drive.kind != KINEMATIC:
        raise CliError(
            f"{drive.kind_origin}: friction drives the body at the prescribed velocities of "
            f"--velocities, not with drive {drive.kind}: give --drive {KINEMATIC} or leave "
            "--drive out"
        )


def _axis(opts: Options) -> tuple[str, np.ndarray, str] | None:
    """(name, values, what) of ``--axis NAME=RANGE``, or None."""
    if "axis" not in opts:
        return None
    flag = opts.flag("axis")
    text = str(opts["axis"])
    name, sep, values = text.partition("=")
    name = name.strip().removeprefix("params.")
    if not sep or not name:
        raise CliError(f"{flag}: expected NAME=RANGE, got {text!r}")
    what = f"{flag} {name}=..."
    if name in ("drive.velocity", "velocity", "velocities"):
        raise CliError(f"{flag}: the velocity is the --velocities axis; choose another NAME")
    if name == FREE_AMPLITUDE and "amplitude" in opts:
        raise CliError(f"{what} cannot be combined with {opts.flag('amplitude')}: both set A")
    given = {**opts.param_origin, **opts.part_origin()}
    if name in given:
        raise CliError(f"{what} cannot be combined with {given[name]}: both set {name}")
    return name, parse_range(f"{flag} {name}", values), what


def _check_ends(model: Any, name: str, values: np.ndarray, what: str) -> None:
    """Both ends of a model-field axis within the field's supported range."""
    for value in (float(values.min()), float(values.max())):
        try:
            model.replace(**{name: value})
        except ValueError as error:
            raise CliError(f"{what}: {error}") from None


def cmd_friction(args: argparse.Namespace) -> int:
    from microslip.io.output import PLOT_SUFFIXES, check_writable

    opts = gather(args, "friction")
    if "velocities" not in opts:
        raise CliError(
            "--velocities [m s-1] is required (flag or [effective-friction] in --config)"
        )
    velocities = parse_range(opts.flag("velocities"), opts["velocities"])
    _kinematic_drive(opts)
    axis = _axis(opts)
    provided = {"drive.velocity": (float(velocities[0]), opts.flag("velocities"))}
    if axis is not None and "." in axis[0]:  # a part field: needs no flag of its own
        provided[axis[0]] = (float(axis[1][0]), axis[2])
    model = opts.model(provided)
    _check_ends(model, "drive.velocity", velocities, opts.flag("velocities"))
    if axis is not None and axis[0] != FREE_AMPLITUDE:
        try:
            model.canonical_name(axis[0])
        except ValueError as error:
            raise CliError(f"{axis[2]}: {error}") from None
        _check_ends(model, *axis)
    overwrite = bool(opts.get("overwrite", False))
    out = plot = None
    if "out" in opts:
        out = check_writable(_output_path(opts, "out", args.config), (".nc",), overwrite=overwrite)
    if "plot" in opts:
        plot = check_writable(
            _output_path(opts, "plot", args.config), PLOT_SUFFIXES, overwrite=overwrite
        )
    if out is not None and plot is not None and _same_file(out, plot):
        raise CliError(f"{opts.flag('out')} and {opts.flag('plot')} name the same file")

    from microslip.analysis.effective_friction import (
        effective_friction_curve,
        effective_friction_map,
    )

    amplitude = opts.get("amplitude")
    with CommandTimer("friction") as timer:
        if axis is None:
            ds = effective_friction_curve(model, velocities, amplitude=amplitude)
        else:
            ds = effective_friction_map(model, velocities, axis[0], axis[1], amplitude=amplitude)
    for line in summary_lines(ds, timer.took()):
        print(line)
    write_outputs(out, plot, overwrite, lambda: ds, lambda tmp: _draw(ds, tmp))
    return 0


def _draw(ds: Any, path: Any, dpi: int = 150) -> None:
    """Draw the curve or map of ``ds`` to ``path`` (its suffix names the format)."""
    from pathlib import Path

    from microslip.plotting.friction import friction_curve_figure, friction_map_figure

    fig = friction_curve_figure(ds) if ds["mu_eff"].ndim == 1 else friction_map_figure(ds)
    try:
        fig.savefig(path, dpi=dpi, format=Path(path).suffix.lstrip("."))
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)


def _unit(ds: Any, name: str) -> str:
    unit = str(ds[name].attrs.get("units", ""))
    return "" if unit in ("", "1") else f" {unit}"


def summary_lines(ds: Any, took: str = "") -> list[str]:
    """A short summary of an effective-friction Dataset: the smallest μ_eff/μ_k, where,
    and where the sliding velocity crosses the critical ṽ = 1; ``took`` how long it took
    (:meth:`~microslip.cli.timing.CommandTimer.took`)."""
    ratio = np.asarray(ds["ratio"].values, dtype=float)
    mu_eff = np.asarray(ds["mu_eff"].values, dtype=float)
    v = np.asarray(ds["velocity"].values, dtype=float)
    took = f" {took}" if took else ""
    dims = list(ds["ratio"].dims)
    other = next((d for d in dims if d != "velocity"), None)
    shape = " x ".join(f"{ds.sizes[d]} {d}" for d in dims)
    lines = [f"mu_eff on {shape} points{took}, v from {v.min():.6g} to {v.max():.6g} m s-1"]
    finite = np.isfinite(ratio)
    if not finite.any():
        return [*lines, "no finite mu_eff (see the warnings)"]
    at = np.unravel_index(np.nanargmin(np.where(finite, ratio, np.nan)), ratio.shape)
    where = f"v = {v[at[dims.index('velocity')]]:.6g} m s-1"
    if other is not None:
        value = float(ds[other].values[at[dims.index(other)]])
        where += f", {other} = {value:.6g}{_unit(ds, other)}"
    lines.append(
        f"min mu_eff/mu_k = {ratio[at]:.6g} (mu_eff = {mu_eff[at]:.6g}) at {where}; "
        f"max mu_eff/mu_k = {np.nanmax(np.where(finite, ratio, np.nan)):.6g}"
    )
    v_tilde = np.asarray(ds["v_tilde"].values, dtype=float)
    if other is None or not np.isfinite(v_tilde).any():
        lines.append(_critical_line(v, v_tilde))
    else:
        below = int((v_tilde < 1.0).sum())
        lines.append(f"v_tilde < 1 (friction reduced) at {below} of {v_tilde.size} points")
    if int((~finite).sum()):
        lines.append(f"{int((~finite).sum())} points without a value (NaN)")
    return lines


def _critical_line(v: np.ndarray, v_tilde: np.ndarray) -> str:
    """Where ṽ crosses 1 along v (log-linear interpolation between the samples)."""
    if not np.isfinite(v_tilde).any():
        return "v_tilde undefined (rigid contact or constant N: mu_eff = mu_k, no stick)"
    crossing = np.flatnonzero(np.diff(np.sign(v_tilde - 1.0)) != 0)
    if crossing.size == 0 or not np.isfinite(v_tilde[crossing[0] : crossing[0] + 2]).all():
        side = "< 1 (friction reduced)" if np.nanmax(v_tilde) < 1.0 else ">= 1"
        return f"v_tilde {side} at every velocity"
    i = int(crossing[0])
    a, b = v_tilde[i] - 1.0, v_tilde[i + 1] - 1.0
    s = a / (a - b) if a != b else 0.0
    if v[i] > 0.0 and v[i + 1] > 0.0:
        critical = float(np.exp(np.log(v[i]) + s * (np.log(v[i + 1]) - np.log(v[i]))))
    else:
        critical = float(v[i] + s * (v[i + 1] - v[i]))
    return f"critical v_tilde = 1 at v = {critical:.6g} m s-1"
