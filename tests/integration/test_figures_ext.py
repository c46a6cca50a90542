"""The extensions' figures (``microslip figures --extensions``, ``make figures-ext``): files,
units on every axis, and the data behind each against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from cli_inprocess import run

import microslip as ms
from microslip.cli.commands import ALL_FIGURES, EXTENSION_FIGURES
from microslip.plotting import extensions, figures
from microslip.plotting.response import fold_indices

P = ms.Parameters()
F0 = P.natural_frequency
Y0 = P.static_deflection


def test_the_registries_agree():
    assert EXTENSION_FIGURES == figures.EXTENSION_FIGURES == extensions.EXTENSION_FIGURES
    assert not set(EXTENSION_FIGURES) & set(ALL_FIGURES)  # `make paper` draws only the paper's


@pytest.fixture(scope="module")
def response():
    return extensions.forced_response_figure(P)


def _labels_have_units(fig):
    for ax in fig.axes:
        for label in (ax.get_xlabel(), ax.get_ylabel()):
            if label:
                assert "[" in label and "]" in label, label


def test_frequency_response_levels_and_linear_limit(response):
    fig, ds = response
    _labels_have_units(fig)
    levels = np.unique(ds["excitation_amplitude"].values)
    np.testing.assert_allclose(levels, extensions.FORCING_LEVELS, rtol=1e-12)
    for k, level in enumerate(extensions.FORCING_LEVELS):
        branch = ds.where(ds["branch"] == k, drop=True)
        f = branch["frequency"].values
        assert f[0] == pytest.approx(0.6 * F0, rel=1e-12)
        assert f[-1] == pytest.approx(1.4 * F0, rel=1e-9)
        # the linear oscillator limit, computed here from K_n = m2 m g / y0
        k_n = P.m2 * P.mass * P.g / Y0
        c = 2.0 * 0.03 * math.sqrt(k_n * P.mass)
        w = 2.0 * np.pi * f
        linear = level / np.sqrt((k_n - P.mass * w * w) ** 2 + (c * w) ** 2)
        np.testing.assert_allclose(branch["linear_amplitude"].values, linear, rtol=1e-12)
        if level == 0.05:  # small forcing: the response is the linear one
            np.testing.assert_allclose(branch["amplitude"].values, linear, rtol=1e-2)
    # P0 = 1 N leans over: two folds, contact lost near the top; the smaller ones do not
    folds = fold_indices(ds)
    assert len(folds) == 2
    assert set(ds["branch"].values[folds]) == {3}
    lost = ds["contact_lost"].values.astype(bool)
    assert lost.any() and set(ds["branch"].values[lost]) == {3}


def test_contact_loss_history():
    fig, ds = extensions.contact_loss_figure(P)
    _labels_have_units(fig)
    flight = ds["state"].values == 2
    n = ds["N"].values
    assert ds["N"].attrs["units"] == "N"
    assert flight.any() and not flight.all()
    np.testing.assert_array_equal(n[flight], 0.0)  # no adhesion: N = 0 in flight
    spans = [p for p in fig.axes[0].patches]
    starts = np.flatnonzero(np.diff(np.r_[0, flight.astype(int)]) == 1)
    assert len(spans) == starts.size  # one shaded span per flight
    assert ds.attrs["excitation"] == "HarmonicForce"


def test_velocity_map_under_excitation():
    fig, ds = extensions.forced_velocity_map_figure(P)
    _labels_have_units(fig)
    v = ds["mean_velocity"]
    assert v.attrs["units"] in ("m s-1", "m/s")
    assert v.size == extensions.MAP_FREQUENCIES.size * extensions.MAP_FORCES.size
    values = v.values
    assert np.all(np.isfinite(values)) and np.all(values >= 0.0)
    # more force, never slower (at each frequency)
    force_axis = v.dims.index("force")
    assert np.all(np.diff(values, axis=force_axis) >= -1e-15)


def test_figures_extensions_command(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    status, _, err = run(capsys, "figures", "--extensions", "--only",
                           "forced_response,contact_loss", "--dpi", "30", "--quiet")  # fmt: skip
    assert status == 0, err
    ext = tmp_path / "figures" / "ext"  # the default directory of the extensions
    names = sorted(p.name for p in ext.iterdir())
    assert names == ["contact_loss.nc", "contact_loss.png", "forced_response.nc",
                     "forced_response.png"]  # fmt: skip
    with xr.open_dataset(ext / "forced_response.nc") as ds:
        assert all("units" in ds[name].attrs for name in ds.data_vars)


def test_figures_extensions_friction_figures(capsys, tmp_path, monkeypatch):
    """The friction figures (plotting/friction.py) are registered: PNG + NetCDF with units."""
    assert {"friction_master_curve", "mu_eff_map", "spring_stick_slip"} <= set(EXTENSION_FIGURES)
    monkeypatch.chdir(tmp_path)
    status, _, err = run(capsys, "figures", "--extensions", "--only", "spring_stick_slip",
                         "--dpi", "30", "--quiet")  # fmt: skip
    assert status == 0, err
    ext = tmp_path / "figures" / "ext"
    assert sorted(p.name for p in ext.iterdir()) == ["spring_stick_slip.nc",
                                                     "spring_stick_slip.png"]  # fmt: skip
    with xr.open_dataset(ext / "spring_stick_slip.nc") as ds:
        assert all("units" in ds[name].attrs for name in ds.data_vars)
        mg = P.mass * P.g
        drop = 2 * (ds.attrs["friction_mu_static"] - ds.attrs["friction_mu_kinetic"]) * mg
        assert float(ds["force_drop"].sel(case=0)) == pytest.approx(drop, rel=1e-8)


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--extensions", "--only", "fig2"], ["unknown figure 'fig2' of --extensions"]),
        (["--only", "contact_loss"], ["unknown figure 'contact_loss'"]),
        (["--extensions", "--mu", "0", "--only", "contact_loss"], ["contact_loss", "mu = 0"]),
        (
            ["--extensions", "--mu", "0", "--only", "mu_eff_map,spring_stick_slip"],
            ["mu_eff_map", "spring_stick_slip", "mu = 0"],
        ),
    ],
)
def test_figures_extensions_refusals(capsys, tmp_path, monkeypatch, args, words):
    monkeypatch.chdir(tmp_path)
    status, _, err = run(capsys, "figures", *args)
    assert status == 2, err
    assert len(err.strip().splitlines()) == 1
    for word in words:
        assert word in err, (word, err)
    assert list(tmp_path.iterdir()) == []
