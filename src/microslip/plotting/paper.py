"""Figures 2–6 of Grudziński & Kostek (2005), redrawn from the model, with their data.

Each ``figureN(params)`` returns a :class:`matplotlib.figure.Figure` (Agg canvas, no
pyplot state) and the :class:`xarray.Dataset` behind it (SI units, every variable and
coordinate with a ``units`` attribute). :func:`write_paper_figures` writes them as
``figN.png`` and ``figN.nc``, each file atomically.

Sign conventions follow :class:`microslip.SimulationResult`: y > 0 is penetration (the
slider's descent), |R| is the compressive reaction, and F_t is signed as in (2.5), so
the friction force opposing forward sliding is negative; the plots show its magnitude
|F_t| against the drive F as the paper does. The data are stored in SI units; the
plots use scaled units (µm, ms, mm/s, …) that are written on every axis.

Layout (panel letters as in the paper's captions and text):

- Fig. 2: (a) load–deflection characteristic |R|(y) with the working point C and the
  range each vibration covers; (b) y(t), (c) ẏ(t) of the free vibrations with
  A = y0/3, 2y0/3, y0; (d) their phase portraits.
- Fig. 3: the largest contact-keeping free vibration, A = y0: (a) y(t), (b) |R|(t) and
  F_t = μ|R|(t), from 0 to 3 m g.
- Fig. 4: F = 0.5 N, columns 1–4 for A = 0, y0/3, 2y0/3, y0; rows (a) y, (b) ẏ, (c) ÿ,
  (d) |R|, (e) friction against F (columns 1–4), (f) x, (g) ẋ, (h) ẍ (columns 1′–4′).
- Fig. 5: the two largest amplitudes of Fig. 4: (a), (b) F and the friction force
  against t (thin: potential static friction μ|R| while sticking); (c) friction against
  ẋ while sliding; (d), (e) ẋ(t); (f) the x–ẋ phase plane while sliding, x counted
  from each release so that the steady cycles fall on one limit-cycle arch.
- Fig. 6: A = 1.3 y0 (momentary loss of contact), F = 0.5 N: (a) y, (b) ẏ, (c) phase
  portrait, (d) |R|, (e) friction against F, (f) x, (g) ẋ, (h) ẍ.
"""

from __future__ import annotations

import numbers
from collections.abc import Callable, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # no display; figures are built with matplotlib.figure.Figure

import numpy as np
import xarray as xr
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from microslip.analysis.free_vibration import free_period, turning_points
from microslip.analysis.steady_state import stick_slip_cycle
from microslip.io.output import write_atomically, write_dataset
from microslip.model.contact import reaction_array
from microslip.model.parameters import Parameters
from microslip.results import FLIGHT, SLIP, STATE_MEANINGS, STICK, SimulationResult
from microslip.simulation import simulate

__all__ = [
    "FIGURES",
    "PAPER_FORCE",
    "figure2",
    "figure3",
    "figure4",
    "figure5",
    "figure6",
    "write_paper_figures",
]

PAPER_FORCE = 0.5  # tangential drive of Sec. 4 and Figs. 4–6 [N]
FIG6_AMPLITUDE_RATIO = 1.3  # A / y0 of the loss-of-contact example (Fig. 6)

# Plot scales: SI value times factor gives the plotted number.
MS, UM, NM = 1e3, 1e6, 1e9  # s -> ms, m -> µm, m -> nm
MM_S, UM_S = 1e3, 1e6  # m/s -> mm/s, m/s -> µm/s

T_LABEL = "$t$ [ms]"
Y_LABEL = "$y$ [µm]"
YDOT_LABEL = r"$\dot y$ [mm/s]"
YDDOT_LABEL = r"$\ddot y$ [m/s$^2$]"
R_LABEL = "$|R|$ [N]"
FT_LABEL = "$|F_t|$, $F$ [N]"
X_LABEL = "$x$ [nm]"
XDOT_LABEL = r"$\dot x$ [µm/s]"
XDDOT_LABEL = r"$\ddot x$ [m/s$^2$]"

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


def _friction_panel(ax: Axes, t_ms, run: SimulationResult, color: str, force: float) -> None:
    """Real friction |F_t| (thick), potential static friction μ|R| while sticking (thin), F."""
    stick = run.state == STICK
    ax.plot(t_ms, np.abs(run.Ft), color=color, lw=1.8, label="real friction $|F_t|$")
    ax.plot(
        t_ms,
        _masked(run.friction_limit, _dilate(stick)),
        color="k",
        lw=0.7,
        label=r"potential static friction $\mu|R|$ (stick)",
    )
    ax.axhline(force, color="k", ls="--", lw=1.0, label=f"drive $F = {force:g}$ N")


def _new_figure(size: tuple[float, float]) -> Figure:
    return Figure(figsize=size, layout="constrained")


# -- Fig. 2 ----------------------------------------------------------------------------


def figure2(params: Parameters | None = None) -> tuple[Figure, xr.Dataset]:
    """Load–deflection characteristic and free normal micro-vibrations (paper Fig. 2)."""
    params = Parameters() if params is None else params
    y0 = params.static_deflection
    weight = params.mass * params.g
    ratios = (1 / 3, 2 / 3, 1.0)
    amplitudes = [r * y0 for r in ratios]
    periods = np.array([free_period(params, a) for a in amplitudes])
    duration = 3.2 * float(periods.max())
    t, runs = _trajectories(params, 0.0, amplitudes, duration, 3001)
    turning = np.array([turning_points(params, a) for a in amplitudes])

    y_char = np.linspace(-0.15 * y0, 1.9 * y0, 801)
    r_char = reaction_array(params, y_char)
    stiffness = params.contact_stiffness

    ds = xr.Dataset(
        {
            "y": _var(("amplitude", "time"), _stack(runs, "y"), "m", "normal displacement"),
            "ydot": _var(("amplitude", "time"), _stack(runs, "ydot"), "m s-1", "normal velocity"),
            "R": _var(
                ("amplitude", "time"), _stack(runs, "R"), "N", "compressive normal reaction |R|"
            ),
            "period": _var("amplitude", periods, "s", "free vibration period T(A)"),
            "frequency": _var("amplitude", 1.0 / periods, "Hz", "free vibration frequency"),
            "y_min": _var("amplitude", turning[:, 0], "m", "highest point (turning point)"),
            "y_max": _var("amplitude", turning[:, 1], "m", "lowest point (turning point)"),
            "amplitude_ratio": _var("amplitude", np.asarray(ratios), "1", "A / y0"),
            "R_characteristic": _var(
                "deflection", r_char, "N", "load-deflection characteristic |R|(y), eq. 2.3"
            ),
            "working_point_y": _var((), y0, "m", "working point C: static deflection y0"),
            "working_point_R": _var((), weight, "N", "working point C: load m g"),
            "contact_stiffness": _var((), stiffness, "N m-1", "contact stiffness K_n at C"),
            "natural_frequency": _var((), params.natural_frequency, "Hz", "f0 at C"),
        },
        coords={
            "time": _time_coord(t),
            "amplitude": _amplitude_coord(amplitudes),
            "deflection": ("deflection", y_char, {"units": "m", "long_name": "deflection y"}),
        },
        attrs=_common_attrs(
            params,
            "Fig. 2",
            "Load-deflection characteristic (a) and free normal contact micro-vibrations "
            "versus time (b, c) and on the phase plane (d) for three amplitudes",
        ),
    )

    fig = _new_figure((11.0, 8.0))
    (ax_a, ax_b), (ax_c, ax_d) = fig.subplots(2, 2)
    t_ms = t * MS

    # (a) characteristic with C, its tangent, and the range of each vibration.
    ax_a.plot(y_char * UM, r_char, color="k", lw=1.5, label="$|R| = S c_n y^{m_2}$")
    y_tan = np.linspace(0.35 * y0, 1.65 * y0, 2)
    ax_a.plot(
        y_tan * UM,
        weight + stiffness * (y_tan - y0),
        color="0.5",
        ls=":",
        lw=1.2,
        label=f"tangent at C, $K_n$ = {stiffness * 1e-6:.3g} N/µm",
    )
    for k, ratio in enumerate(ratios):
        lo, hi = turning[k]
        ax_a.plot(
            np.array([lo, hi]) * UM,
            reaction_array(params, np.array([lo, hi])),
            "o",
            color=COLORS[k],
            ms=6,
            label=f"{_amplitude_label(ratio)}: $|R|$ from "
            f"{reaction_array(params, lo):.3g} to {reaction_array(params, hi):.3g} N",
        )
    ax_a.plot([y0 * UM], [weight], "s", color="k", ms=8)
    ax_a.annotate(
        f"C ($y_0$ = {y0 * UM:.3f} µm, $mg$ = {weight:.3g} N)",
        (y0 * UM, weight),
        xytext=(-10, 22),
        textcoords="offset points",
        ha="right",
        arrowprops={"arrowstyle": "-", "color": "k", "lw": 0.8},
    )
    ax_a.vlines(y0 * UM, 0, weight, color="k", lw=0.6, ls="--")
    ax_a.hlines(weight, y_char[0] * UM, y0 * UM, color="k", lw=0.6, ls="--")
    ax_a.set_xlim(y_char[0] * UM, y_char[-1] * UM)
    ax_a.set_ylim(0, None)
    ax_a.set_xlabel("deflection $y$ [µm]")
    ax_a.set_ylabel("load $|R|$ [N]")
    ax_a.legend(fontsize="small", loc="upper left")
    _panel(ax_a, "a", "load–deflection characteristic")

    for k, (ratio, run) in enumerate(zip(ratios, runs, strict=True)):
        label = f"{_amplitude_label(ratio)}, $f$ = {1 / periods[k]:.0f} Hz"
        ax_b.plot(t_ms, run.y * UM, color=COLORS[k], label=label)
        ax_c.plot(t_ms, run.ydot * MM_S, color=COLORS[k], label=label)
        one = t <= periods[k]
        ax_d.plot(run.y[one] * UM, run.ydot[one] * MM_S, color=COLORS[k], label=label)
    for ax in (ax_b, ax_c):
        ax.set_xlim(0, t_ms[-1])
        ax.set_xlabel(T_LABEL)
    ax_b.axhline(y0 * UM, color="k", ls="--", lw=0.8, label="$y_0$ (static equilibrium)")
    ax_b.axhline(0.0, color="0.4", lw=0.6)
    ax_c.axhline(0.0, color="0.4", lw=0.6)
    ax_b.set_ylabel(Y_LABEL + " (penetration)")
    ax_c.set_ylabel(YDOT_LABEL)
    ax_b.set_ylim(-0.03 * y0 * UM, 2.25 * y0 * UM)
    ax_b.legend(fontsize="small", loc="upper center", ncols=2)
    _panel(ax_b, "b", "free vibration $y(t)$")
    _panel(ax_c, "c", r"free vibration $\dot y(t)$")
    ax_d.plot([y0 * UM], [0.0], "s", color="k", ms=6)
    ax_d.annotate("C", (y0 * UM, 0.0), xytext=(5, 5), textcoords="offset points")
    ax_d.axvline(0.0, color="0.4", lw=0.6)
    ax_d.axhline(0.0, color="0.4", lw=0.6)
    ax_d.set_xlabel(Y_LABEL)
    ax_d.set_ylabel(YDOT_LABEL)
    _panel(ax_d, "d", "phase portraits")
    fig.suptitle(
        f"Fig. 2 — free normal contact micro-vibrations ($f_0$ = {params.natural_frequency:.0f} Hz)"
    )
    return fig, ds


# -- Fig. 3 ----------------------------------------------------------------------------


def figure3(params: Parameters | None = None) -> tuple[Figure, xr.Dataset]:
    """Largest contact-keeping free vibration A = y0 and its contact forces (paper Fig. 3)."""
    params = Parameters() if params is None else params
    y0 = params.static_deflection
    weight = params.mass * params.g
    period = free_period(params, y0)
    t, (run,) = _trajectories(params, 0.0, [y0], 3.0 * period, 3001)
    r_abs = run.R
    friction = params.mu * r_abs
    ds = xr.Dataset(
        {
            "y": _var("time", run.y, "m", "normal displacement (penetration > 0)"),
            "ydot": _var("time", run.ydot, "m s-1", "normal velocity"),
            "R": _var("time", r_abs, "N", "compressive normal reaction |R|"),
            "Ft": _var("time", friction, "N", "friction force F_t = mu |R| (Fig. 3b)"),
            "amplitude": _var((), y0, "m", "normal vibration amplitude A = y0"),
            "period": _var((), period, "s", "free vibration period T(A)"),
            "weight": _var((), weight, "N", "static reaction m g"),
        },
        coords={"time": _time_coord(t)},
        attrs=_common_attrs(
            params,
            "Fig. 3",
            "Normal contact vibration (a) and contact forces (b) as functions of time, A = y0",
        ),
    )

    fig = _new_figure((8.5, 6.5))
    ax_a, ax_b = fig.subplots(2, 1, sharex=True)
    t_ms = t * MS
    ax_a.plot(t_ms, run.y * UM, color="tab:blue", label="$y(t)$")
    ax_a.axhline(y0 * UM, color="k", ls="--", lw=0.8, label="$y_0$ (static equilibrium)")
    ax_a.axhline(0.0, color="tab:red", ls=":", lw=1.0, label="$y = 0$ (edge of contact)")
    ax_a.set_ylabel(Y_LABEL + " (penetration)")
    ax_a.set_ylim(-0.05 * y0 * UM, 2.2 * y0 * UM)
    ax_a.legend(fontsize="small", loc="upper center", ncols=3)
    _panel(ax_a, "a", f"normal vibration, $A = y_0$ = {y0 * UM:.3f} µm")

    ax_b.plot(t_ms, r_abs, color="tab:blue", lw=1.6, label="normal reaction $|R|$")
    ax_b.plot(
        t_ms, friction, color="tab:orange", lw=1.6, label=rf"$F_t = \mu|R|$ ($\mu$ = {params.mu:g})"
    )
    ax_b.axhline(weight, color="k", ls="--", lw=0.8, label=f"$mg$ = {weight:.3g} N (mean of $|R|$)")
    ax_b.axhline(3 * weight, color="0.5", ls=":", lw=0.8, label="$3mg$")
    ax_b.set_ylabel("force [N]")
    ax_b.set_xlabel(T_LABEL)
    ax_b.set_xlim(0, t_ms[-1])
    ax_b.set_ylim(-0.5, 3.9 * weight)
    ax_b.legend(fontsize="small", loc="upper center", ncols=4)
    _panel(
        ax_b,
        "b",
        f"contact forces: $|R|$ from {r_abs.min():.2g} to {r_abs.max():.4g} N "
        f"({r_abs.max() / weight:.3f} $mg$)",
    )
    fig.suptitle("Fig. 3 — largest free vibration without loss of contact")
    return fig, ds


# -- Fig. 4 ----------------------------------------------------------------------------


def figure4(
    params: Parameters | None = None, *, force: float = PAPER_FORCE, duration: float = 5e-3
) -> tuple[Figure, xr.Dataset]:
    """Stick–slip under F = 0.5 N for A = 0, y0/3, 2y0/3, y0 (paper Fig. 4)."""
    params = Parameters() if params is None else params
    y0 = params.static_deflection
    ratios = (0.0, 1 / 3, 2 / 3, 1.0)
    amplitudes = [r * y0 for r in ratios]
    t, runs = _trajectories(params, force, amplitudes, duration, 5001)
    variables = _motion_variables(params, force, runs)
    caption = (
        "Normal micro-vibrations with amplitudes A = 0, y0/3, 2y0/3, y0 and their "
        f"influence on R, F_t and x, xdot, xddot under F = {force:g} N"
    )
    ds = _cycle_dataset(params, force, variables, t, ratios, "Fig. 4", caption)
    distance, velocity = ds["slip_distance"].values, ds["mean_velocity"].values

    fig = _new_figure((14.0, 17.0))
    axes = fig.subplots(8, 4, sharex=True)
    t_ms = t * MS
    rows = "abcdefgh"
    for j, (ratio, run) in enumerate(zip(ratios, runs, strict=True)):
        col = axes[:, j]
        color = COLORS[j]
        stick = run.state == STICK
        col[0].plot(t_ms, run.y * UM, color=color)
        col[0].axhline(y0 * UM, color="k", ls="--", lw=0.6)
        col[1].plot(t_ms, run.ydot * MM_S, color=color)
        col[2].plot(t_ms, params.g - run.R / params.mass, color=color)
        col[3].plot(t_ms, run.R, color=color)
        col[3].axhline(params.mass * params.g, color="k", ls="--", lw=0.6)
        _friction_panel(col[4], t_ms, run, color, force)
        col[5].plot(t_ms, run.x * NM, color=color)
        col[6].plot(t_ms, run.xdot * UM_S, color=color)
        col[7].plot(t_ms, run.xddot, color=color)
        for ax in col[4:]:
            _shade(ax, t_ms, stick, STICK_SHADE)
        if np.isfinite(velocity[j]) and distance[j] > 0:
            note = (
                rf"$\Delta x$ = {distance[j] * NM:.3g} nm/cycle" + "\n"
                rf"$\bar v$ = {velocity[j] * UM_S:.3g} µm/s"
            )
        elif velocity[j] == 0:
            note = "no sliding"
        else:
            note = ""
        if note:
            col[5].text(
                0.97, 0.06, note, transform=col[5].transAxes, ha="right", va="bottom",
                fontsize="small",
                bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "0.7"},
            )  # fmt: skip
        for i, ax in enumerate(col):
            ax.set_title(
                f"({rows[i]}) {j + 1}{'′' if i >= 5 else ''}", loc="left", fontsize="small", pad=3
            )
        col[0].set_title(
            f"(a) {j + 1}    {_amplitude_label(ratio)}"
            + (f" = {ratio * y0 * UM:.3f} µm" if ratio > 0 else " (no vibration)"),
            loc="left",
            fontsize="medium",
        )
        col[-1].set_xlabel(T_LABEL)
    for i, label in enumerate(
        (Y_LABEL, YDOT_LABEL, YDDOT_LABEL, R_LABEL, FT_LABEL, X_LABEL, XDOT_LABEL, XDDOT_LABEL)
    ):
        axes[i, 0].set_ylabel(label)
        if i < 5:  # normal quantities and forces: one scale for all columns
            lows = [ax.get_ylim()[0] for ax in axes[i]]
            highs = [ax.get_ylim()[1] for ax in axes[i]]
            for ax in axes[i]:
                ax.set_ylim(min(lows), max(highs))
    # Headroom above the friction curves for the letters and the legend.
    for ax in axes[4]:
        ax.set_ylim(0, 1.25 * max(params.mu * float(np.max(ds["R"])), force))
    axes[0, 0].set_xlim(0, t_ms[-1])
    axes[4, 0].legend(fontsize="x-small", loc="upper right")
    fig.suptitle(
        f"Fig. 4 — normal micro-vibrations (a)–(e), columns 1–4, and sliding (f)–(h), "
        f"columns 1′–4′, under $F$ = {force:g} N (grey: stick)"
    )
    return fig, ds


# -- Fig. 5 ----------------------------------------------------------------------------


def _slip_phases(run: SimulationResult) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Samples of the sliding phases, those of the first one, and x from each release [m].

    Each phase runs from its release sample to the sample of the stop (the sample at a
    switching instant holds the state just after it). The first phase starts from rest at
    the highest point at t = 0, not from a release, and is a transient.
    """
    stick = run.state == STICK
    slide = ~stick
    slide[1:] |= ~stick[:-1]
    sticks = np.flatnonzero(stick)
    first = slide & (np.arange(slide.size) < (sticks[0] if sticks.size else slide.size))
    start = slide.copy()
    start[1:] &= ~slide[:-1]
    x_release = run.x[np.flatnonzero(start)][np.maximum(np.cumsum(start) - 1, 0)]
    return slide, first, np.where(slide, run.x - x_release, np.nan)


def figure5(
    params: Parameters | None = None, *, force: float = PAPER_FORCE, duration: float = 3e-3
) -> tuple[Figure, xr.Dataset]:
    """Friction force and velocity in stick–slip, A = 2y0/3 and y0 (paper Fig. 5)."""
    params = Parameters() if params is None else params
    y0 = params.static_deflection
    ratios = (2 / 3, 1.0)
    amplitudes = [r * y0 for r in ratios]
    t, runs = _trajectories(params, force, amplitudes, duration, 6001)
    phases = [_slip_phases(run) for run in runs]
    variables = _motion_variables(params, force, runs)
    variables["x_from_release"] = _var(
        ("amplitude", "time"),
        np.stack([phase[2] for phase in phases]),
        "m",
        "x minus x at the release of the current slip phase (NaN while sticking), Fig. 5f",
    )
    caption = (
        "Friction force F_t and velocity xdot of the slider in stick-slip motion for "
        "the two largest amplitudes of Fig. 4"
    )
    ds = _cycle_dataset(params, force, variables, t, ratios, "Fig. 5", caption)

    fig = _new_figure((15.0, 8.5))
    (ax_a, ax_b, ax_c), (ax_d, ax_e, ax_f) = fig.subplots(2, 3)
    t_ms = t * MS
    for k, (ratio, run, (slide, first, x_rel)) in enumerate(zip(ratios, runs, phases, strict=True)):
        color = COLORS[k + 2]
        label = _amplitude_label(ratio)
        ax_force, ax_vel = (ax_a, ax_d) if k == 0 else (ax_b, ax_e)
        _friction_panel(ax_force, t_ms, run, color, force)
        ax_vel.plot(t_ms, run.xdot * UM_S, color=color, label=rf"$\dot x(t)$, {label}")
        for ax in (ax_force, ax_vel):
            _shade(ax, t_ms, run.state == STICK, STICK_SHADE, label="stick ($t_s$)")
            ax.set_xlim(0, t_ms[-1])
            ax.set_xlabel(T_LABEL)
        peak = float(np.max(run.xdot)) * UM_S
        ax_force.set_ylim(0, 1.3 * max(float(np.max(ds["friction_limit"])), force))
        ax_vel.set_ylim(-0.03 * peak, 1.3 * peak)
        ax_force.set_ylabel("$F$, $F_t$ [N]")
        ax_vel.set_ylabel(XDOT_LABEL)
        ax_force.legend(fontsize="small", loc="upper right")
        ax_vel.legend(fontsize="small", loc="upper right")
        _panel(ax_force, "ab"[k], f"$F$ and $F_t$ against $t$, {label}")
        _panel(ax_vel, "de"[k], rf"velocity $\dot x(t)$, {label}")
        for mask, style, suffix in (
            (slide & ~first, {"lw": 1.8}, "steady cycles"),
            (first, {"lw": 1.0, "ls": ":"}, "first slip (transient)"),
        ):
            ax_c.plot(
                _masked(run.xdot * UM_S, mask),
                _masked(np.abs(run.Ft), mask),
                color=color,
                label=f"{label}, {suffix}",
                **style,
            )
            ax_f.plot(
                _masked(x_rel * NM, mask),
                _masked(run.xdot * UM_S, mask),
                color=color,
                label=f"{label}, {suffix}",
                **style,
            )
    ax_c.axhline(force, color="k", ls="--", lw=1.0, label=f"$F = {force:g}$ N")
    ax_c.set_xlabel(XDOT_LABEL)
    ax_c.set_ylabel(r"$|F_t| = \mu|R|$ [N]")
    ax_c.set_xlim(0, None)
    ax_c.legend(fontsize="small", loc="upper right")
    _panel(ax_c, "c", r"friction force against $\dot x$ (sliding phase)")
    ax_f.set_xlabel("$x - x_r$ [nm] (from the release $x_r$ of each slip)")
    ax_f.set_ylabel(XDOT_LABEL)
    ax_f.set_xlim(0, None)
    ax_f.set_ylim(0, 1.35 * float(np.max(ds["xdot"])) * UM_S)
    ax_f.legend(fontsize="small", loc="upper right")
    _panel(ax_f, "f", r"phase plane $x$–$\dot x$ (sliding phase; limit cycle)")
    fig.suptitle(
        f"Fig. 5 — friction force and sliding velocity in stick–slip, $F$ = {force:g} N "
        "(grey: stick; thin line: potential static friction $\\mu|R|$)"
    )
    return fig, ds


# -- Fig. 6 ----------------------------------------------------------------------------


def figure6(
    params: Parameters | None = None,
    *,
    force: float = PAPER_FORCE,
    amplitude_ratio: float = FIG6_AMPLITUDE_RATIO,
    duration: float = 5e-3,
) -> tuple[Figure, xr.Dataset]:
    """Vibration with momentary loss of contact and the resulting drift (paper Fig. 6)."""
    params = Parameters() if params is None else params
    y0 = params.static_deflection
    amplitude = amplitude_ratio * y0
    t, (run,) = _trajectories(params, force, [amplitude], duration, 5001)
    period = free_period(params, amplitude)
    variables = _motion_variables(params, force, [run], stacked=False)
    variables["amplitude_ratio"] = _var((), amplitude_ratio, "1", "A / y0")
    variables["amplitude"] = _var((), amplitude, "m", "normal vibration amplitude A")
    variables["period"] = _var((), period, "s", "free vibration period T(A)")
    ds = xr.Dataset(
        variables,
        coords={"time": _time_coord(t)},
        attrs=_common_attrs(
            params,
            "Fig. 6",
            "Normal contact free micro-vibration with momentary loss of contact (a-c), "
            f"its R and F_t (d, e) and x, xdot, xddot (f-h) under F = {force:g} N",
        ),
    )

    fig = _new_figure((15.0, 11.0))
    grid = fig.add_gridspec(3, 6)
    ax_a = fig.add_subplot(grid[0, 0:2])
    ax_b = fig.add_subplot(grid[0, 2:4], sharex=ax_a)
    ax_c = fig.add_subplot(grid[0, 4:6])
    ax_d = fig.add_subplot(grid[1, 0:3], sharex=ax_a)
    ax_e = fig.add_subplot(grid[1, 3:6], sharex=ax_a)
    ax_f = fig.add_subplot(grid[2, 0:2], sharex=ax_a)
    ax_g = fig.add_subplot(grid[2, 2:4], sharex=ax_a)
    ax_h = fig.add_subplot(grid[2, 4:6], sharex=ax_a)
    t_ms = t * MS
    color = "tab:purple"
    stick = run.state == STICK
    flight = run.state == FLIGHT

    ax_a.plot(t_ms, run.y * UM, color=color)
    ax_a.axhline(y0 * UM, color="k", ls="--", lw=0.7, label="$y_0$")
    ax_a.axhline(0.0, color="tab:red", ls=":", lw=1.0, label="$y = 0$ (edge of contact)")
    ax_a.set_ylabel(Y_LABEL + " (penetration)")
    _panel(ax_a, "a", "normal vibration $y(t)$")
    ax_b.plot(t_ms, run.ydot * MM_S, color=color)
    ax_b.axhline(0.0, color="0.4", lw=0.6)
    ax_b.set_ylabel(YDOT_LABEL)
    _panel(ax_b, "b", r"normal velocity $\dot y(t)$")
    one = t <= period
    ax_c.plot(run.y[one] * UM, run.ydot[one] * MM_S, color=color, label="one period")
    ax_c.plot(
        _masked(run.y * UM, flight & one),
        _masked(run.ydot * MM_S, flight & one),
        color="tab:red",
        lw=2.5,
        alpha=0.6,
        label="loss of contact ($y < 0$)",
    )
    ax_c.axvline(0.0, color="tab:red", ls=":", lw=1.0)
    ax_c.axhline(0.0, color="0.4", lw=0.6)
    ax_c.plot([y0 * UM], [0.0], "s", color="k", ms=5, label="C")
    ax_c.set_xlabel(Y_LABEL)
    ax_c.set_ylabel(YDOT_LABEL)
    ax_c.set_ylim(None, 1.6 * float(np.max(run.ydot)) * MM_S)
    ax_c.legend(fontsize="small", loc="upper center", ncols=3)
    _panel(ax_c, "c", "phase portrait")

    ax_d.plot(t_ms, run.R, color=color, label="$|R|$")
    ax_d.axhline(params.mass * params.g, color="k", ls="--", lw=0.7, label="$mg$")
    ax_d.set_ylabel(R_LABEL)
    _panel(ax_d, "d", "normal reaction")
    _friction_panel(ax_e, t_ms, run, color, force)
    ax_e.set_ylim(0, 1.35 * max(float(np.max(run.friction_limit)), force))
    ax_e.set_ylabel(FT_LABEL)
    _panel(ax_e, "e", "friction force against $F$")
    ax_f.plot(t_ms, run.x * NM, color=color)
    ax_f.set_ylabel(X_LABEL)
    _panel(ax_f, "f", "displacement $x$")
    ax_g.plot(t_ms, run.xdot * UM_S, color=color)
    ax_g.set_ylabel(XDOT_LABEL)
    _panel(ax_g, "g", r"velocity $\dot x$")
    ax_h.plot(t_ms, run.xddot, color=color)
    ax_h.axhline(0.0, color="0.4", lw=0.6)
    ax_h.set_ylabel(XDDOT_LABEL)
    _panel(ax_h, "h", r"acceleration $\ddot x$")
    for ax in (ax_a, ax_b, ax_d, ax_e, ax_f, ax_g, ax_h):
        _shade(ax, t_ms, flight, FLIGHT_SHADE, label="loss of contact")
        _shade(ax, t_ms, stick, STICK_SHADE, label="stick")
        ax.set_xlabel(T_LABEL)
    ax_a.set_xlim(0, t_ms[-1])
    handles: dict[str, object] = {}
    for ax in (ax_a, ax_d, ax_e):
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            handles.setdefault(label, handle)
    fig.legend(
        list(handles.values()), list(handles), loc="outside lower center", ncols=5, fontsize="small"
    )
    fig.suptitle(
        f"Fig. 6 — normal vibration with momentary loss of contact, "
        f"$A$ = {amplitude_ratio:g} $y_0$ = {amplitude * UM:.3f} µm, $F$ = {force:g} N: "
        "the slider drifts"
    )
    return fig, ds


# -- writing ---------------------------------------------------------------------------

FIGURES: dict[str, Callable[[Parameters], tuple[Figure, xr.Dataset]]] = {
    "fig2": figure2,
    "fig3": figure3,
    "fig4": figure4,
    "fig5": figure5,
    "fig6": figure6,
}


def write_paper_figures(
    out_dir: str | Path,
    params: Parameters | None = None,
    *,
    figures: Sequence[str] = ("fig2", "fig3", "fig4", "fig5", "fig6"),
    dpi: int = 150,
    progress: Callable[[str], None] | None = None,
) -> list[Path]:
    """Write ``figN.png`` and ``figN.nc`` (its data, SI units) for each requested figure.

    Parameters
    ----------
    out_dir : path
        Output directory (created if missing).
    params : Parameters, optional
        Model constants; the paper's data by default.
    figures : sequence of {"fig2", ..., "fig6"}
        Which figures to write.
    dpi : int
        Resolution of the PNG files [dots per inch].
    progress : callable, optional
        Called with a short message as each figure is computed and written.

    Returns
    -------
    list of Path
        The files written, PNG then NetCDF for each figure, in the order requested.
        Each file is written to a temporary name and renamed, so no partial file is
        left behind on error.
    """
    params = Parameters() if params is None else params
    if not isinstance(params, Parameters):
        raise ValueError(f"params must be a microslip.Parameters, got {type(params).__name__}")
    if isinstance(figures, str):
        figures = (figures,)
    unknown = [name for name in figures if name not in FIGURES]
    if unknown:
        raise ValueError(f"unknown figure {unknown[0]!r}; known: {', '.join(FIGURES)}")
    if isinstance(dpi, bool) or not isinstance(dpi, numbers.Integral) or dpi <= 0:
        raise ValueError(f"dpi must be a positive integer, got {dpi!r}")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    for name in figures:
        if progress is not None:
            progress(f"{name}: computing")
        fig, ds = FIGURES[name](params)
        png = out / f"{name}.png"
        nc = out / f"{name}.nc"
        write_atomically(png, lambda tmp, fig=fig: fig.savefig(tmp, format="png", dpi=dpi))
        write_dataset(ds, nc)
        written += [png, nc]
        if progress is not None:
            progress(f"{name}: wrote {png.name}, {nc.name}")
    return written
