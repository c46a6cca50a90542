"""Figs. 2–6 of the paper: files, units, and the physics of the data behind each figure."""

from __future__ import annotations

import matplotlib.figure
import matplotlib.image
import numpy as np
import pytest
import xarray as xr
from figure_lines import curves
from scipy.optimize import brentq

import microslip as ms
from microslip.plotting import figure3, paper, write_paper_figures
from microslip.plotting.figures import write_figure7
from microslip.results import FLIGHT, SLIP, STICK

NAMES = ("fig2", "fig3", "fig4", "fig5", "fig6")
P = ms.Parameters()
Y0 = P.static_deflection
WEIGHT = P.mass * P.g
F = 0.5  # the paper's tangential drive in Figs. 4-6 [N]


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    """Every figure written once (low dpi, for speed); the Figure objects are kept."""
    directory = tmp_path_factory.mktemp("figures")
    messages: list[str] = []
    drawn: dict = {}
    patch = pytest.MonkeyPatch()
    for name, draw in paper.FIGURES.items():
        patch.setitem(
            paper.FIGURES, name, lambda p, draw=draw, name=name: drawn.setdefault(name, draw(p))
        )
    try:
        paths = write_paper_figures(directory, progress=messages.append, dpi=30)
    finally:
        patch.undo()
    return directory, paths, messages, {name: fig for name, (fig, _ds) in drawn.items()}


@pytest.fixture(scope="module")
def data(out):
    directory = out[0]
    loaded = {}
    for name in NAMES:
        with xr.open_dataset(directory / f"{name}.nc") as ds:
            loaded[name] = ds.load()
    return loaded


@pytest.fixture(scope="module")
def figures(out):
    return out[3]


def plateaus(x: np.ndarray, state: np.ndarray) -> np.ndarray:
    """x [m] at the start of each stick phase."""
    stick = (state == STICK).astype(int)
    return x[np.flatnonzero(np.diff(np.r_[0, stick]) == 1)]


def lowest_point(params: ms.Parameters, amplitude: float) -> float:
    """y_max [m] of the free vibration from rest at y0 - A (0 <= A <= y0): the energy
    integral of (2.4), S c_n (y^(m2+1) - y_min^(m2+1)) / (m2+1) = m g (y - y_min)."""
    k, m2, w = params.stiffness_coefficient, params.m2, params.mass * params.g
    y_min = params.static_deflection - amplitude

    def work(y):
        return k * (y ** (m2 + 1) - y_min ** (m2 + 1)) / (m2 + 1) - w * (y - y_min)

    y0 = params.static_deflection
    return brentq(work, y0, 10 * y0, xtol=1e-15 * y0, rtol=1e-14)


# -- files ------------------------------------------------------------------------------


def test_every_figure_is_written_with_its_data_and_nothing_else(out):
    directory, paths, messages, _figures = out
    expected = [directory / f"{n}.{ext}" for n in NAMES for ext in ("png", "nc")]
    assert paths == expected
    assert sorted(p.name for p in directory.iterdir()) == sorted(p.name for p in expected)
    assert all(any(n in m for m in messages) for n in NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_png_shows_the_figure_at_the_requested_size(out, name):
    directory, _paths, _messages, figures = out
    image = matplotlib.image.imread(directory / f"{name}.png")
    width, height = figures[name].get_size_inches() * 30  # dpi=30
    assert image.shape[:2] == (round(height), round(width))
    grey = image[..., :3].mean(axis=-1)
    assert (grey < 0.5).mean() > 0.005  # has lines and text


# Axis labels of the paper's data, with their units (panel by panel, as drawn).
T, Y, YD = "$t$ [ms]", "$y$ [µm]", r"$\dot y$ [mm/s]"
LABELS = {
    "fig2": [
        ("deflection $y$ [µm]", "load $|R|$ [N]"),
        (T, Y + " (penetration)"),
        (T, YD),
        (Y, YD),
    ],
    "fig3": [("", Y + " (penetration)"), (T, "force [N]")],
    "fig5": [
        (T, "$F$, $F_t$ [N]"),
        (T, "$F$, $F_t$ [N]"),
        (r"$\dot x$ [µm/s]", r"$|F_t| = \mu|R|$ [N]"),
        (T, r"$\dot x$ [µm/s]"),
        (T, r"$\dot x$ [µm/s]"),
        ("$x - x_r$ [nm] (from the release $x_r$ of each slip)", r"$\dot x$ [µm/s]"),
    ],
    "fig6": [
        (T, Y + " (penetration)"),
        (T, YD),
        (Y, YD),
        (T, "$|R|$ [N]"),
        (T, "$|F_t|$, $F$ [N]"),
        (T, "$x$ [nm]"),
        (T, r"$\dot x$ [µm/s]"),
        (T, r"$\ddot x$ [m/s$^2$]"),
    ],
}
FIG4_ROWS = [
    Y, YD, r"$\ddot y$ [m/s$^2$]", "$|R|$ [N]", "$|F_t|$, $F$ [N]", "$x$ [nm]",
    r"$\dot x$ [µm/s]", r"$\ddot x$ [m/s$^2$]",
]  # fmt: skip


@pytest.mark.parametrize("name", sorted(LABELS))
def test_panels_and_axis_labels_with_units(figures, name):
    axes = figures[name].axes
    assert [(ax.get_xlabel(), ax.get_ylabel()) for ax in axes] == LABELS[name]
    assert all(curves(ax) for ax in axes)  # every panel draws data


def test_fig4_is_an_8_by_4_grid_labelled_by_row(figures):
    axes = np.array(figures["fig4"].axes).reshape(8, 4)
    assert [ax.get_ylabel() for ax in axes[:, 0]] == FIG4_ROWS
    assert all(ax.get_ylabel() == "" for ax in axes[:, 1:].ravel())
    assert [ax.get_xlabel() for ax in axes[-1]] == [T] * 4
    assert all(curves(ax) for ax in axes.ravel())


def test_plotted_curves_are_the_saved_data_in_the_labelled_units(figures, data):
    """The numbers on the axes are the NetCDF data times the factor its label names."""
    ds = data["fig4"]
    axes = np.array(figures["fig4"].axes).reshape(8, 4)
    factors = {"y": 1e6, "ydot": 1e3, "R": 1.0, "x": 1e9, "xdot": 1e6, "xddot": 1.0}
    rows = {"y": 0, "ydot": 1, "R": 3, "x": 5, "xdot": 6, "xddot": 7}
    for column in range(4):
        for name, row in rows.items():
            (line,) = curves(axes[row, column])
            np.testing.assert_allclose(line.get_xdata(), ds["time"].values * 1e3, rtol=1e-15)
            expected = ds[name].isel(amplitude=column).values * factors[name]
            np.testing.assert_allclose(line.get_ydata(), expected, rtol=1e-15, atol=0)


@pytest.mark.parametrize("name", NAMES)
def test_netcdf_variables_and_coordinates_carry_units(data, name):
    ds = data[name]
    assert len(ds.data_vars) >= 5
    for key in [*ds.data_vars, *ds.coords]:
        units = ds[key].attrs.get("units")
        assert isinstance(units, str) and units.strip(), f"{name}:{key} has no units"
    for dim in ds.dims:
        assert dim in ds.coords, f"{name}: dimension {dim} has no coordinate"
    assert ds["time"].attrs["units"] == "s"
    assert np.all(np.diff(ds["time"].values) > 0)


def test_fig2_plotted_trajectories_span_the_turning_points(figures):
    """(b): each y(t) runs from y0 - A (its start, at rest) to the lowest point that the
    energy integral gives; (a): the characteristic passes through C = (y0, m g)."""
    ax_a, ax_b = figures["fig2"].axes[:2]
    lines = curves(ax_b, "$A =")
    assert len(lines) == 3
    for line, ratio in zip(lines, (1 / 3, 2 / 3, 1.0), strict=True):
        y = np.asarray(line.get_ydata()) / 1e6
        assert y.min() == pytest.approx(Y0 - ratio * Y0, rel=1e-12, abs=1e-12 * Y0)
        assert y.max() == pytest.approx(lowest_point(P, ratio * Y0), rel=1e-4)
    (characteristic,) = curves(ax_a, "S c_n")
    r_at_y0 = np.interp(Y0 * 1e6, characteristic.get_xdata(), characteristic.get_ydata())
    assert r_at_y0 == pytest.approx(WEIGHT, rel=1e-4)


def test_fig3_plotted_reaction_peaks_at_three_mg(figures):
    ax_b = figures["fig3"].axes[1]
    (reaction,) = curves(ax_b, "normal reaction")
    (friction,) = curves(ax_b, "F_t")
    assert np.max(reaction.get_ydata()) == pytest.approx(3 * WEIGHT, rel=1e-3)
    assert np.max(friction.get_ydata()) == pytest.approx(3 * P.mu * WEIGHT, rel=1e-3)
    assert ax_b.get_ylim()[1] > 3 * WEIGHT  # the peak is inside the frame


def test_fig7_boundary_and_labels(tmp_path):
    """Fig. 7 for the paper's data: labels with units, and the drawn no-sliding boundary
    is F = mu S c_n (y0 - A)^m2 (eq. 4.2), computed here from the constants."""
    from microslip.plotting import velocity_map_figure

    nc, _png = write_figure7(tmp_path, P, dpi=20)
    with xr.open_dataset(nc) as ds:
        ds = ds.load()
    for key in [*ds.data_vars, *ds.coords]:
        assert ds[key].attrs.get("units"), key
    fig = velocity_map_figure(ds, P)
    surface, contour, colorbar = fig.axes
    assert (surface.get_xlabel(), surface.get_ylabel(), surface.get_zlabel()) == (
        "F [N]", "A [µm]", "v [10⁻⁴ m/s]"
    )  # fmt: skip
    assert (contour.get_xlabel(), contour.get_ylabel()) == (
        "tangential force F [N]", "vibration amplitude A [µm]"
    )  # fmt: skip
    assert colorbar.get_ylabel() == "v [10⁻⁴ m/s]"
    (boundary,) = curves(contour, "no-sliding boundary")
    a = np.asarray(boundary.get_ydata()) * 1e-6
    expected = P.mu * P.area * P.c_n * np.clip(Y0 - a, 0.0, None) ** 2
    np.testing.assert_allclose(boundary.get_xdata(), expected, rtol=1e-12, atol=1e-15)
    assert a.max() == pytest.approx(3e-7)
    assert ds["force"].values.min() == 0.05 and ds["force"].values.max() == 0.95


def test_failed_write_leaves_no_file(tmp_path, monkeypatch):
    def broken_savefig(self, fname, *args, **kwargs):
        with open(fname, "wb") as handle:
            handle.write(b"\x89PNG half")
        raise OSError("disk full")

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", broken_savefig)
    # the OSError comes back as one line naming the file (OutputError, a ValueError)
    with pytest.raises(ValueError, match=r"fig3\.png.*disk full"):
        write_paper_figures(tmp_path, figures=("fig3",))
    assert list(tmp_path.iterdir()) == []


def test_bad_arguments_are_refused_before_any_work(tmp_path):
    with pytest.raises(ValueError, match="fig7"):
        write_paper_figures(tmp_path, figures=("fig3", "fig7"))
    with pytest.raises(ValueError, match="dpi"):
        write_paper_figures(tmp_path, figures=("fig3",), dpi=0)
    assert list(tmp_path.iterdir()) == []


# -- physics of the saved data ----------------------------------------------------------


def test_fig2_characteristic_working_point_and_free_vibrations(data):
    ds = data["fig2"]
    r_at_y0 = np.interp(Y0, ds["deflection"].values, ds["R_characteristic"].values)
    assert r_at_y0 == pytest.approx(WEIGHT, rel=1e-4)
    assert float(ds["working_point_R"]) == pytest.approx(WEIGHT, rel=1e-12)
    np.testing.assert_allclose(ds["amplitude"].values, Y0 * np.array([1, 2, 3]) / 3)
    frequency = ds["frequency"].values
    assert np.all(np.diff(frequency) < 0) and np.all(frequency < P.natural_frequency)
    for k, amplitude in enumerate(ds["amplitude"].values):
        y = ds["y"].isel(amplitude=k).values
        ydot = ds["ydot"].isel(amplitude=k).values
        y_min, y_max = ms.turning_points(P, float(amplitude))
        assert y[0] == pytest.approx(Y0 - amplitude, rel=1e-12, abs=1e-20)
        assert y.min() == pytest.approx(y_min, rel=1e-6, abs=1e-6 * Y0)
        assert y.max() == pytest.approx(y_max, rel=1e-4)
        energy = ms.normal_energy(P, y, ydot)
        assert np.ptp(energy) <= 1e-7 * WEIGHT * Y0  # conservative free vibration


def test_fig3_reaction_spans_zero_to_three_mg(data):
    ds = data["fig3"]
    r_abs = ds["R"].values
    assert r_abs.max() == pytest.approx(3 * WEIGHT, rel=1e-3)
    assert r_abs.min() <= 1e-3 * WEIGHT
    np.testing.assert_allclose(ds["Ft"].values, P.mu * r_abs, rtol=1e-12)
    # the mean of |R| over whole periods is m g (docs/model-facts.md, fact 4)
    t = ds["time"].values
    whole = t <= 3 * float(ds["period"])
    mean = np.trapezoid(r_abs[whole], t[whole]) / (t[whole][-1] - t[whole][0])
    assert mean == pytest.approx(WEIGHT, rel=1e-3)


def test_fig3_scales_with_mu():
    _fig, ds = figure3(P.replace(mu=0.3))
    assert float(ds["Ft"].max()) == pytest.approx(0.3 * 3 * WEIGHT, rel=1e-3)


@pytest.mark.parametrize("name", ("fig4", "fig5", "fig6"))
def test_slider_never_moves_backwards_and_sticks_exactly(data, name):
    ds = data[name].transpose(..., "time")
    x = ds["x"].values.reshape(-1, ds.sizes["time"])
    xdot = ds["xdot"].values.reshape(x.shape)
    state = ds["state"].values.reshape(x.shape)
    ft = ds["Ft"].values.reshape(x.shape)
    limit = ds["friction_limit"].values.reshape(x.shape)
    force = float(ds["force"])
    assert force == F
    assert np.all(np.diff(x, axis=-1) >= 0.0)
    assert np.all(xdot >= -1e-15)
    stick = state == STICK
    held = stick[:, 1:] & stick[:, :-1]
    assert np.all(np.diff(x, axis=-1)[held] == 0.0)  # stick phases are flat
    assert np.all(xdot[stick] == 0.0)
    np.testing.assert_array_equal(ft[stick], -force)
    slip = state == SLIP
    np.testing.assert_allclose(ft[slip], -limit[slip], rtol=1e-12)
    assert np.all(np.abs(ft) <= limit * (1 + 1e-12) + 1e-15)  # Coulomb (2.2)


def test_fig4_columns(data):
    ds = data["fig4"]
    np.testing.assert_allclose(ds["amplitude"].values, Y0 * np.array([0, 1, 2, 3]) / 3)
    still = ds.isel(amplitude=0)
    assert np.all(still["x"].values == 0.0) and np.all(still["xdot"].values == 0.0)
    assert np.all(still["state"].values == STICK)
    np.testing.assert_allclose(still["R"].values, WEIGHT, rtol=1e-12)
    distance = ds["slip_distance"].values
    assert distance[0] == 0.0 and np.all(np.diff(distance) > 0)
    final = ds["x"].isel(time=-1).values
    assert final[0] == 0.0 and np.all(np.diff(final) > 0)
    for k in (1, 2, 3):
        column = ds.isel(amplitude=k)
        assert np.any(column["state"].values == STICK)  # stick-slip, once per period
        steps = np.diff(plateaus(column["x"].values, column["state"].values))
        assert steps.size >= 5
        # each cycle after the first slides the exact steady distance (docs/model-facts.md, fact 6)
        np.testing.assert_allclose(steps, distance[k], rtol=1e-6)
        assert ds["mean_velocity"].values[k] == pytest.approx(
            ms.mean_velocity(P, force=F, amplitude=float(column["amplitude"])), rel=1e-12
        )


def test_fig5_slip_phases_follow_the_steady_cycle(data):
    ds = data["fig5"]
    np.testing.assert_allclose(ds["amplitude"].values, Y0 * np.array([2, 3]) / 3)
    for k in range(2):
        column = ds.isel(amplitude=k)
        cycle = ms.stick_slip_cycle(P, force=F, amplitude=float(column["amplitude"]))
        x_rel = column["x_from_release"].values
        state = column["state"].values
        # at each stick start (after the first slip) x_from_release is the slip distance
        starts = np.flatnonzero((state[1:] == STICK) & (state[:-1] != STICK)) + 1
        ends = x_rel[starts][1:]
        assert ends.size >= 2
        np.testing.assert_allclose(ends, cycle.slip_distance, rtol=1e-6)
        steady = np.isfinite(x_rel) & (column["time"].values > column["time"].values[starts[0]])
        assert np.nanmax(column["xdot"].values[steady]) == pytest.approx(
            cycle.peak_velocity, rel=1e-4
        )


def test_fig6_loses_contact_and_drifts(data):
    ds = data["fig6"]
    assert float(ds["amplitude"]) == pytest.approx(1.3 * Y0)
    state = ds["state"].values
    flight = state == FLIGHT
    assert flight.any() and (state == STICK).any()
    assert ds["y"].values.min() == pytest.approx(-0.3 * Y0, rel=1e-6)
    assert np.all(ds["R"].values[flight] == 0.0) and np.all(ds["Ft"].values[flight] == 0.0)
    np.testing.assert_allclose(ds["xddot"].values[flight], F / P.mass, rtol=1e-12)
    x = ds["x"].values
    assert x[-1] > 0.0
    steps = np.diff(plateaus(x, state))
    assert steps.size >= 4
    np.testing.assert_allclose(steps, steps[-1], rtol=1e-6)  # periodic drift
    assert steps[-1] == pytest.approx(
        ms.stick_slip_cycle(P, force=F, amplitude=1.3 * Y0).slip_distance, rel=1e-6
    )
