"""The commands info, simulate and figures (map and sweep: :mod:`.sweep_command`).

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
import uuid
from collections.abc import Callable
from pathlib import Path

import numpy as np

from microslip.cli.interrupts import RUN, uninterruptible
from microslip.cli.options import CliError, Options, gather, refuse_underscores
from microslip.cli.timing import CommandTimer

ALL_FIGURES = ("fig2", "fig3", "fig4", "fig5", "fig6", "fig7")
# The extensions' figures (plotting/extensions.py; ``figures --extensions``)
EXTENSION_FIGURES = (
    "forced_response",
    "forced_velocity_map",
    "contact_loss",
    "friction_master_curve",
    "mu_eff_map",
    "spring_stick_slip",
)


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
    model = opts.model()
    table = opts.params.describe()
    if model.friction is not None and model.friction.owns_mu:
        unused = f"(unused: friction {type(model.friction).__name__} has its own coefficients)"
        for key in ("mu", "static_friction_force"):
            table[key] = {**table[key], "description": f"{table[key]['description']} {unused}"}
    parts = _part_table(model)
    if opts.get("json", False):
        print(json.dumps({**table, **parts}, indent=2))
        return 0
    print("microslip model (Grudzinski & Kostek 2005)")
    if any(part is not None for part in model.parts().values()):
        print(f"  parts: {model.describe()}")
    for name, entry in {**table, **parts}.items():
        print(f"  {name:22s} {entry['value']:<14.6g} {entry['unit']:12s} {entry['description']}")
    return 0


def _part_table(model) -> dict[str, dict]:
    """The numeric fields of the model's parts, by dotted name, like Parameters.describe;
    with damping also its coefficient c [N s/m]."""
    from microslip.model.damping import damping_coefficient
    from microslip.model.tangential import MindlinSpring

    out: dict[str, dict] = {}
    for slot, part in model.parts().items():
        if part is None:
            continue
        for name in part.field_names():
            out[f"{slot}.{name}"] = {
                "value": getattr(part, name),
                "unit": part.field_unit(name),
                "description": f"{type(part).__name__}: {part.field_description(name)}",
            }
    if model.damping is not None:
        out["damping.coefficient"] = {
            "value": damping_coefficient(model.params, model.damping.ratio),
            "unit": "N s m-1",
            "description": "damping coefficient c = 2 zeta sqrt(K_n m)",
        }
    if isinstance(model.tangential, MindlinSpring):
        out["tangential.stiffness_at_y0"] = {
            "value": model.tangential.ratio * model.params.contact_stiffness,
            "unit": "N m-1",
            "description": "tangential stiffness k_t = lambda K_n at the static deflection",
        }
    return out


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
        check_writable,
    )
    from microslip.simulation import DEFAULT_RTOL

    opts = gather(args, "simulate")
    params = opts.params
    model = opts.model()  # every part checked before anything runs
    force = _simulate_force(opts, model)
    if "duration" not in opts:
        raise CliError("--duration is required (flag or [simulate] in --config)")
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
    if "amplitude" not in opts and initial_state is None and model.excitation is None:
        raise CliError("give --amplitude or --initial-state (a forced model starts from rest)")
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
    with CommandTimer("simulate") as timer:
        result = ms.simulate(
            model,
            force=force,
            duration=duration,
            amplitude=opts.get("amplitude"),
            initial_state=initial_state,
            method=method,
            dt=opts.get("dt"),
            rtol=opts.get("rtol"),
            atol=opts.get("atol"),
            t_eval=t_eval,
            save_every=save_every,
            allow_large=allow_large,
        )
    kinds = [k for _, k in result.events]
    # the slider's own displacement over the run: x(0) need not be 0 (--initial-state)
    span = float(result.t[-1])
    mean_v = (result.x[-1] - result.x[0]) / span if span > 0 else float("nan")
    print(
        f"simulated {span:.6g} s with {result.method} {timer.took(3)}: "
        f"x = {result.x[-1]:.6e} m, mean velocity (x(T)-x(0))/T = {mean_v:.6e} m/s, "
        f"{kinds.count('slip_start')} slip starts, {kinds.count('stick_start')} sticks, "
        f"{kinds.count('contact_lost')} losses of contact, {result.t.size} samples"
    )
    if thinned:  # after the run: a refused run must print one line only
        _note(
            f"output thinned to 1 step in {save_every} ({result.t.size} samples); "
            "choose with --samples or --save-every"
        )
    from microslip.plotting.trajectory import write_trajectory_plot

    write_outputs(
        out, plot, overwrite, result.to_xarray, lambda tmp: write_trajectory_plot(result, tmp)
    )
    return 0


def _simulate_force(opts: Options, model) -> float | None:
    """``--force`` [N]: required without a drive, refused with one (the drive sets the
    tangential loading; :meth:`microslip.Model.resolve_force`)."""
    if model.drive is None:
        if "force" not in opts:
            raise CliError(
                "--force is required (flag or [simulate] in --config), or give a tangential "
                "--drive {constant-force,harmonic,spring,prescribed-velocity}"
            )
        return opts["force"]
    if "force" in opts:
        drive = opts.parts["drive"]
        hint = " (its force is --drive-force)" if drive.kind == "constant-force" else ""
        raise CliError(
            f"{opts.flag('force')} cannot be combined with drive {drive.kind} "
            f"({drive.kind_origin}): the drive sets the tangential loading{hint}; remove "
            f"{opts.flag('force')}"
        )
    return None


def write_outputs(
    out: Path | None,
    plot: Path | None,
    overwrite: bool,
    dataset: Callable[[], object],
    draw: Callable[[Path], None],
) -> None:
    """Write the NetCDF ``out`` (of ``dataset()``, built only when asked for) and the
    figure ``plot`` (``draw(path)``) as one batch: both land, or neither; print each."""
    from microslip.io.output import OutputBatch, write_dataset

    with OutputBatch(overwrite=overwrite) as batch:
        if out is not None:
            data = dataset()
            batch.write(out, lambda tmp: write_dataset(data, tmp, overwrite=False))
        if plot is not None:
            batch.write(plot, draw)
        for path in _commit(batch):
            print(f"wrote {path}")


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
    extensions = bool(opts.get("extensions", False))
    known = EXTENSION_FIGURES if extensions else ALL_FIGURES
    only = opts.get("only")
    names = known if only is None else tuple(n.strip() for n in only.split(","))
    for name in names:
        if name not in known:
            which = " of --extensions" if extensions else ""
            raise CliError(
                f"{opts.flag('only')}: unknown figure {name!r}{which}; known: {', '.join(known)}"
            )
    dpi = opts.get("dpi", 150)
    if not 10 <= dpi <= 2400:
        raise CliError(f"{opts.flag('dpi')} must be an integer in [10, 2400], got {dpi!r}")
    check_drawable(opts.params, names)  # μ = 0 and Figs. 4–7: refused before computing
    overwrite = bool(opts.get("overwrite", False))
    default_dir = Path("figures", "ext") if extensions else Path("figures")
    out_dir = _output_path(opts, "out", args.config) if "out" in opts else default_dir
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
    timer = CommandTimer("figures", quiet=quiet)
    work = out_dir / f".figures.{uuid.uuid4().hex[:8]}.partial"
    try:
        with timer, batch:
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
    print(f"wrote {len(written)} files to {out_dir} {timer.took(1)}")
    return written


def _remove_empty(directories: list[Path]) -> None:
    """Remove the directories this run created, deepest first, if they are still empty."""
    for directory in reversed(directories):
        try:
            directory.rmdir()
        except OSError:
            return
