"""The tutorial (docs/tutorial/tutorial.py) runs, and what it shows the reader is true.

The tutorial is a jupytext percent script; the docs build executes it as a notebook
(myst-nb). Here it runs as a plain script in a scratch directory, and the values it
computes are checked against closed forms and quadratures computed here, independently
of microslip: the working point (Sec. 3), the exact free period (energy integral,
docs/model-facts.md fact 2), the motion threshold (eq. 4.2), and the claims its text
makes (a time average tends to the exact mean velocity, the Dask sweep equals the
in-process one bit for bit, the strong forcing folds twice).
"""

from __future__ import annotations

import math
import os
import runpy
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

ROOT = Path(__file__).resolve().parents[2]
TUTORIAL = ROOT / "docs" / "tutorial" / "tutorial.py"


@pytest.fixture(scope="module")
def tutorial(tmp_path_factory) -> dict:
    """The tutorial's global variables after running it as a script."""
    work = tmp_path_factory.mktemp("tutorial")
    old = Path.cwd()
    os.chdir(work)
    try:
        names = runpy.run_path(str(TUTORIAL), run_name="tutorial")
    finally:
        os.chdir(old)
    names["_work"] = work
    return names


def _free_period(p, amplitude: float) -> float:
    """T(A) = 2 ∫ dy / sqrt(2 (E - V(y)) / m) between the turning points (no contact loss)."""
    sc, m2, mg = p.area * p.c_n, p.m2, p.mass * p.g

    def potential(y):
        return sc * max(y, 0.0) ** (m2 + 1) / (m2 + 1) - mg * y

    y0 = (mg / sc) ** (1 / m2)
    top = y0 - amplitude
    energy = potential(top)
    bottom = brentq(lambda y: potential(y) - energy, y0, 10 * y0, xtol=1e-30, rtol=1e-15)

    # y = mid - half cos θ removes the inverse-square-root singularities at both ends
    mid, half = 0.5 * (top + bottom), 0.5 * (bottom - top)

    def integrand(theta):
        y = mid - half * math.cos(theta)
        kinetic = max(energy - potential(y), 0.0)
        return half * math.sin(theta) / math.sqrt(2 * kinetic / p.mass) if kinetic > 0 else 0.0

    value, _ = quad(integrand, 0.0, math.pi, epsabs=0.0, epsrel=1e-12, limit=200)
    return 2 * value


def test_the_tutorial_is_a_percent_notebook():
    import jupytext  # the docs extra, part of the dev extra

    notebook = jupytext.read(TUTORIAL, fmt="py:percent")
    kinds = [cell.cell_type for cell in notebook.cells]
    assert kinds.count("code") >= 10 and kinds.count("markdown") >= 10
    assert notebook.metadata["kernelspec"]["name"] == "python3"
    assert "%matplotlib inline" in notebook.cells[1].source  # un-commented for Jupyter


def test_working_point_is_the_papers(tutorial):
    p = tutorial["p"]
    y0 = (p.mass * p.g / (p.area * p.c_n)) ** (1 / p.m2)
    assert tutorial["y0"] == pytest.approx(y0, rel=1e-14)
    assert y0 == pytest.approx(2.25e-7, rel=2e-3)  # Sec. 3
    f0 = math.sqrt(p.m2 * p.g / y0) / (2 * math.pi)
    assert p.natural_frequency == pytest.approx(f0, rel=1e-13)
    assert round(f0) == 1485  # Sec. 3


def test_backbone_value_is_the_energy_integral(tutorial):
    p = tutorial["p"]
    amplitude = 0.05 * tutorial["y0"]
    period = _free_period(p, amplitude)
    assert tutorial["backbone_small"] == pytest.approx(1 / (period * p.natural_frequency), rel=1e-9)


def test_time_average_tends_to_the_exact_mean_velocity(tutorial):
    v_exact, v_time = tutorial["v_exact"], tutorial["v_time"]
    assert v_exact > 0
    assert v_time == pytest.approx(v_exact, rel=1e-4)


def test_threshold_and_map_follow_eq_4_2(tutorial):
    p = tutorial["p"]
    sc = p.area * p.c_n
    y0 = tutorial["y0"]
    amplitude = tutorial["amplitude"]
    assert tutorial["threshold"] == pytest.approx(p.mu * sc * (y0 - amplitude) ** p.m2, rel=1e-12)
    vmap = tutorial["vmap"].transpose("force", "amplitude")
    forces = vmap["force"].values[:, None]
    amps = vmap["amplitude"].values[None, :]
    limit = p.mu * sc * np.maximum(y0 - amps, 0.0) ** p.m2
    values = vmap.values
    still = forces < limit * (1 - 1e-9)
    moving = forces > limit * (1 + 1e-9)
    assert still.any() and moving.any()
    assert np.all(values[still] == 0.0)
    assert np.all(values[moving] > 0.0)


def test_forced_orbit_is_stable_and_slides_below_mu_m_g(tutorial):
    orbit = tutorial["orbit"]
    assert orbit.stable and np.all(np.abs(orbit.multipliers) < 1)
    assert orbit.period == pytest.approx(1 / 1400.0, rel=1e-12)
    p = tutorial["p"]
    assert 0 < tutorial["v_forced"] < math.inf
    assert 0.8 < p.static_friction_force


def test_strong_forcing_folds_twice_inside_the_span(tutorial):
    response = tutorial["response"]
    folds = tutorial["folds"]
    assert len(folds) == 2
    f = response["frequency"].values
    assert f[0] == pytest.approx(1100.0) and f[-1] == pytest.approx(1600.0)
    assert all(1100.0 < f[i] < 1600.0 for i in folds)
    assert not response["stable"].values.all()  # the middle branch between the folds


def test_dask_sweep_equals_in_process_and_round_trips_netcdf(tutorial):
    import xarray as xr

    on_cluster, in_process = tutorial["on_cluster"], tutorial["in_process"]
    assert on_cluster.dims == ("mu", "m2", "force", "amplitude")
    assert np.array_equal(on_cluster.values, in_process.values)  # bit for bit, no NaN
    assert np.isfinite(on_cluster.values).all()
    # no vibration (A = 0) and F < μ m g: the slider never moves, for every μ and m2
    assert np.all(on_cluster.sel(amplitude=0.0).values == 0.0)
    work = tutorial["_work"]
    with xr.open_dataset(work / "sweep.nc") as back:
        assert np.array_equal(back["mean_velocity"].values, on_cluster.values)
        assert back["mean_velocity"].attrs["units"] == "m s-1"
    assert (work / "sweep.partial.zarr").is_dir()
