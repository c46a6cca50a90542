"""Fig. 7: the mean-velocity map v(F, A), checked against independent facts.

- docs/model-facts.md, fact 5: v = 0 exactly on the no-motion side of F = μ S c_n max(y0 - A, 0)^m2,
  v > 0 on the other; with loss of contact (A > y0) any F > 0 moves the slider.
- docs/model-facts.md, fact 7: in natural scales the map is μ y0 ω V(F/(μ m g), A/y0; m2), so maps
  for other μ, m, c_n, S, g follow from the paper's by scaling alone.
- The finite-time average of a time-domain run approaches the steady map.
"""

import math

import numpy as np
import pytest

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection


def test_zero_exactly_below_the_motion_threshold_and_positive_above():
    amplitudes = np.linspace(0.0, 1.5 * Y0, 31)
    thresholds = np.array([P.motion_threshold(a) for a in amplitudes])
    for factor, moves in ((1.0 - 1e-9, False), (1.0 + 1e-6, True)):
        forces = np.clip(thresholds * factor, 0.0, None)
        for force, amplitude in zip(forces, amplitudes, strict=True):
            if force >= P.static_friction_force or (amplitude > Y0 and not moves):
                continue
            v = ms.mean_velocity(P, force=float(force), amplitude=float(amplitude))
            if moves and force > 0:
                assert v > 0.0, (force, amplitude)
            else:
                assert v == 0.0, (force, amplitude)


def test_loss_of_contact_moves_for_any_force():
    v = ms.velocity_map(P, forces=[1e-6, 1e-3, 0.1], amplitudes=[1.01 * Y0, 1.3 * Y0])
    assert (v.values > 0).all()
    assert ms.velocity_map(P, forces=[0.0], amplitudes=[1.3 * Y0]).item() == 0.0


def test_map_is_monotone_in_force_and_amplitude():
    v = ms.velocity_map(
        P, forces=np.linspace(0.05, 0.95, 40), amplitudes=np.linspace(0.0, 3e-7, 40)
    ).values
    assert (np.diff(v, axis=0) >= 0).all()
    assert (np.diff(v, axis=1) >= 0).all()


@pytest.mark.parametrize(
    "changes",
    [
        {"mu": 0.25},
        {"mass": 3.0, "c_n": 1.0e16},
        {"area": 1.0e-3, "g": 3.7},
        {"mu": 0.05, "mass": 0.2, "c_n": 9.0e16},
    ],
)
def test_natural_scaling_of_the_map(changes):
    """v(F, A; params) = (μ y0 ω)' / (μ y0 ω) · v(F φ-scaled, A y0-scaled; paper)."""
    other = P.replace(**changes)
    phi = np.array([0.2, 0.45, 0.7, 0.9])  # F / (μ m g)
    a = np.array([0.15, 0.5, 0.9, 1.2])  # A / y0

    def scale(p):
        return p.mu * p.static_deflection * math.sqrt(p.g / p.static_deflection)

    v_paper = ms.velocity_map(
        P, forces=phi * P.static_friction_force, amplitudes=a * Y0
    ).values / scale(P)
    v_other = ms.velocity_map(
        other, forces=phi * other.static_friction_force, amplitudes=a * other.static_deflection
    ).values / scale(other)
    np.testing.assert_allclose(v_other, v_paper, rtol=1e-9, atol=1e-12 * np.abs(v_paper).max())


def test_sweep_over_parameters_equals_separate_maps():
    forces, amplitudes = [0.3, 0.6], [1e-7, 2.5e-7]
    swept = ms.sweep(P, {"mu": [0.08, 0.12], "m2": [1.8, 2.4]}, force=forces, amplitude=amplitudes)
    for mu in (0.08, 0.12):
        for m2 in (1.8, 2.4):
            single = ms.velocity_map(P.replace(mu=mu, m2=m2), forces=forces, amplitudes=amplitudes)
            np.testing.assert_array_equal(swept.sel(mu=mu, m2=m2).values, single.values)


def test_forces_above_mu_m_g_have_no_steady_state():
    with pytest.warns(RuntimeWarning, match="no steady state"):
        v = ms.velocity_map(P, forces=[0.5, 1.2], amplitudes=[1e-7])
    assert np.isinf(v.sel(force=1.2).values).all()
    assert np.isfinite(v.sel(force=0.5).values).all()


def test_time_domain_average_approaches_the_steady_map():
    forces = np.array([0.3, 0.5, 0.8])
    amplitudes = np.array([1e-7, 2e-7, 2.8e-7])
    steady = ms.velocity_map(P, forces=forces, amplitudes=amplitudes).values
    errors = []
    for duration in (0.02, 0.08):
        timed = ms.velocity_map(
            P, forces=forces, amplitudes=amplitudes, method="time", duration=duration
        ).values
        errors.append(np.abs(timed - steady).max() / steady.max())
    # the transient and the unfinished last cycle average out like 1/duration
    assert errors[1] < errors[0] / 2.5
    assert errors[1] < 2e-2
