"""``microslip figures`` for parameter sets other than the paper's (issue 8, defect 7).

Every figure is drawn, and its curves lie where the set's own scales put them: the
turning points of the free vibration from the energy integral of (2.4), the peak
reaction (m2 + 1) m g at A = y0, loss of contact at y = -0.3 y0 for A = 1.3 y0, the
no-sliding boundary of eq. (4.2), and, for m2 = 2, the paper's slip distance rescaled by
μ g T0² (eqs. 2.3–2.5 divided by m g depend on t/T0, F/(μ m g), A/y0 and m2 only).
"""

from __future__ import annotations

import re

import numpy as np
import pytest
import xarray as xr
from figure_lines import curves
from scipy.optimize import brentq

import microslip as ms
from microslip.plotting import FigureNotDrawable, figure5, paper, velocity_map_figure
from microslip.plotting.figures import write_figures
from microslip.results import FLIGHT, STICK

P = ms.Parameters()
SETS = {
    "mass 5": {"mass": 5.0},
    "m2 1.5": {"m2": 1.5},
    "m2 1": {"m2": 1.0},
    "mu 0.3, mass 0.2": {"mu": 0.3, "mass": 0.2},
}
NAMES = ("fig2", "fig3", "fig4", "fig5", "fig6", "fig7")
PREFIX = {"f": 1e-15, "p": 1e-12, "n": 1e-9, "µ": 1e-6, "m": 1e-3, "": 1.0, "k": 1e3}


def si_per_unit(label: str) -> float:
    """SI value of one plotted unit, read from an axis label "... [prefix+unit]"."""
    match = re.search(r"\[(f|p|n|µ|m|k|)(m|s|N)(/s(\$\^2\$)?)?\]", label)
    assert match, f"no unit in {label!r}"
    return PREFIX[match.group(1)]


def lowest_point(params: ms.Parameters, amplitude: float) -> float:
    """y_max [m] from rest at y0 - A, 0 <= A <= y0: energy integral of (2.4)."""
    k, m2, w = params.stiffness_coefficient, params.m2, params.mass * params.g
    y0 = params.static_deflection
    y_min = y0 - amplitude

    def work(y):
        return k * (y ** (m2 + 1) - y_min ** (m2 + 1)) / (m2 + 1) - w * (y - y_min)

    return brentq(work, y0, 10 * y0, xtol=1e-15 * y0, rtol=1e-14)


@pytest.fixture(scope="module", params=list(SETS), ids=list(SETS))
def drawn(request, tmp_path_factory):
    """Every figure for one parameter set, written at low dpi; Figures and data kept."""
    params = P.replace(**SETS[request.param])
    directory = tmp_path_factory.mktemp("figures")
    figures: dict = {}
    patch = pytest.MonkeyPatch()
    for name, draw in paper.FIGURES.items():
        patch.setitem(
            paper.FIGURES, name, lambda p, draw=draw, name=name: figures.setdefault(name, draw(p))
        )
    try:
        paths = write_figures(directory, params, dpi=20)
    finally:
        patch.undo()
    data = {}
    for name in NAMES:
        with xr.open_dataset(directory / f"{name}.nc") as ds:
            data[name] = ds.load()
    figures["fig7"] = (velocity_map_figure(data["fig7"], params), data["fig7"])
    return params, paths, directory, {name: fig for name, (fig, _ds) in figures.items()}, data


def test_every_figure_is_written_with_units_on_every_variable(drawn):
    _params, paths, directory, _figures, data = drawn
    expected = [directory / f"{n}.{e}" for n in NAMES[:-1] for e in ("png", "nc")]
    assert paths == [*expected, directory / "fig7.nc", directory / "fig7.png"]
    for name, ds in data.items():
        for key in [*ds.data_vars, *ds.coords]:
            assert str(ds[key].attrs.get("units", "")).strip(), f"{name}:{key}"


def test_every_panel_has_a_unit_and_readable_numbers(drawn):
    """Units follow the set's scales: the largest plotted number of each panel of the
    key figures is between 0.01 and 10^4 of its unit (the paper's: 0.2 µm ... 30 N)."""
    _params, _paths, _dir, figures, _data = drawn
    for name in ("fig2", "fig3", "fig5", "fig6"):
        for ax in figures[name].axes:
            si_per_unit(ax.get_ylabel())
            si_per_unit(ax.get_xlabel() or figures[name].axes[-1].get_xlabel())
            peak = max(np.nanmax(np.abs(np.asarray(c.get_ydata(), float))) for c in curves(ax))
            assert 1e-2 <= peak <= 1e4, (name, ax.get_ylabel(), peak)


def test_fig2_turning_points_from_the_energy_integral(drawn):
    params, _paths, _dir, figures, _data = drawn
    y0 = params.static_deflection
    ax_b = figures["fig2"].axes[1]
    unit = si_per_unit(ax_b.get_ylabel())
    lines = curves(ax_b, "$A =")
    assert len(lines) == 3
    for line, ratio in zip(lines, (1 / 3, 2 / 3, 1.0), strict=True):
        y = np.asarray(line.get_ydata()) * unit
        assert y.min() == pytest.approx(y0 - ratio * y0, rel=1e-9, abs=1e-9 * y0)
        assert y.max() == pytest.approx(lowest_point(params, ratio * y0), rel=1e-4)
    # the time axis spans 3.2 periods of the largest vibration, in the labelled unit
    t_end = ax_b.get_xlim()[1] * si_per_unit(ax_b.get_xlabel())
    assert t_end == pytest.approx(3.2 * ms.free_period(params, y0), rel=1e-9)


def test_fig3_peak_reaction_is_m2_plus_1_times_m_g(drawn):
    params, _paths, _dir, figures, data = drawn
    weight = params.mass * params.g
    ax_b = figures["fig3"].axes[1]
    (reaction,) = curves(ax_b, "normal reaction")
    peak = np.max(reaction.get_ydata()) * si_per_unit(ax_b.get_ylabel())
    assert peak == pytest.approx((params.m2 + 1) * weight, rel=1e-3)
    assert ax_b.get_ylim()[1] * si_per_unit(ax_b.get_ylabel()) > peak  # inside the frame
    assert float(data["fig3"]["R"].max()) == pytest.approx(peak, rel=1e-12)


def test_fig4_drive_window_and_stick_slip(drawn):
    params, _paths, _dir, _figures, data = drawn
    ds = data["fig4"]
    friction = params.mu * params.mass * params.g
    force = float(ds["force"])
    assert force == pytest.approx(0.5 / 0.981 * friction, rel=1e-12)
    t = ds["time"].values
    assert t[-1] == pytest.approx(5e-3 * params.natural_period / P.natural_period, rel=1e-12)
    still = ds.isel(amplitude=0)
    assert np.all(still["x"].values == 0.0) and np.all(still["state"].values == STICK)
    cycle = ms.stick_slip_cycle(params, force=force, amplitude=params.static_deflection)
    column = ds.isel(amplitude=3)
    state = column["state"].values
    starts = np.flatnonzero(np.diff(np.r_[0, (state == STICK).astype(int)]) == 1)
    steps = np.diff(column["x"].values[starts])
    assert steps.size >= 4
    np.testing.assert_allclose(steps, cycle.slip_distance, rtol=1e-6)
    if params.m2 == 2.0:  # similar to the paper's: x / (mu g T0^2) is the same
        paper = ms.stick_slip_cycle(P, force=0.5, amplitude=P.static_deflection)
        scale = params.mu * params.g * params.natural_period**2
        paper_scale = P.mu * P.g * P.natural_period**2
        assert steps[-1] / scale == pytest.approx(paper.slip_distance / paper_scale, rel=1e-6)


def test_fig5_slip_phases_reach_the_steady_slip_distance(drawn):
    params, _paths, _dir, _figures, data = drawn
    ds = data["fig5"]
    force = float(ds["force"])
    for k in range(2):
        column = ds.isel(amplitude=k)
        cycle = ms.stick_slip_cycle(params, force=force, amplitude=float(column["amplitude"]))
        state = column["state"].values
        starts = np.flatnonzero((state[1:] == STICK) & (state[:-1] != STICK)) + 1
        ends = column["x_from_release"].values[starts][1:]
        assert ends.size >= 2
        np.testing.assert_allclose(ends, cycle.slip_distance, rtol=1e-6)


def test_fig6_loses_contact_at_minus_0_3_y0_and_flies_at_f_over_m(drawn):
    params, _paths, _dir, _figures, data = drawn
    ds = data["fig6"]
    y0 = params.static_deflection
    assert ds["y"].values.min() == pytest.approx(-0.3 * y0, rel=1e-6)
    flight = ds["state"].values == FLIGHT
    assert flight.any()
    np.testing.assert_allclose(
        ds["xddot"].values[flight], float(ds["force"]) / params.mass, rtol=1e-12
    )
    assert np.all(ds["R"].values[flight] == 0.0)


def test_fig7_grid_and_no_sliding_boundary(drawn):
    """The map covers the paper's F/(mu m g) and A/y0 ranges; v = 0 exactly up to the
    boundary F = mu S c_n (y0 - A)^m2 (eq. 4.2), which is drawn where it belongs."""
    params, _paths, _dir, figures, data = drawn
    ds = data["fig7"]
    y0 = params.static_deflection
    friction = params.mu * params.mass * params.g
    forces, amplitudes = ds["force"].values, ds["amplitude"].values
    assert forces.max() == pytest.approx(0.95 / 0.981 * friction, rel=1e-12)
    assert amplitudes.max() == pytest.approx(3e-7 / P.static_deflection * y0, rel=1e-12)
    v = ds["mean_velocity"].transpose("amplitude", "force").values
    threshold = (
        params.mu * params.area * params.c_n * np.clip(y0 - amplitudes, 0, None) ** params.m2
    )
    below = forces[None, :] <= threshold[:, None] * (1 - 1e-9)
    above = (forces[None, :] > threshold[:, None] * (1 + 1e-6)) & (forces[None, :] < friction)
    assert below.any() and above.any()
    assert np.all(v[below] == 0.0) and np.all(v[above] > 0.0)
    contour = figures["fig7"].axes[1]
    (boundary,) = curves(contour, "no-sliding boundary")
    f_unit, a_unit = si_per_unit(contour.get_xlabel()), si_per_unit(contour.get_ylabel())
    a = np.asarray(boundary.get_ydata()) * a_unit
    expected = params.mu * params.area * params.c_n * np.clip(y0 - a, 0, None) ** params.m2
    np.testing.assert_allclose(np.asarray(boundary.get_xdata()) * f_unit, expected, rtol=1e-9)


def test_no_friction_draws_figs_2_3_and_names_the_others(tmp_path):
    messages: list[str] = []
    with pytest.raises(FigureNotDrawable) as info:
        write_figures(tmp_path, P.replace(mu=0.0), dpi=20, progress=messages.append)
    error = info.value
    assert error.figure == "fig4, fig5, fig6, fig7"
    assert "mu = 0" in str(error) and "\n" not in str(error)
    written = sorted(p.name for p in tmp_path.iterdir())
    assert written == ["fig2.nc", "fig2.png", "fig3.nc", "fig3.png"]
    assert sorted(p.name for p in error.written) == written
    assert any("fig7: not drawn" in m for m in messages)


def test_fig5_draws_an_amplitude_that_never_slides():
    """F = 0.05 N is below the threshold mu m g / 9 = 0.109 N at A = 2 y0/3 (eq. 4.2)."""
    fig, ds = figure5(P, force=0.05)
    still = ds.isel(amplitude=0)
    assert np.all(still["xdot"].values == 0.0) and np.all(still["state"].values == STICK)
    assert np.all(np.isnan(still["x_from_release"].values))
    assert float(ds["mean_velocity"][0]) == 0.0 and float(ds["mean_velocity"][1]) > 0.0
    ax_d = fig.axes[3]
    assert any(text.get_text() == "no sliding" for text in ax_d.texts)
    assert ax_d.get_ylim()[1] > ax_d.get_ylim()[0]


def test_cli_names_the_figure_it_cannot_draw_in_one_line(cli, tmp_path):
    """(Refused before any computation, so this costs no JIT compilation.)"""
    out = tmp_path / "mu0"
    result = cli("figures", "--mu", "0", "--only", "fig7", "--dpi", "20", "--out", str(out))
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and "fig7 cannot be drawn" in result.stderr
    assert "mu = 0" in result.stderr and "Traceback" not in result.stderr
    assert not any(out.glob("fig7*"))
