"""The sweep definition: validation, chunk geometry and identity."""

import numpy as np
import pytest

from microslip import Parameters
from microslip.sweeps import SweepSpec

F = np.linspace(0.1, 0.9, 5)
A = np.linspace(0.0, 3e-7, 10)


def test_chunks_cover_the_grid_exactly_once():
    spec = SweepSpec.build(None, {"mu": [0.1, 0.2], "m2": [1.5, 2.0, 2.5]}, F, A, amplitude_chunk=4)
    assert spec.dims == ("mu", "m2", "force", "amplitude")
    assert spec.shape == (2, 3, 5, 10)
    assert spec.chunk_grid == (2, 3, 3)
    covered = np.zeros(spec.shape, dtype=int)
    for key in spec.chunks():
        covered[spec.region(key)] += 1
    assert (covered == 1).all()
    assert spec.params_at((1, 2, 0)) == Parameters(mu=0.2, m2=2.5)


def test_fingerprint_tracks_every_input():
    base = SweepSpec.build(None, None, F, A)
    assert base.fingerprint() == SweepSpec.build(None, None, F, A).fingerprint()
    assert base.fingerprint() != SweepSpec.build(None, None, F, A * 1.0000001).fingerprint()
    assert base.fingerprint() != SweepSpec.build(Parameters(mu=0.2), None, F, A).fingerprint()
    changed = SweepSpec.build(None, None, F[:-1], A)
    assert changed.differences(base.definition()) == ["forces"]


@pytest.mark.parametrize(
    ("axes", "forces", "amplitudes", "message"),
    [
        ({"stiffness": [1.0]}, F, A, "unknown parameter 'stiffness'"),
        ({"force": [1.0]}, F, A, "sweep axis of its own"),
        ({"mu": [-0.1]}, F, A, "mu must be >= 0"),
        ({"mass": [1.0, np.nan]}, F, A, "mass must be finite"),
        ({"mu": []}, F, A, "mu must not be empty"),
        (None, [], A, "force must not be empty"),
        (None, [-0.1, 0.2], A, "force must be >= 0"),
        (None, F, [np.nan], "amplitude must be finite"),
        (None, F, [-1e-7], "amplitude must be >= 0"),
    ],
)
def test_bad_sweeps(axes, forces, amplitudes, message):
    with pytest.raises(ValueError, match=message):
        SweepSpec.build(None, axes, forces, amplitudes)


def test_bad_method_and_chunk():
    with pytest.raises(ValueError, match="method"):
        SweepSpec.build(None, None, F, A, method="fast")
    with pytest.raises(ValueError, match="amplitude_chunk"):
        SweepSpec.build(None, None, F, A, amplitude_chunk=0)


# -- issue 8: the step check of simulate(method="rk4"), options that do nothing ----------
def test_time_sweep_refuses_a_step_that_misses_the_vibration():
    t0 = Parameters().natural_period
    # dt = 1e-4 s > T0/10 used to return negative velocities with exit status 0.
    with pytest.raises(ValueError, match=r"dt=0.0001 s is too large.*T0 = 0.0006734 s"):
        SweepSpec.build(None, None, F, A, method="time", dt=1e-4)
    SweepSpec.build(None, None, F, A, method="time", dt=t0 / 10)  # the largest allowed step
    with pytest.raises(ValueError, match="dt"):
        SweepSpec.build(None, None, F, A, method="time", dt=t0 / 10 * (1 + 1e-9))


def test_step_check_names_the_parameter_set_with_the_shortest_period():
    axes = {"mu": [0.1, 0.2], "m2": [2.0, 1.5, 3.0]}
    periods = {m2: Parameters(m2=m2).natural_period for m2 in axes["m2"]}
    shortest = min(periods, key=periods.get)
    assert shortest == 1.5  # the stiffest contact at the paper's c_n
    dt = periods[2.0] / 20  # resolves m2 = 2, not m2 = 1.5
    with pytest.raises(ValueError) as info:
        SweepSpec.build(None, axes, F, A, method="time", dt=dt)
    message = str(info.value)
    assert "at mu=0.1, m2=1.5" in message
    assert f"T0 = {periods[1.5]:.4g} s" in message
    SweepSpec.build(None, axes, F, A, method="time", dt=periods[1.5] / 10)


def test_steady_sweep_refuses_time_options():
    with pytest.raises(ValueError, match=r"dt=1e-06 applies to method='time' only"):
        SweepSpec.build(None, None, F, A, dt=1e-6)
    with pytest.raises(ValueError, match=r"duration=1\.0 applies to method='time' only"):
        SweepSpec.build(None, None, F, A, duration=1.0)
    # The default duration is what the CLI passes when none was given: accepted.
    assert SweepSpec.build(None, None, F, A, duration=0.05).method == "steady"
    assert SweepSpec.build(None, None, F, A, method="time", duration=0.01).duration == 0.01


def test_every_parameter_combination_is_validated():
    # Each value is valid alone; together c_n = 1e10 and area = 1e-12 give y0 = 31 m.
    with pytest.raises(ValueError, match=r"y0 = 31\.32 m"):
        SweepSpec.build(None, {"c_n": [1e10, 4.52e16], "area": [1e-3, 1e-12]}, F, A)


def test_force_and_amplitude_limits_hold_for_every_parameter_set():
    light = {"mass": [1.0, 1e-6]}  # 1e6 m g = 9.81 N for the light slider
    small = [0.0, 1e-7]  # below 1e3 y0 of both sets
    SweepSpec.build(None, light, [9.8], small)
    with pytest.raises(ValueError, match=r"force.*at mass=1e-06"):
        SweepSpec.build(None, light, [9.9], small)
    y0_light = Parameters(mass=1e-6).static_deflection
    SweepSpec.build(None, light, F, [1e3 * y0_light])
    with pytest.raises(ValueError, match=r"amplitude.*1e3 y0.*at mass=1e-06"):
        SweepSpec.build(None, light, F, [1e3 * y0_light * (1 + 1e-9)])


def test_too_many_parameter_combinations_are_refused():
    axes = {name: np.linspace(1.0, 1.1, 1000) for name in ("mass", "g", "area")}
    with pytest.raises(ValueError, match="1000000000 parameter combinations"):
        SweepSpec.build(None, axes, F, A)
