"""Figs. 2 and 3 of the paper: the free normal micro-vibrations (layout: see
:mod:`microslip.plotting.paper`)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")  # no display; figures are built with matplotlib.figure.Figure

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from microslip.analysis.free_vibration import free_period, turning_points
from microslip.model.contact import reaction_array
from microslip.model.parameters import Parameters
from microslip.plotting._paper_common import (
    COLORS,
    _amplitude_coord,
    _amplitude_label,
    _common_attrs,
    _label,
    _new_figure,
    _panel,
    _stack,
    _time_coord,
    _trajectories,
    _var,
)
from microslip.plotting.scales import (
    figure_scales,
)

# -- Fig. 2 ----------------------------------------------------------------------------


def figure2(params: Parameters | None = None) -> tuple[Figure, xr.Dataset]:
    """Load–deflection characteristic and free normal micro-vibrations (paper Fig. 2)."""
    params = Parameters() if params is None else params
    u = figure_scales(params)
    y0 = params.static_deflection
    weight = params.mass * params.g
    ratios = (1 / 3, 2 / 3, 1.0)
    amplitudes = [r * y0 for r in ratios]
    periods = np.array([free_period(params, a) for a in amplitudes])
    duration = 3.2 * float(periods.max())
    t, runs = _trajectories(params, 0.0, amplitudes, duration, 3001)
    turning = np.array([turning_points(params, a) for a in amplitudes])

    # Down to past the edge of contact, up to past the lowest turning point (which for the
    # paper's m2 = 2 is sqrt(3) y0 at A = y0, and grows as m2 falls).
    y_top = max(1.9 * y0, 1.05 * float(turning[:, 1].max()))
    y_char = np.linspace(-0.15 * y0, y_top, 801)
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
    t_ms = t * u.t.factor

    # (a) characteristic with C, its tangent, and the range of each vibration.
    ym, fm = u.y.factor, u.R.factor
    ax_a.plot(y_char * ym, r_char * fm, color="k", lw=1.5, label="$|R| = S c_n y^{m_2}$")
    y_tan = np.linspace(0.35 * y0, 1.65 * y0, 2)
    ax_a.plot(
        y_tan * ym,
        (weight + stiffness * (y_tan - y0)) * fm,
        color="0.5",
        ls=":",
        lw=1.2,
        label=f"tangent at C, $K_n$ = {stiffness * fm / ym:.3g} {u.R.symbol}/{u.y.symbol}",
    )
    for k, ratio in enumerate(ratios):
        lo, hi = turning[k]
        ax_a.plot(
            np.array([lo, hi]) * ym,
            reaction_array(params, np.array([lo, hi])) * fm,
            "o",
            color=COLORS[k],
            ms=6,
            label=f"{_amplitude_label(ratio)}: $|R|$ from "
            f"{reaction_array(params, lo) * fm:.3g} to {reaction_array(params, hi) * fm:.3g} "
            f"{u.R.symbol}",
        )
    ax_a.plot([y0 * ym], [weight * fm], "s", color="k", ms=8)
    ax_a.annotate(
        f"C ($y_0$ = {y0 * ym:.3f} {u.y.symbol}, $mg$ = {weight * fm:.3g} {u.R.symbol})",
        (y0 * ym, weight * fm),
        xytext=(-10, 22),
        textcoords="offset points",
        ha="right",
        arrowprops={"arrowstyle": "-", "color": "k", "lw": 0.8},
    )
    ax_a.vlines(y0 * ym, 0, weight * fm, color="k", lw=0.6, ls="--")
    ax_a.hlines(weight * fm, y_char[0] * ym, y0 * ym, color="k", lw=0.6, ls="--")
    ax_a.set_xlim(y_char[0] * ym, y_char[-1] * ym)
    ax_a.set_ylim(0, None)
    ax_a.set_xlabel(u.y.label("deflection $y$"))
    ax_a.set_ylabel(u.R.label("load $|R|$"))
    ax_a.legend(fontsize="small", loc="upper left")
    _panel(ax_a, "a", "load–deflection characteristic")

    for k, (ratio, run) in enumerate(zip(ratios, runs, strict=True)):
        label = f"{_amplitude_label(ratio)}, $f$ = {1 / periods[k]:.0f} Hz"
        ax_b.plot(t_ms, run.y * u.y.factor, color=COLORS[k], label=label)
        ax_c.plot(t_ms, run.ydot * u.ydot.factor, color=COLORS[k], label=label)
        one = t <= periods[k]
        ax_d.plot(run.y[one] * ym, run.ydot[one] * u.ydot.factor, color=COLORS[k], label=label)
    for ax in (ax_b, ax_c):
        ax.set_xlim(0, t_ms[-1])
        ax.set_xlabel(_label(u, "t"))
    ax_b.axhline(y0 * u.y.factor, color="k", ls="--", lw=0.8, label="$y_0$ (static equilibrium)")
    ax_b.axhline(0.0, color="0.4", lw=0.6)
    ax_c.axhline(0.0, color="0.4", lw=0.6)
    ax_b.set_ylabel(_label(u, "y") + " (penetration)")
    ax_c.set_ylabel(_label(u, "ydot"))
    ax_b.set_ylim(-0.03 * y0 * ym, max(2.25 * y0, 1.1 * float(turning[:, 1].max())) * ym)
    ax_b.legend(fontsize="small", loc="upper center", ncols=2)
    _panel(ax_b, "b", "free vibration $y(t)$")
    _panel(ax_c, "c", r"free vibration $\dot y(t)$")
    ax_d.plot([y0 * u.y.factor], [0.0], "s", color="k", ms=6)
    ax_d.annotate("C", (y0 * u.y.factor, 0.0), xytext=(5, 5), textcoords="offset points")
    ax_d.axvline(0.0, color="0.4", lw=0.6)
    ax_d.axhline(0.0, color="0.4", lw=0.6)
    ax_d.set_xlabel(_label(u, "y"))
    ax_d.set_ylabel(_label(u, "ydot"))
    _panel(ax_d, "d", "phase portraits")
    fig.suptitle(
        f"Fig. 2 — free normal contact micro-vibrations ($f_0$ = {params.natural_frequency:.0f} Hz)"
    )
    return fig, ds


# -- Fig. 3 ----------------------------------------------------------------------------


def figure3(params: Parameters | None = None) -> tuple[Figure, xr.Dataset]:
    """Largest contact-keeping free vibration A = y0 and its contact forces (paper Fig. 3)."""
    params = Parameters() if params is None else params
    u = figure_scales(params)
    y0 = params.static_deflection
    weight = params.mass * params.g
    # Starting from rest at y = 0, the energy integral of (2.4) gives the lowest point
    # S c_n y_max^m2 = (m2 + 1) m g: the peak reaction, 3 m g for the paper's m2 = 2.
    peak_ratio = params.m2 + 1.0
    y_low = y0 * peak_ratio ** (1.0 / params.m2)
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
    t_ms = t * u.t.factor
    ax_a.plot(t_ms, run.y * u.y.factor, color="tab:blue", label="$y(t)$")
    ax_a.axhline(y0 * u.y.factor, color="k", ls="--", lw=0.8, label="$y_0$ (static equilibrium)")
    ax_a.axhline(0.0, color="tab:red", ls=":", lw=1.0, label="$y = 0$ (edge of contact)")
    ax_a.set_ylabel(_label(u, "y") + " (penetration)")
    ax_a.set_ylim(-0.05 * y0 * u.y.factor, max(2.2 * y0, 1.2 * y_low) * u.y.factor)
    ax_a.legend(fontsize="small", loc="upper center", ncols=3)
    _panel(ax_a, "a", f"normal vibration, $A = y_0$ = {y0 * u.y.factor:.3f} {u.y.symbol}")

    fm = u.R.factor
    ax_b.plot(t_ms, r_abs * fm, color="tab:blue", lw=1.6, label="normal reaction $|R|$")
    ax_b.plot(
        t_ms,
        friction * fm,
        color="tab:orange",
        lw=1.6,
        label=rf"$F_t = \mu|R|$ ($\mu$ = {params.mu:g})",
    )
    ax_b.axhline(
        weight * fm,
        color="k",
        ls="--",
        lw=0.8,
        label=f"$mg$ = {weight * fm:.3g} {u.R.symbol} (mean of $|R|$)",
    )
    ax_b.axhline(peak_ratio * weight * fm, color="0.5", ls=":", lw=0.8, label=f"${peak_ratio:g}mg$")
    ax_b.set_ylabel(u.R.label("force"))
    ax_b.set_xlabel(_label(u, "t"))
    ax_b.set_xlim(0, t_ms[-1])
    ax_b.set_ylim(-0.05 * weight * fm, 1.3 * peak_ratio * weight * fm)
    ax_b.legend(fontsize="small", loc="upper center", ncols=4)
    _panel(
        ax_b,
        "b",
        f"contact forces: $|R|$ from {r_abs.min() * fm:.2g} to {r_abs.max() * fm:.4g} "
        f"{u.R.symbol} "
        f"({r_abs.max() / weight:.3f} $mg$)",
    )
    fig.suptitle("Fig. 3 — largest free vibration without loss of contact")
    return fig, ds
