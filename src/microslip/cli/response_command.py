"""``microslip response``: the forced-response curve of the normal motion.

The branch of periodic orbits (:func:`microslip.analysis.forced_response.forced_response`)
from the orbit reached from rest at the first value of ``--frequencies F1:F2`` [Hz] (or
``--amplitudes A1:A2``, the excitation amplitude in N or m) to the second, through
folds; written to NetCDF (``--out``) and drawn (``--plot``). Like every command, it
checks everything (the model, both ends of the range, the outputs) before computing.
"""

from __future__ import annotations

import argparse

import numpy as np

from microslip.cli.commands import _output_path, _same_file, write_outputs
from microslip.cli.model_options import require_paper_tangential
from microslip.cli.options import CliError, Options, gather, refuse_underscores
from microslip.cli.timing import CommandTimer

__all__ = ["cmd_response", "parse_pair", "summary_lines"]


def parse_pair(name: str, text: str) -> tuple[float, float]:
    """``"START:END"`` as two distinct finite floats (``CliError`` naming ``name``)."""
    refuse_underscores(name, text)
    parts = str(text).split(":")
    if len(parts) != 2:
        raise CliError(f"{name}: expected START:END, got {text!r}")
    try:
        start, end = (float(p) for p in parts)
    except ValueError:
        raise CliError(f"{name}: expected START:END with two numbers, got {text!r}") from None
    if not (np.isfinite(start) and np.isfinite(end)):
        raise CliError(f"{name}: START and END must be finite, got {text!r}")
    if start == end:
        raise CliError(f"{name}: START and END must differ, got {text!r}")
    return start, end


def _range(opts: Options) -> tuple[str, str, tuple[float, float]]:
    """(option, dotted field, (start, end)) of the continuation parameter."""
    opts.refuse_together("frequencies", "amplitudes", "continue in one parameter at a time")
    if "amplitudes" in opts:
        name, dotted = "amplitudes", "excitation.amplitude"
    elif "frequencies" in opts:
        name, dotted = "frequencies", "excitation.frequency"
    else:
        raise CliError("give --frequencies F1:F2 [Hz] or --amplitudes A1:A2 (flag or [response])")
    return name, dotted, parse_pair(opts.flag(name), opts[name])


def cmd_response(args: argparse.Namespace) -> int:
    from microslip.io.output import PLOT_SUFFIXES, check_writable

    opts = gather(args, "response")
    if opts.parts["excitation"].kind == "none":
        raise CliError(
            "response needs a normal excitation: give --excitation "
            "{harmonic-force,base-motion,prescribed-penetration} (or [excitation] in --config); "
            "a free vibration has no forced response"
        )
    name, dotted, (start, end) = _range(opts)
    model = opts.model({dotted: (start, opts.flag(name))})
    require_paper_tangential(
        model, opts.parts, "response",
        instead="the forced response is that of the normal motion, which the tangential "
        "parts do not change: leave them out",
    )  # fmt: skip
    try:  # both ends within the supported range of the field, before computing
        model.replace(**{dotted: end})
    except ValueError as error:
        raise CliError(f"{opts.flag(name)} END: {error}") from None
    from microslip.analysis.forced_response import MAX_POINTS_LIMIT, forced_response

    max_points = opts.get("max_points")
    if max_points is not None and not 2 <= max_points <= MAX_POINTS_LIMIT:
        raise CliError(
            f"{opts.flag('max_points')} must be an integer in [2, {MAX_POINTS_LIMIT}], "
            f"got {max_points!r}"
        )
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

    kwargs = {} if max_points is None else {"max_points": max_points}
    with CommandTimer("response") as timer:
        ds = forced_response(model, **{name: (start, end)}, **kwargs)
    for line in summary_lines(ds, name, timer.took()):
        print(line)
    from microslip.plotting.response import write_response_plot

    write_outputs(out, plot, overwrite, lambda: ds, lambda tmp: write_response_plot(ds, tmp))
    return 0


def _spans(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) index of each run of True in ``mask``."""
    edges = np.diff(np.r_[0, mask.astype(np.int8), 0])
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1, strict=True))


def summary_lines(ds, name: str = "frequencies", took: str = "") -> list[str]:
    """A short summary of a forced-response Dataset: points, folds, contact loss; ``took``
    how long it took (:meth:`~microslip.cli.timing.CommandTimer.took`)."""
    from microslip.plotting.response import fold_indices

    variable, unit = ("frequency", "Hz") if name == "frequencies" else ("excitation_amplitude", "")
    unit = ds[variable].attrs.get("units", unit)
    values = np.asarray(ds[variable].values, dtype=float)
    stable = np.asarray(ds["stable"].values, dtype=bool)
    took = f" {took}" if took else ""
    lines = [
        f"{values.size} branch points{took}, {variable} from {values[0]:.6g} to "
        f"{values[-1]:.6g} {unit}; {int(stable.sum())} stable, {int((~stable).sum())} unstable; "
        f"amplitude at the end {float(ds['amplitude'].values[-1]):.6e} m"
    ]
    folds = fold_indices(ds)
    if folds:
        at = ", ".join(f"{values[i]:.6g}" for i in folds)
        lines.append(f"{len(folds)} folds at {variable} = {at} {unit}")
    else:
        lines.append("no folds")
    lost = np.asarray(ds["contact_lost"].values, dtype=bool)
    if lost.any():
        ranges = ", ".join(f"{values[a]:.6g} to {values[b]:.6g}" for a, b in _spans(lost))
        lines.append(f"contact lost at {int(lost.sum())} points: {variable} {ranges} {unit}")
    else:
        lines.append("contact kept at every point")
    if "period_doubling" in ds and bool(np.asarray(ds["period_doubling"].values).any()):
        doubling = np.asarray(ds["period_doubling"].values, dtype=bool)
        lines.append(
            f"period doubling at {int(doubling.sum())} points (continued as unstable period-1)"
        )
    return lines
