"""``microslip map``/``sweep --method time`` with StaticKinetic friction: the file, the
figure (the no-sliding boundary on μ_s, the runaway region from μ_k m g), the refusals,
and the plot of a sweep over a part field."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from cli_inprocess import one_line_failure, run
from figure_lines import curves

import microslip as ms
from microslip.plotting import velocity_map_figure

P = ms.Parameters()
Y0 = P.static_deflection
MU_S, MU_K = 0.15, 0.1
STATIC_KINETIC = ["--friction", "static-kinetic", "--friction-mu-static", str(MU_S),
                  "--friction-mu-kinetic", str(MU_K)]  # fmt: skip
GRID = ["--force", "0.05:1.6:12", "--amplitude", "0:3e-7:6"]


def test_a_static_kinetic_time_map_and_its_figure(capsys, tmp_path):
    out, png = tmp_path / "map.nc", tmp_path / "map.png"
    status, _, err = run(capsys, "map", "--method", "time", *STATIC_KINETIC, *GRID,
                         "--duration", "0.003", "--out", out, "--plot", png)  # fmt: skip
    assert status == 0, err
    assert png.stat().st_size > 0
    with xr.open_dataset(out) as ds:
        ds = ds.load()
    assert ds.attrs["friction"] == "StaticKinetic"
    assert (ds.attrs["friction_mu_static"], ds.attrs["friction_mu_kinetic"]) == (MU_S, MU_K)
    assert ds["mean_velocity"].attrs["units"] == "m s-1"
    # The same numbers as the library's sweep of the same model.
    model = ms.Model(P, friction=ms.StaticKinetic(MU_S, MU_K))
    direct = ms.sweep(model, None, force=ds["force"].values, amplitude=ds["amplitude"].values,
                      method="time", duration=0.003)  # fmt: skip
    np.testing.assert_array_equal(
        ds["mean_velocity"].transpose(*direct.dims).values, np.asarray(direct.values)
    )
    fig = velocity_map_figure(ds, P)
    contour = fig.axes[1]
    assert "μ_s = 0.15, μ_k = 0.1" in contour.get_title()
    # No sliding below μ_s S c_n (y0 - A)^m2 (eq. 4.2 with the static coefficient).
    (boundary,) = curves(contour, "no-sliding boundary")
    a = np.asarray(boundary.get_ydata()) * 1e-6
    expected = MU_S * P.area * P.c_n * np.clip(Y0 - a, 0.0, None) ** P.m2
    np.testing.assert_allclose(boundary.get_xdata(), expected, rtol=1e-12, atol=1e-15)
    # The runaway region starts at μ_k m g.
    (hatch,) = [p for p in contour.patches if "μ_k m g" in str(p.get_label())]
    assert hatch.get_x() == pytest.approx(MU_K * P.mass * P.g, rel=1e-12)


@pytest.mark.parametrize(
    ("args", "words"),
    [
        # the exact steady state needs Coulomb friction
        (["map", *STATIC_KINETIC, *GRID, "--out", "m.nc"],
         ["--friction: microslip map does not support friction=StaticKinetic",
          "--method time", "static-kinetic"]),
        # the allowed friction law comes first; the refused part is the drive
        (["map", "--method", "time", *STATIC_KINETIC, "--drive", "harmonic", "--drive-mean",
          "0.5", "--drive-amplitude", "0.2", "--drive-frequency", "50", *GRID, "--out", "m.nc"],
         ["--drive: microslip map does not support drive=HarmonicDrive"]),
        (["map", "--method", "time", "--friction", "stribeck", "--friction-mu-static", "0.15",
          "--friction-mu-kinetic", "0.1", "--friction-velocity", "1e-3",
          "--friction-exponent", "2", *GRID, "--out", "m.nc"],
         ["--friction: microslip map does not support friction=Stribeck"]),
    ],
)  # fmt: skip
def test_refusals(capsys, tmp_path, monkeypatch, args, words):
    monkeypatch.chdir(tmp_path)
    status, stdout, err = run(capsys, *args)
    one_line_failure(status, err, *words)
    assert stdout == ""
    assert list(tmp_path.iterdir()) == []


def test_a_sweep_over_a_part_field_is_plotted(capsys, tmp_path):
    """A map per value of a part field (damping.ratio): the panels' parameters are the
    Parameters fields only. The plot used to fail with 'unknown parameter' after the
    whole sweep had run, and nothing was written."""
    out, png = tmp_path / "s.nc", tmp_path / "s.png"
    status, _, err = run(capsys, "sweep", "--method", "time", "--damping", "viscous",
                         "--param", "damping.ratio=0.01,0.05", "--force", "0.1:0.9:4",
                         "--amplitude", "0:2e-7:3", "--duration", "0.002", "--out", out,
                         "--plot", png)  # fmt: skip
    assert status == 0, err
    assert out.stat().st_size > 0 and png.stat().st_size > 0
