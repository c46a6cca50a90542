"""Identity 7: spring-driven stick–slip at constant N (docs/theory/stick_slip_drive.md).

A rigid-contact block, undamped, static/kinetic friction μ_s > μ_k, pulled through a
spring k_d whose far end moves at v_d. With Δ = (μ_s − μ_k) N / k_d and ω = sqrt(k_d/m),
each slip is part of a harmonic oscillation about the kinetic equilibrium, from velocity
0 at the spring force μ_s N to velocity 0 at (2 μ_k − μ_s) N:

    force drop    2 (μ_s − μ_k) N            (every drive velocity)
    stick time    2 Δ / v_d
    slip time     (2/ω) (π − arctan(Δ ω / v_d))
    period        stick time + slip time,    slip distance v_d · period
    first slip    μ_s N / (k_d v_d)          (from a relaxed spring)

Checked for Δ ω / v_d from 100 (slow drive: slip time → π/ω) to 0.1 (fast: → 2π/ω),
with N = m g (rest at y0) and N = S c_n δ_m^m2 (a prescribed penetration of amplitude 0).
"""

import math

import numpy as np
import pytest

import microslip as ms
from microslip.analysis.spring_stick_slip import stick_slip_drive
from microslip.analysis.stick_slip_closed_form import constant_normal_cycle

P = ms.Parameters()
Y0 = P.static_deflection
T0 = P.natural_period
MU_S, MU_K = 0.15, 0.1
K_D = 1e6  # N/m: ω = 1000 rad/s
NAMES = ms.integrators.EVENT_NAMES
RATIOS = [100.0, 10.0, 1.0, 0.1]  # Δ ω / v_d


def closed_form(normal, velocity, stiffness=K_D, mass=P.mass):
    omega = math.sqrt(stiffness / mass)
    half = (MU_S - MU_K) * normal / stiffness
    stick = 2.0 * half / velocity
    slip = 2.0 / omega * (math.pi - math.atan(half * omega / velocity))
    return {
        "drop": 2.0 * (MU_S - MU_K) * normal,
        "stick": stick,
        "slip": slip,
        "period": stick + slip,
        "first": MU_S * normal / (stiffness * velocity),
        "omega": omega,
        "half": half,
    }


def model_and_normal(kind, velocity):
    drive = ms.SpringDrive(stiffness=K_D, velocity=velocity)
    friction = ms.StaticKinetic(mu_static=MU_S, mu_kinetic=MU_K)
    if kind == "rest":
        return ms.Model(P, friction=friction, drive=drive), {"amplitude": 0.0}, P.mass * P.g
    mean = 1.5 * Y0
    excitation = ms.PrescribedPenetration(mean=mean, amplitude=0.0, frequency=P.natural_frequency)
    normal = P.stiffness_coefficient * mean**P.m2
    return ms.Model(P, excitation=excitation, friction=friction, drive=drive), {}, normal


def velocity_for(ratio, normal):
    omega = math.sqrt(K_D / P.mass)
    return (MU_S - MU_K) * normal / K_D * omega / ratio


def cycles(result, velocity):
    """Per slip: (start time, end time, F at start, F at end, x at start, x at end)."""
    kinds = result.event_kind
    starts = np.flatnonzero(kinds == NAMES.index("slip_start"))
    ends = np.flatnonzero(kinds == NAMES.index("stick_start"))
    n = min(starts.size, ends.size)
    t_s, t_e = result.event_t[starts[:n]], result.event_t[ends[:n]]
    x_s, x_e = result.event_states[starts[:n], 2], result.event_states[ends[:n], 2]
    return t_s, t_e, K_D * (velocity * t_s - x_s), K_D * (velocity * t_e - x_e), x_s, x_e


def relative_errors(result, velocity, expected):
    t_s, t_e, f_s, f_e, x_s, x_e = cycles(result, velocity)
    assert t_s.size >= 5
    return {
        "drop": np.max(np.abs((f_s - f_e) / expected["drop"] - 1.0)),
        "period": np.max(np.abs(np.diff(t_s) / expected["period"] - 1.0)),
        "slip": np.max(np.abs((t_e - t_s) / expected["slip"] - 1.0)),
        "stick": np.max(np.abs((t_s[1:] - t_e[:-1]) / expected["stick"] - 1.0)),
        "first": abs(t_s[0] / expected["first"] - 1.0),
        "distance": np.max(np.abs((x_e - x_s) / (velocity * expected["period"]) - 1.0)),
    }


@pytest.mark.parametrize("kind", ["rest", "prescribed"])
@pytest.mark.parametrize("ratio", RATIOS)
def test_event_method_matches_closed_form(kind, ratio):
    _m, _kw, normal = model_and_normal(kind, 1.0)
    velocity = velocity_for(ratio, normal)
    model, kwargs, normal = model_and_normal(kind, velocity)
    expected = closed_form(normal, velocity)
    duration = expected["first"] + 6.2 * expected["period"]
    result = ms.simulate(model, duration=duration, **kwargs)
    errors = relative_errors(result, velocity, expected)
    # measured <= 2.2e-12 (the drop at Δω/v_d = 0.1), the rest <= 2e-14
    assert max(errors.values()) < 1e-9, errors


def rk4_bound(expected, velocity, dt):
    """RK4's phase error (ω dt)^4/120 per radian over the slip's ω t_slip radians, times
    1 + v_d/(Δ ω): a fast drive stops with a small deceleration Δ ω² against a speed
    of order v_d, so a speed error moves the stop that much more; plus rounding."""
    omega, half = expected["omega"], expected["half"]
    phase = (omega * dt) ** 4 / 120.0 * omega * expected["slip"]
    return phase * (1.0 + velocity / (half * omega)) + 1e-11


@pytest.mark.parametrize("divisions", [10, 20, 200])  # dt = T0 / n (200: the default)
@pytest.mark.parametrize("ratio", RATIOS)
def test_rk4_matches_closed_form_to_its_order(ratio, divisions):
    model, kwargs, normal = model_and_normal("rest", velocity_for(ratio, P.mass * P.g))
    velocity = model.drive.velocity
    expected = closed_form(normal, velocity)
    dt = T0 / divisions
    duration = expected["first"] + 6.2 * expected["period"]
    result = ms.simulate(model, duration=duration, method="rk4", dt=dt, **kwargs)
    errors = relative_errors(result, velocity, expected)
    # measured: at most 0.26 of the bound (drop, Δω/v_d = 0.1, dt = T0/10)
    assert max(errors.values()) < rk4_bound(expected, velocity, dt), errors


@pytest.mark.parametrize("ratio", [100.0, 0.1])
def test_analysis_returns_the_closed_form(ratio):
    velocity = velocity_for(ratio, P.mass * P.g)
    model, _kw, normal = model_and_normal("rest", velocity)
    expected = closed_form(normal, velocity)
    cycle = stick_slip_drive(model, cycles=4, transient_cycles=1)
    assert cycle.regime == "stick-slip"
    assert cycle.force_drop == pytest.approx(expected["drop"], rel=1e-9)
    assert cycle.period == pytest.approx(expected["period"], rel=1e-9)
    assert cycle.stick_time == pytest.approx(expected["stick"], rel=1e-9)
    assert cycle.slip_time == pytest.approx(expected["slip"], rel=1e-9)
    assert cycle.slip_distance == pytest.approx(velocity * expected["period"], rel=1e-9)
    assert cycle.peak_force == pytest.approx(MU_S * normal, rel=1e-9)
    assert cycle.mean_velocity == pytest.approx(velocity, rel=1e-9)
    assert math.isnan(cycle.slips_per_normal_period)
    form = constant_normal_cycle(model)
    assert form.period == pytest.approx(expected["period"], rel=1e-14)
    assert form.force_drop == pytest.approx(expected["drop"], rel=1e-14)
    assert form.first_slip_time == pytest.approx(expected["first"], rel=1e-14)


def test_drop_does_not_depend_on_drive_velocity_and_slow_limit():
    """The drop is 2(μ_s − μ_k)N from slow to fast; the slow slip lasts half a period."""
    drops = []
    for ratio in (1000.0, 0.05):
        velocity = velocity_for(ratio, P.mass * P.g)
        model, kwargs, normal = model_and_normal("rest", velocity)
        expected = closed_form(normal, velocity)
        result = ms.simulate(model, duration=expected["first"] + 3.2 * expected["period"], **kwargs)
        t_s, t_e, f_s, f_e, _xs, _xe = cycles(result, velocity)
        drops.append(f_s - f_e)
        if ratio == 1000.0:
            np.testing.assert_allclose(t_e - t_s, math.pi / expected["omega"], rtol=1e-3)
    np.testing.assert_allclose(
        np.concatenate(drops), 2.0 * (MU_S - MU_K) * P.mass * P.g, rtol=1e-10
    )
