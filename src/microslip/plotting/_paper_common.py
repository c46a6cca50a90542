"""Data and drawing helpers shared by the paper's Figs. 2–6.

See :mod:`microslip.plotting.paper` for the layout and sign conventions; the units of
every axis come from :func:`microslip.plotting.scales.figure_scales`.
"""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")  # no display; figures are built with matplotlib.figure.Figure

import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from microslip.analysis.steady_state import stick_slip_cycle
from microslip.model.parameters import Parameters
from microslip.plotting.scales import (
    FigureScales,
    figure_scales,
    require_friction,
)
from microslip.results import FLIGHT, SLIP, STATE_MEANINGS, STICK, SimulationResult
from microslip.simulation import simulate

FIG6_AMPLITUDE_RATIO = 1.3  # A / y0 of the loss-of-contact example (Fig. 6)
# Time windows of Figs. 4, 5, 6 for the paper's data [s]; other data: times T0 / T0(paper).
FIG4_DURATION, FIG5_DURATION, FIG6_DURATION = 5e-3, 3e-3, 5e-3

# Axis quantities; their units come from figure_scales (the paper's for its data).
_QUANTITIES = {
    "t": "$t$",
    "y": "$y$",
    "ydot": r"$\dot y$",
    "yddot": r"$\ddot y$",
    "R": "$|R|$",
    "Ft": "$|F_t|$, $F$",
    "x": "$x$",
    "xdot": r"$\dot x$",
    "xddot": r"$\ddot x$",
}

COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:red")
STICK_SHADE = {"color": "0.85", "alpha": 0.6, "lw": 0}
FLIGHT_SHADE = {"color": "tab:red", "alpha": 0.12, "lw": 0}


# -- data helpers ----------------------------------------------------------------------


def _var(dims, values, units: str, long_name: str, **attrs):
    return (dims, np.asarray(values), {"units": units, "long_name": long_name, **attrs})


def _time_coord(t: np.ndarray):
    return ("time", t, {"units": "s", "long_name": "time"})


def _amplitude_coord(amplitudes: Sequence[float]):
    return (
        "amplitude",
        np.asarray(amplitudes, dtype=float),
        {"units": "m", "long_name": "normal vibration amplitude A = y0 - y_min"},
    )


def _common_attrs(params: Parameters, figure: str, caption: str) -> dict:
    return {
        "title": f"Grudzinski & Kostek (2005), {figure}, recomputed with microslip",
        "caption": caption,
        "static_deflection_m": params.static_deflection,
        "natural_frequency_Hz": params.natural_frequency,
        **{f"param_{k}": v for k, v in params.to_dict().items()},
    }


def _cycle_dataset(
    params: Parameters,
    force: float,
    variables: dict,
    t: np.ndarray,
    ratios: Sequence[float],
    figure: str,
    caption: str,
) -> xr.Dataset:
    """Dataset of Figs. 4–5: ``variables`` on (time, amplitude) plus, per amplitude A =
    ratio·y0, A/y0 and the steady slip distance per normal period [m] and mean velocity
    [m/s] under ``force`` [N]."""
    amplitudes = [r * params.static_deflection for r in ratios]
    distance, velocity = _cycle_summary(params, force, amplitudes)
    variables = {
        **variables,
        "amplitude_ratio": _var("amplitude", np.asarray(ratios), "1", "A / y0"),
        "slip_distance": _var(
            "amplitude", distance, "m", "steady slip distance per normal period (Delta x)"
        ),
        "mean_velocity": _var("amplitude", velocity, "m s-1", "steady mean sliding velocity"),
    }
    return xr.Dataset(
        variables,
        coords={"time": _time_coord(t), "amplitude": _amplitude_coord(amplitudes)},
        attrs=_common_attrs(params, figure, caption),
    )


def _trajectories(
    params: Parameters,
    force: float,
    amplitudes: Sequence[float],
    duration: float,
    samples: int,
) -> tuple[np.ndarray, list[SimulationResult]]:
    """Simulate each amplitude on one common time grid [s].

    The grid is ``samples`` uniform points plus every switching instant of every run, so
    the corners of stick, slip and loss of contact are drawn exactly (the sample at a
    switching instant holds the state just after the switch).
    """
    grid = [np.linspace(0.0, duration, samples)]
    for amplitude in amplitudes:
        first = simulate(params, force=force, amplitude=amplitude, duration=duration)
        grid.append(first.event_t)
    t = np.unique(np.clip(np.concatenate(grid), 0.0, duration))
    runs = [
        simulate(params, force=force, amplitude=a, duration=duration, method="event", t_eval=t)
        for a in amplitudes
    ]
    return t, runs


def _stack(runs: Sequence[SimulationResult], name: str) -> np.ndarray:
    return np.stack([np.asarray(getattr(r, name)) for r in runs])


def _motion_variables(
    params: Parameters, force: float, runs: Sequence[SimulationResult], *, stacked: bool = True
) -> dict[str, tuple]:
    """Variables of forced runs (Figs. 4–6): on (amplitude, time), or on time for one run."""
    dims = ("amplitude", "time") if stacked else ("time",)

    def get(name: str) -> np.ndarray:
        return _stack(runs, name) if stacked else np.asarray(getattr(runs[0], name))

    r_abs = get("R")
    return {
        "y": _var(dims, get("y"), "m", "normal displacement (penetration > 0)"),
        "ydot": _var(dims, get("ydot"), "m s-1", "normal velocity"),
        "yddot": _var(
            dims, params.g - r_abs / params.mass, "m s-2", "normal acceleration g - |R|/m"
        ),
        "R": _var(dims, r_abs, "N", "compressive normal reaction |R| (eq. 2.3)"),
        "Ft": _var(dims, get("Ft"), "N", "friction force on the slider, signed as in eq. 2.5"),
        "friction_limit": _var(
            dims, params.mu * r_abs, "N", "potential static friction force mu |R|"
        ),
        "x": _var(dims, get("x"), "m", "tangential displacement"),
        "xdot": _var(dims, get("xdot"), "m s-1", "tangential velocity"),
        "xddot": _var(dims, get("xddot"), "m s-2", "tangential acceleration"),
        "state": _var(
            dims,
            get("state").astype(np.int8),
            "1",
            "contact state",
            flag_values=np.array([STICK, SLIP, FLIGHT], dtype=np.int8),
            flag_meanings=STATE_MEANINGS,
        ),
        "force": _var((), force, "N", "constant tangential drive F"),
    }


def _cycle_summary(params: Parameters, force: float, amplitudes: Sequence[float]):
    """Steady stick–slip cycle per amplitude: (slip distance [m], mean velocity [m/s])."""
    distance, velocity = [], []
    for amplitude in amplitudes:
        try:
            cycle = stick_slip_cycle(params, force=force, amplitude=amplitude)
        except ValueError:  # F > mu m g: no steady cycle
            distance.append(np.nan)
            velocity.append(np.inf)
            continue
        distance.append(cycle.slip_distance)
        velocity.append(cycle.mean_velocity)
    return np.asarray(distance), np.asarray(velocity)


# -- drawing helpers -------------------------------------------------------------------


def _amplitude_label(ratio: float) -> str:
    for value, text in ((0.0, "0"), (1 / 3, "y_0/3"), (2 / 3, "2y_0/3"), (1.0, "y_0")):
        if abs(ratio - value) < 1e-9:
            return f"$A = {text}$"
    return f"$A = {ratio:.3g}\\,y_0$"


def _label(u: FigureScales, name: str) -> str:
    """Axis label of a quantity with its plotted unit, e.g. "$t$ [ms]"."""
    return getattr(u, name).label(_QUANTITIES[name])


def _force_text(u: FigureScales, force: float) -> str:
    """A force [N] in the plotted force unit, e.g. "0.5 N"."""
    return f"{force * u.Ft.factor:g} {u.Ft.symbol}"


def _panel(ax: Axes, letter: str, text: str = "") -> None:
    ax.set_title(f"({letter}) {text}".rstrip(), loc="left", fontsize="medium")


def _shade(ax: Axes, t_ms: np.ndarray, mask: np.ndarray, style: dict, label=None) -> None:
    if np.any(mask):
        ax.fill_between(
            t_ms, 0, 1, where=mask, transform=ax.get_xaxis_transform(), label=label, **style
        )


def _dilate(mask: np.ndarray) -> np.ndarray:
    """The mask grown by one sample each way (so masked curves meet their neighbours)."""
    grown = mask.copy()
    grown[1:] |= mask[:-1]
    grown[:-1] |= mask[1:]
    return grown


def _masked(values: np.ndarray, mask: np.ndarray) -> np.ndarray:
    return np.where(mask, values, np.nan)


def _friction_panel(
    ax: Axes, t_ms, run: SimulationResult, color: str, force: float, u: FigureScales
) -> None:
    """Real friction |F_t| (thick), potential static friction μ|R| while sticking (thin), F."""
    stick = run.state == STICK
    scale = u.Ft.factor
    ax.plot(t_ms, np.abs(run.Ft) * scale, color=color, lw=1.8, label="real friction $|F_t|$")
    ax.plot(
        t_ms,
        _masked(run.friction_limit * scale, _dilate(stick)),
        color="k",
        lw=0.7,
        label=r"potential static friction $\mu|R|$ (stick)",
    )
    ax.axhline(
        force * scale, color="k", ls="--", lw=1.0, label=f"drive $F$ = {_force_text(u, force)}"
    )


def _drive(
    params: Parameters,
    force: float | None,
    duration: float | None,
    paper_duration: float,
    figure: str,
) -> tuple[FigureScales, float, float]:
    """Scales, drive F [N] and time window [s] of Figs. 4–6 for ``params``.

    By default F = 0.5 N and the window are the paper's, scaled by μ m g and T0 (see
    :mod:`microslip.plotting.scales`); FigureNotDrawable for μ = 0, where that F is 0.
    """
    u = figure_scales(params)
    if force is None:
        require_friction(params, figure)
        force = u.drive
    if duration is None:
        duration = paper_duration * u.time_ratio
    return u, float(force), float(duration)


def _new_figure(size: tuple[float, float]) -> Figure:
    return Figure(figsize=size, layout="constrained")
