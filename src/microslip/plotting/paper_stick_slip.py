"""Figs. 4, 5 and 6 of the paper: stick–slip under a constant drive, and the drift
with momentary loss of contact (layout: see :mod:`microslip.plotting.paper`)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")  # no display; figures are built with matplotlib.figure.Figure

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from microslip.analysis.free_vibration import free_period
from microslip.model.parameters import Parameters
from microslip.plotting._paper_common import (
    COLORS,
    FIG4_DURATION,
    FIG5_DURATION,
    FIG6_AMPLITUDE_RATIO,
    FIG6_DURATION,
    FLIGHT_SHADE,
    STICK_SHADE,
    _amplitude_label,
    _common_attrs,
    _cycle_dataset,
    _drive,
    _force_text,
    _friction_panel,
    _label,
    _masked,
    _motion_variables,
    _new_figure,
    _panel,
    _shade,
    _time_coord,
    _trajectories,
    _var,
)
from microslip.results import FLIGHT, STICK, SimulationResult

# -- Fig. 4 ----------------------------------------------------------------------------


def figure4(
    params: Parameters | None = None,
    *,
    force: float | None = None,
    duration: float | None = None,
) -> tuple[Figure, xr.Dataset]:
    """Stick–slip under F = 0.5 N for A = 0, y0/3, 2y0/3, y0 (paper Fig. 4).

    ``force`` [N] and ``duration`` [s] default to the paper's 0.5 N and 5 ms, scaled by
    μ m g and T0 for other parameters. FigureNotDrawable for μ = 0 without ``force``.
    """
    params = Parameters() if params is None else params
    u, force, duration = _drive(params, force, duration, FIG4_DURATION, "fig4")
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
    t_ms = t * u.t.factor
    rows = "abcdefgh"
    for j, (ratio, run) in enumerate(zip(ratios, runs, strict=True)):
        col = axes[:, j]
        color = COLORS[j]
        stick = run.state == STICK
        col[0].plot(t_ms, run.y * u.y.factor, color=color)
        col[0].axhline(y0 * u.y.factor, color="k", ls="--", lw=0.6)
        col[1].plot(t_ms, run.ydot * u.ydot.factor, color=color)
        col[2].plot(t_ms, (params.g - run.R / params.mass) * u.yddot.factor, color=color)
        col[3].plot(t_ms, run.R * u.R.factor, color=color)
        col[3].axhline(params.mass * params.g * u.R.factor, color="k", ls="--", lw=0.6)
        _friction_panel(col[4], t_ms, run, color, force, u)
        col[5].plot(t_ms, run.x * u.x.factor, color=color)
        col[6].plot(t_ms, run.xdot * u.xdot.factor, color=color)
        col[7].plot(t_ms, run.xddot * u.xddot.factor, color=color)
        for ax in col[4:]:
            _shade(ax, t_ms, stick, STICK_SHADE)
        if np.isfinite(velocity[j]) and distance[j] > 0:
            note = (
                rf"$\Delta x$ = {distance[j] * u.x.factor:.3g} {u.x.symbol}/cycle" + "\n"
                rf"$\bar v$ = {velocity[j] * u.xdot.factor:.3g} {u.xdot.symbol}"
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
            + (
                f" = {ratio * y0 * u.y.factor:.3f} {u.y.symbol}" if ratio > 0 else " (no vibration)"
            ),
            loc="left",
            fontsize="medium",
        )
        col[-1].set_xlabel(_label(u, "t"))
    for i, name in enumerate(("y", "ydot", "yddot", "R", "Ft", "x", "xdot", "xddot")):
        axes[i, 0].set_ylabel(_label(u, name))
        if i < 5:  # normal quantities and forces: one scale for all columns
            lows = [ax.get_ylim()[0] for ax in axes[i]]
            highs = [ax.get_ylim()[1] for ax in axes[i]]
            for ax in axes[i]:
                ax.set_ylim(min(lows), max(highs))
    # Headroom above the friction curves for the letters and the legend.
    for ax in axes[4]:
        ax.set_ylim(0, 1.25 * max(params.mu * float(np.max(ds["R"])), force) * u.Ft.factor)
    axes[0, 0].set_xlim(0, t_ms[-1])
    axes[4, 0].legend(fontsize="x-small", loc="upper right")
    fig.suptitle(
        f"Fig. 4 — normal micro-vibrations (a)–(e), columns 1–4, and sliding (f)–(h), "
        f"columns 1′–4′, under $F$ = {_force_text(u, force)} (grey: stick)"
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
    if not start.any():  # the slider never moves (F at or below the threshold of eq. 4.2)
        return slide, first, np.full(run.x.shape, np.nan)
    x_release = run.x[np.flatnonzero(start)][np.maximum(np.cumsum(start) - 1, 0)]
    return slide, first, np.where(slide, run.x - x_release, np.nan)


def figure5(
    params: Parameters | None = None,
    *,
    force: float | None = None,
    duration: float | None = None,
) -> tuple[Figure, xr.Dataset]:
    """Friction force and velocity in stick–slip, A = 2y0/3 and y0 (paper Fig. 5).

    ``force`` [N] and ``duration`` [s] default to the paper's 0.5 N and 3 ms, scaled by
    μ m g and T0 for other parameters. FigureNotDrawable for μ = 0 without ``force``.
    An amplitude at which the slider does not move is drawn with "no sliding".
    """
    params = Parameters() if params is None else params
    u, force, duration = _drive(params, force, duration, FIG5_DURATION, "fig5")
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
    t_ms = t * u.t.factor
    for k, (ratio, run, (slide, first, x_rel)) in enumerate(zip(ratios, runs, phases, strict=True)):
        color = COLORS[k + 2]
        label = _amplitude_label(ratio)
        ax_force, ax_vel = (ax_a, ax_d) if k == 0 else (ax_b, ax_e)
        _friction_panel(ax_force, t_ms, run, color, force, u)
        ax_vel.plot(t_ms, run.xdot * u.xdot.factor, color=color, label=rf"$\dot x(t)$, {label}")
        for ax in (ax_force, ax_vel):
            _shade(ax, t_ms, run.state == STICK, STICK_SHADE, label="stick ($t_s$)")
            ax.set_xlim(0, t_ms[-1])
            ax.set_xlabel(_label(u, "t"))
        peak = float(np.max(run.xdot)) * u.xdot.factor
        if peak <= 0.0:  # never slides: one plotted unit of velocity as the scale
            peak = 1.0
            ax_vel.text(0.5, 0.5, "no sliding", transform=ax_vel.transAxes, ha="center")
        top = max(float(np.max(ds["friction_limit"])), force) * u.Ft.factor
        ax_force.set_ylim(0, 1.3 * top)
        ax_vel.set_ylim(-0.03 * peak, 1.3 * peak)
        ax_force.set_ylabel(u.Ft.label("$F$, $F_t$"))
        ax_vel.set_ylabel(_label(u, "xdot"))
        ax_force.legend(fontsize="small", loc="upper right")
        ax_vel.legend(fontsize="small", loc="upper right")
        _panel(ax_force, "ab"[k], f"$F$ and $F_t$ against $t$, {label}")
        _panel(ax_vel, "de"[k], rf"velocity $\dot x(t)$, {label}")
        for mask, style, suffix in (
            (slide & ~first, {"lw": 1.8}, "steady cycles"),
            (first, {"lw": 1.0, "ls": ":"}, "first slip (transient)"),
        ):
            ax_c.plot(
                _masked(run.xdot * u.xdot.factor, mask),
                _masked(np.abs(run.Ft) * u.Ft.factor, mask),
                color=color,
                label=f"{label}, {suffix}",
                **style,
            )
            ax_f.plot(
                _masked(x_rel * u.x.factor, mask),
                _masked(run.xdot * u.xdot.factor, mask),
                color=color,
                label=f"{label}, {suffix}",
                **style,
            )
    ax_c.axhline(
        force * u.Ft.factor, color="k", ls="--", lw=1.0, label=f"$F$ = {_force_text(u, force)}"
    )
    ax_c.set_xlabel(_label(u, "xdot"))
    ax_c.set_ylabel(u.Ft.label(r"$|F_t| = \mu|R|$"))
    ax_c.set_xlim(0, None)
    ax_c.legend(fontsize="small", loc="upper right")
    _panel(ax_c, "c", r"friction force against $\dot x$ (sliding phase)")
    ax_f.set_xlabel(u.x.label("$x - x_r$") + " (from the release $x_r$ of each slip)")
    ax_f.set_ylabel(_label(u, "xdot"))
    ax_f.set_xlim(0, None)
    peak = float(np.max(ds["xdot"])) * u.xdot.factor
    ax_f.set_ylim(0, 1.35 * (peak if peak > 0.0 else 1.0))
    ax_f.legend(fontsize="small", loc="upper right")
    _panel(ax_f, "f", r"phase plane $x$–$\dot x$ (sliding phase; limit cycle)")
    fig.suptitle(
        "Fig. 5 — friction force and sliding velocity in stick–slip, "
        f"$F$ = {_force_text(u, force)} "
        "(grey: stick; thin line: potential static friction $\\mu|R|$)"
    )
    return fig, ds


# -- Fig. 6 ----------------------------------------------------------------------------


def figure6(
    params: Parameters | None = None,
    *,
    force: float | None = None,
    amplitude_ratio: float = FIG6_AMPLITUDE_RATIO,
    duration: float | None = None,
) -> tuple[Figure, xr.Dataset]:
    """Vibration with momentary loss of contact and the resulting drift (paper Fig. 6).

    ``force`` [N] and ``duration`` [s] default to the paper's 0.5 N and 5 ms, scaled by
    μ m g and T0 for other parameters; A = ``amplitude_ratio`` y0 [-] (1.3 in the paper:
    contact is lost for any ratio above 1). FigureNotDrawable for μ = 0 without ``force``.
    """
    params = Parameters() if params is None else params
    u, force, duration = _drive(params, force, duration, FIG6_DURATION, "fig6")
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
    t_ms = t * u.t.factor
    color = "tab:purple"
    stick = run.state == STICK
    flight = run.state == FLIGHT

    ax_a.plot(t_ms, run.y * u.y.factor, color=color)
    ax_a.axhline(y0 * u.y.factor, color="k", ls="--", lw=0.7, label="$y_0$")
    ax_a.axhline(0.0, color="tab:red", ls=":", lw=1.0, label="$y = 0$ (edge of contact)")
    ax_a.set_ylabel(_label(u, "y") + " (penetration)")
    _panel(ax_a, "a", "normal vibration $y(t)$")
    ax_b.plot(t_ms, run.ydot * u.ydot.factor, color=color)
    ax_b.axhline(0.0, color="0.4", lw=0.6)
    ax_b.set_ylabel(_label(u, "ydot"))
    _panel(ax_b, "b", r"normal velocity $\dot y(t)$")
    one = t <= period
    ax_c.plot(
        run.y[one] * u.y.factor, run.ydot[one] * u.ydot.factor, color=color, label="one period"
    )
    ax_c.plot(
        _masked(run.y * u.y.factor, flight & one),
        _masked(run.ydot * u.ydot.factor, flight & one),
        color="tab:red",
        lw=2.5,
        alpha=0.6,
        label="loss of contact ($y < 0$)",
    )
    ax_c.axvline(0.0, color="tab:red", ls=":", lw=1.0)
    ax_c.axhline(0.0, color="0.4", lw=0.6)
    ax_c.plot([y0 * u.y.factor], [0.0], "s", color="k", ms=5, label="C")
    ax_c.set_xlabel(_label(u, "y"))
    ax_c.set_ylabel(_label(u, "ydot"))
    ax_c.set_ylim(None, 1.6 * float(np.max(run.ydot)) * u.ydot.factor)
    ax_c.legend(fontsize="small", loc="upper center", ncols=3)
    _panel(ax_c, "c", "phase portrait")

    ax_d.plot(t_ms, run.R * u.R.factor, color=color, label="$|R|$")
    ax_d.axhline(params.mass * params.g * u.R.factor, color="k", ls="--", lw=0.7, label="$mg$")
    ax_d.set_ylabel(_label(u, "R"))
    _panel(ax_d, "d", "normal reaction")
    _friction_panel(ax_e, t_ms, run, color, force, u)
    ax_e.set_ylim(0, 1.35 * max(float(np.max(run.friction_limit)), force) * u.Ft.factor)
    ax_e.set_ylabel(_label(u, "Ft"))
    _panel(ax_e, "e", "friction force against $F$")
    ax_f.plot(t_ms, run.x * u.x.factor, color=color)
    ax_f.set_ylabel(_label(u, "x"))
    _panel(ax_f, "f", "displacement $x$")
    ax_g.plot(t_ms, run.xdot * u.xdot.factor, color=color)
    ax_g.set_ylabel(_label(u, "xdot"))
    _panel(ax_g, "g", r"velocity $\dot x$")
    ax_h.plot(t_ms, run.xddot * u.xddot.factor, color=color)
    ax_h.axhline(0.0, color="0.4", lw=0.6)
    ax_h.set_ylabel(_label(u, "xddot"))
    _panel(ax_h, "h", r"acceleration $\ddot x$")
    for ax in (ax_a, ax_b, ax_d, ax_e, ax_f, ax_g, ax_h):
        _shade(ax, t_ms, flight, FLIGHT_SHADE, label="loss of contact")
        _shade(ax, t_ms, stick, STICK_SHADE, label="stick")
        ax.set_xlabel(_label(u, "t"))
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
        f"$A$ = {amplitude_ratio:g} $y_0$ = {amplitude * u.y.factor:.3f} {u.y.symbol}, "
        f"$F$ = {_force_text(u, force)}: "
        "the slider drifts"
    )
    return fig, ds
