"""mean_velocity on any model, friction_curve, and their refusals (sliding on a forced contact)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import microslip as ms
from microslip.analysis import sliding_tables
from microslip.analysis.forced_sliding import mean_velocities, sliding_table
from microslip.analysis.friction_curve import friction_curve
from microslip.analysis.periodic import NotPeriodOneError
from microslip.analysis.steady_state import mean_velocity, stick_slip_cycle
from microslip.model.capabilities import UnsupportedModelError

P = ms.Parameters()
FORCED = ms.Model(P, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(0.5, 1400.0))


def test_forced_model_refuses_an_amplitude_and_free_models_an_initial_state():
    with pytest.raises(ValueError, match=r"^amplitude=1e-07 applies to the free vibration"):
        mean_velocity(FORCED, force=0.5, amplitude=1e-7)
    with pytest.raises(ValueError, match="initial_normal_state applies to a model with"):
        mean_velocity(P, force=0.5, amplitude=1e-7, initial_normal_state=(0.0, 0.0))
    with pytest.raises(ValueError, match=r"amplitude \[m\] is required"):
        mean_velocity(ms.Model(P), force=0.5)


def test_stick_slip_cycle_is_paper_only():
    with pytest.raises(UnsupportedModelError, match="stick_slip_cycle does not support damping"):
        stick_slip_cycle(ms.Model(P, damping=ms.Viscous(0.1)), force=0.5, amplitude=1e-7)
    with pytest.raises(UnsupportedModelError, match="excitation=BaseMotion"):
        stick_slip_cycle(
            ms.Model(P, excitation=ms.BaseMotion(1e-8, 1400.0)), force=0.5, amplitude=1e-7
        )
    assert stick_slip_cycle(ms.Model(P), force=0.6, amplitude=1e-7).mean_velocity > 0


def test_damped_free_vibration_decays_to_rest():
    model = ms.Model(P, damping=ms.HuntCrossley(0.1))
    limit = P.mu * P.mass * P.g
    assert mean_velocity(model, force=0.99 * limit, amplitude=2e-7) == 0.0
    with pytest.warns(RuntimeWarning, match="no steady mean velocity"):
        assert mean_velocity(model, force=1.01 * limit) == math.inf
    with pytest.raises(ValueError, match="depends on the transient"):
        mean_velocity(model, force=limit, amplitude=1e-7)
    assert mean_velocity(model, force=limit, amplitude=0.0) == 0.0


def test_forced_model_beyond_mu_m_g_is_unbounded():
    with pytest.warns(RuntimeWarning, match="exceeds mu N_mean"):
        assert mean_velocity(FORCED, force=1.0) == math.inf


def test_mean_velocity_does_not_decrease_with_force():
    table = sliding_tables.model_sliding_table(FORCED)
    forces = np.linspace(0.0, P.mu * P.mass * P.g, 2001)
    v = mean_velocities(table, P.mu, forces)
    assert v[0] == 0.0 and v[-1] > 0.0 and np.all(np.isfinite(v))
    assert np.all(np.diff(v) >= 0.0)
    # No slip until μ N falls below F somewhere on the orbit.
    assert np.all(v[forces <= P.mu * table.min_normal_force] == 0.0)
    assert np.all(v[forces > P.mu * table.min_normal_force * 1.001] > 0.0)


def test_not_period_one_falls_back_to_a_time_average(monkeypatch):
    def refuse(model, initial_state=None):
        raise NotPeriodOneError("the response is period-2")

    class Run:
        t = np.array([0.05, 0.1])
        x = np.array([1e-6, 4e-6])

    calls = {}

    def fake_simulate(model, **kwargs):
        calls.update(kwargs)
        return Run()

    monkeypatch.setattr(sliding_tables, "model_sliding_table", refuse)
    monkeypatch.setattr("microslip.simulation.simulate", fake_simulate)
    with pytest.warns(RuntimeWarning, match="period-2; mean_velocity falls back to the time"):
        value = mean_velocity(FORCED, force=0.8)
    assert value == pytest.approx(3e-6 / 0.05, rel=1e-15)
    assert calls["force"] == 0.8
    assert calls["duration"] == pytest.approx(200 / 1400.0)


def test_sliding_table_refuses_bad_nodes():
    t = np.array([0.0, 1.0, 1.0])
    with pytest.raises(ValueError, match="increase strictly"):
        sliding_table(t, t, t, t[:-1], t[:-1], mass=1.0, gravity=9.81)


def test_friction_curve_at_fixed_force_is_the_scalar_mean_velocity():
    freqs = [1300.0, 1400.0, 1500.0]
    ds = friction_curve(FORCED, frequencies=freqs, force=0.8)
    assert ds["mean_velocity"].dims == ("frequency",)
    assert ds["frequency"].attrs["units"] == "Hz" and ds["mean_velocity"].attrs["units"] == "m s-1"
    assert ds.attrs["excitation"] == "HarmonicForce" and ds.attrs["damping_ratio"] == 0.05
    for f, value in zip(freqs, ds["mean_velocity"].values, strict=True):
        model = FORCED.replace(**{"excitation.frequency": f})
        assert value == mean_velocity(model, force=0.8)
    assert ds["period_one"].values.all()


def test_friction_curve_at_fixed_velocity_inverts_the_mean_velocity():
    freqs = np.array([1300.0, 1450.0])
    target = 1e-5
    ds = friction_curve(FORCED, frequencies=freqs, velocity=target)
    for name, unit in (("force_needed", "N"), ("mu_eff", "1"), ("mu_eff_ratio", "1")):
        assert ds[name].attrs["units"] == unit
    for f, needed in zip(freqs, ds["force_needed"].values, strict=True):
        model = FORCED.replace(**{"excitation.frequency": f})
        assert mean_velocity(model, force=needed) == pytest.approx(target, rel=1e-9)
        assert needed < P.mu * P.mass * P.g  # normal vibration lowers the friction
    assert np.allclose(ds["mu_eff"], ds["force_needed"] / (P.mass * P.g), rtol=1e-15)
    assert np.allclose(ds["mu_eff_ratio"], ds["mu_eff"] / P.mu, rtol=1e-15)


def test_friction_curve_refusals():
    with pytest.raises(ValueError, match="exactly one of force"):
        friction_curve(FORCED, frequencies=[1400.0], force=0.5, velocity=1e-5)
    with pytest.raises(UnsupportedModelError, match="friction_curve does not support excitation"):
        friction_curve(ms.Model(P), frequencies=[1400.0], force=0.5)
    with pytest.raises(ValueError, match=r"excitation\.frequency"):
        friction_curve(FORCED, frequencies=[1e9], force=0.5)
    with pytest.raises(ValueError, match="velocity must be > 0"):
        friction_curve(FORCED, frequencies=[1400.0], velocity=0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        friction_curve(FORCED, frequencies=[1400.0], force=0.5)  # no warning when fine
