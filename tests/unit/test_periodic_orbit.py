"""periodic_orbit, orbit_state and forced_response: contracts and input checks."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import microslip as ms
from microslip.analysis.forced_response import forced_response
from microslip.analysis.orbit_table import orbit_state
from microslip.analysis.periodic import (
    NotPeriodOneError,
    periodic_orbit,
    transient_states,
)
from microslip.model.normal import normal_acceleration

P = ms.Parameters()
F0 = P.natural_frequency
Y0 = P.static_deflection
FORCED = ms.Model(P, ms.Viscous(0.05), ms.HarmonicForce(3.0, 0.95 * F0))  # loses contact


def test_orbit_state_reproduces_a_quintic_exactly():
    coef = np.array([0.3, -1.2, 0.7, 2.0, -0.5, 1.1])
    poly = np.polynomial.Polynomial(coef)
    t = np.array([0.0, 0.3, 0.35, 1.0])
    d1, d2 = poly.deriv(), poly.deriv(2)
    args = (t, poly(t), d1(t), d2(t[:-1]), d2(t[1:]))
    for x in (0.0, 0.1, 0.31, 0.349, 0.7, 1.0):
        y, yd = orbit_state(x, *args)
        assert abs(y - poly(x)) <= 1e-13 and abs(yd - d1(x)) <= 1e-12


def test_orbit_contract():
    orbit = periodic_orbit(FORCED)
    T = 1.0 / (0.95 * F0)
    assert orbit.period == pytest.approx(T, rel=1e-15)
    assert orbit.t[0] == 0.0 and orbit.t[-1] == pytest.approx(T, rel=1e-14)
    assert np.all(np.diff(orbit.t) >= 0.0) and orbit.accel_start.size == orbit.t.size - 1
    scale = np.array([Y0, Y0 * 2.0 * math.pi * F0])
    assert np.all(
        np.abs((np.array([orbit.y[-1], orbit.ydot[-1]]) - orbit.y0_state) / scale) < 1e-11
    )
    assert orbit.y0_state[0] == orbit.y[0]
    c = FORCED.pack(0.0)
    # Accelerations at the nodes: the model's law away from the contact switches.
    for k in range(0, orbit.t.size - 1, 7):
        a = normal_acceleration(orbit.t[k], orbit.y[k], orbit.ydot[k], c)
        assert orbit.accel_start[k] == pytest.approx(a, rel=1e-9, abs=1e-9 * P.g)
    assert orbit.y_min <= orbit.y.min() and orbit.y_max >= orbit.y.max()
    assert orbit.contact_lost and orbit.stable and orbit.period_one
    assert orbit.max_multiplier == pytest.approx(np.abs(orbit.multipliers).max())
    # det Φ = exp(-∫ (∂N/∂ẏ)/m dt) < 1 with damping.
    assert 0.0 < abs(np.prod(orbit.multipliers)) < 1.0


def test_transients_side_by_side_give_the_same_orbits():
    """transient_states integrates the first transients side by side, each row in its
    own step count (two here: two frequencies); each orbit from it is the orbit alone,
    bit for bit."""
    models = [
        FORCED,
        FORCED.replace(**{"excitation.amplitude": 1.0}),
        FORCED.replace(**{"excitation.frequency": 0.5 * F0}),
    ]
    states = transient_states(models)
    for model, state in zip(models, states, strict=True):
        alone = periodic_orbit(model)
        batched = periodic_orbit(model, transient_state=state)
        np.testing.assert_array_equal(batched.y0_state, alone.y0_state)
        np.testing.assert_array_equal(batched.y, alone.y)
        np.testing.assert_array_equal(batched.multipliers, alone.multipliers)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"transient_state": [Y0, 0.0], "initial_state": (Y0, 0.0)}, "initial_state"),
        ({"transient_state": [Y0, 0.0], "transient_periods": 8}, "transient_periods"),
        ({"transient_state": [Y0, math.nan]}, "two finite numbers"),
        ({"transient_state": [Y0]}, "two finite numbers"),
    ],
)
def test_transient_state_refusals(kwargs, match):
    with pytest.raises(ValueError, match=match) as info:
        periodic_orbit(FORCED, **kwargs)
    assert "\n" not in str(info.value)


def test_undamped_orbit_is_neutral():
    orbit = periodic_orbit(ms.Model(P, None, ms.HarmonicForce(0.05, 0.5 * F0)), transient_periods=0)
    assert abs(abs(np.prod(orbit.multipliers)) - 1.0) < 1e-10  # area preserving


def test_prescribed_penetration_is_closed_form():
    model = ms.Model(P, None, ms.PrescribedPenetration(Y0, 1.5 * Y0, F0))
    orbit = periodic_orbit(model)
    expected = Y0 + 1.5 * Y0 * np.cos(2.0 * math.pi * F0 * orbit.t)
    assert np.allclose(orbit.y, expected, rtol=0, atol=1e-15 * Y0 * 10)
    assert orbit.multipliers.size == 0 and orbit.stable and orbit.contact_lost
    assert orbit.y_min == pytest.approx(-0.5 * Y0) and orbit.N_min == 0.0


def test_free_vibration_is_refused():
    with pytest.raises(ms.UnsupportedModelError, match="free_period"):
        periodic_orbit(ms.Model(P))
    with pytest.raises(ValueError, match="excitation=None"):
        forced_response(ms.Model(P), frequencies=(1000.0, 1200.0))


def test_not_period_one_error_is_a_value_error():
    assert issubclass(NotPeriodOneError, ValueError)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({}, "exactly one"),
        ({"frequencies": (1000.0, 1200.0), "amplitudes": (0.1, 0.2)}, "exactly one"),
        ({"frequencies": (1000.0, 1000.0)}, "distinct"),
        ({"frequencies": (1000.0, math.nan)}, "finite"),
        ({"frequencies": (-1.0, 1000.0)}, "frequencies must lie"),
        ({"frequencies": (1000.0, 2e7)}, "frequencies must lie"),
        ({"frequencies": 1000.0}, "pair"),
        ({"frequencies": (1000.0, 1200.0), "max_points": 0}, "max_points"),
        ({"frequencies": (1000.0, 1200.0), "max_points": 2.5}, "max_points"),
        ({"frequencies": (1000.0, 1200.0), "max_points": 10**6}, "max_points"),
        ({"amplitudes": (-1.0, 0.5)}, "excitation.amplitude"),
    ],
)
def test_forced_response_inputs(kwargs, match):
    with pytest.raises(ValueError, match=match):
        forced_response(FORCED, **kwargs)


def test_prescribed_penetration_has_nothing_to_continue():
    model = ms.Model(P, None, ms.PrescribedPenetration(Y0, 0.1 * Y0, F0))
    with pytest.raises(ms.UnsupportedModelError, match="PrescribedPenetration"):
        forced_response(model, frequencies=(1000.0, 1200.0))


def test_dataset_layout_and_amplitude_branch():
    model = ms.Model(P, ms.HuntCrossley(0.05), ms.HarmonicForce(0.1, 0.8 * F0))
    ds = forced_response(model, amplitudes=(0.1, 2.0))
    assert float(ds.excitation_amplitude[0]) == 0.1 and float(ds.excitation_amplitude[-1]) == 2.0
    assert np.all(ds.frequency.values == 0.8 * F0)
    for name, var in ds.data_vars.items():
        assert "units" in var.attrs and "long_name" in var.attrs, name
    assert ds.excitation_amplitude.attrs["units"] == "N" and ds.amplitude.attrs["units"] == "m"
    assert ds.attrs["Conventions"] == "CF-1.10" and ds.attrs["damping"] == "HuntCrossley"
    assert np.all(np.diff(ds.amplitude.values) > 0)  # grows with the force


def test_point_cap_warns():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = forced_response(FORCED, frequencies=(0.9 * F0, 1.4 * F0), max_points=3)
    assert ds.sizes["point"] == 3 and ds.attrs["complete"] == 0
    assert any("max_points" in str(w.message) for w in caught)


@pytest.mark.parametrize(
    "model",
    [
        # Kelvin–Voigt under base motion: separation where N_raw = 0 while δ > 0, touchdown
        # with a force jump on a moving surface (saltation with ∂g/∂t).
        ms.Model(P, ms.Viscous(0.1), ms.BaseMotion(Y0, 0.7 * F0)),
        ms.Model(P, ms.HuntCrossley(0.1), ms.HarmonicForce(8.0, 0.7 * F0)),
    ],
    ids=["kv_base_loss", "hc_force_loss"],
)
def test_monodromy_is_the_derivative_of_the_flow_map(model):
    """Φ from the variational equations (with saltation) equals a central difference of
    the same fixed-step flow map: any mismatch between the integrated field and its
    Jacobian, or a wrong saltation at a switch, shows as an O(step) or O(1) difference."""
    from microslip.analysis.normal_flow import S_EVENTS, propagate
    from microslip.analysis.periodic import state_scale, steps_per_period

    orbit = periodic_orbit(model)
    c, n = model.pack(0.0), steps_per_period(model)
    s = orbit.y0_state
    _, phi, _, _, summary = propagate(c, s[0], s[1], 0.0, orbit.period, n, False, True)
    assert summary[S_EVENTS] == 2.0  # one separation and one touchdown per period
    scale = state_scale(model)
    fd = np.empty((2, 2))
    for j in range(2):
        d = np.zeros(2)
        d[j] = 1e-6 * scale[j]
        plus = propagate(c, *(s + d), 0.0, orbit.period, n, False, False)[0]
        minus = propagate(c, *(s - d), 0.0, orbit.period, n, False, False)[0]
        fd[:, j] = (plus - minus) / (2.0 * d[j])
    # Compare in the scaled state, where the entries are O(1).
    to_scaled = scale[np.newaxis, :] / scale[:, np.newaxis]
    assert np.max(np.abs((phi - fd) * to_scaled)) < 1e-7, (phi, fd)
    assert np.allclose(
        np.sort_complex(orbit.multipliers),
        np.sort_complex(np.linalg.eigvals(fd)),
        rtol=0,
        atol=1e-7,
    )


def test_each_point_is_integrated_in_the_steps_of_its_own_frequency(monkeypatch):
    """A frequency branch integrates each point's period in steps_per_period at that
    point's frequency (96 per natural period, at least 64), the residual's two flows
    (at λ and λ + h) in the same count: not the count of the branch's lowest frequency
    everywhere (at 2 f0, 6x the work on a 0.3 f0 start), and not a count that differs
    between the two flows of a difference quotient."""
    from microslip.analysis import forced_response as module
    from microslip.analysis.periodic import steps_per_period

    calls = []
    original = module.propagate_each

    def spy(cs, starts, durations, n_steps, *rest):
        calls.append((durations.copy(), np.array(n_steps)))
        return original(cs, starts, durations, n_steps, *rest)

    monkeypatch.setattr(module, "propagate_each", spy)
    result = forced_response(FORCED, frequencies=(0.3 * F0, 0.6 * F0), max_step=0.2)
    assert result.attrs["complete"] == 1
    residuals, record = calls[:-1], calls[-1]
    seen = set()
    rows = [(d[0], n[0]) for d, n in residuals] + list(zip(*record, strict=True))
    for period, n in rows:  # a residual's first flow is at λ, its second at λ + h
        assert n == steps_per_period(FORCED, 1.0 / period)
        seen.add(int(n))
    for _durations, n_steps in residuals:
        assert n_steps[0] == n_steps[1]
    # the branch's two ends: 320 steps at 0.3 f0, 160 at 0.6 f0
    assert max(seen) == steps_per_period(FORCED, 0.3 * F0) == 320
    assert min(seen) <= steps_per_period(FORCED, 0.59 * F0) < 170
