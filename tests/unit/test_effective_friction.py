"""effective_friction, _curve and _map: refusals, the Dataset layout, the sharing of one
normal motion between speeds and values, symmetries and the constant-N limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

import microslip as ms
from microslip.analysis import normal_period
from microslip.model.capabilities import UnsupportedModelError

P = ms.Parameters()
Y0 = P.static_deflection
PUNCH = ms.Parameters(m2=1.0, c_n=1e8, area=1.0)
EXCITATION = ms.PrescribedPenetration(mean=1e-7, amplitude=0.5e-7, frequency=1000.0)
SPEEDS = np.geomspace(1e-5, 1e-2, 7)


def punch(**parts) -> ms.Model:
    parts = {"tangential": ms.TangentialSpring(1e6), "drive": ms.PrescribedVelocity(1e-4),
             "excitation": EXCITATION, **parts}  # fmt: skip
    return ms.Model(PUNCH, **parts)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: ms.effective_friction(ms.Model(P), amplitude=Y0), "does not support drive=None"),
        (lambda: ms.effective_friction(P), "must be a microslip.Model"),
        (lambda: ms.effective_friction(punch(), method="fast"), "method must be one of"),
        (lambda: ms.effective_friction(punch(drive=ms.ConstantForce(0.5)), method="exact"),
         "needs drive=ms.PrescribedVelocity"),
        (lambda: ms.effective_friction(punch(drive=ms.PrescribedVelocity(0.0))), "nonzero"),
        (lambda: ms.effective_friction(punch(), amplitude=Y0), "free vibration only"),
        (lambda: ms.effective_friction(ms.Model(P, drive=ms.PrescribedVelocity(1e-4))),
         "give amplitude"),
        (lambda: ms.effective_friction(punch(drive=ms.ConstantForce(0.5)), blocks=1),
         "blocks must be >= 2"),
        (lambda: ms.effective_friction_curve(punch(drive=ms.SpringDrive()), SPEEDS),
         "velocity is the swept axis"),
        (lambda: ms.effective_friction_curve(punch(), [1e-4, np.nan]), "finite"),
        (lambda: ms.effective_friction_curve(punch(), [[1e-4]]), "one-dimensional"),
        (lambda: ms.effective_friction_curve(punch(), [1e-4, 1e9]), "1e6 g T0"),
        (lambda: ms.effective_friction_curve(punch(), [1e-4, 0.0]),
         r"^drive velocity 0\.0 m s-1 must be nonzero"),  # the value, not a NumPy repr
        (lambda: ms.effective_friction_map(punch(), SPEEDS, "drive.velocity", [1e-4]),
         "velocity axis"),
        (lambda: ms.effective_friction_map(punch(), SPEEDS, "tangential.colour", [1.0]),
         "unknown model field"),
        (lambda: ms.effective_friction_map(punch(), SPEEDS, "damping.ratio", [0.1]),
         "no damping part"),
        (lambda: ms.effective_friction_map(punch(), SPEEDS, "excitation.amplitude", [-1e-8]),
         "excitation.amplitude"),
    ],
)  # fmt: skip
def test_refusals_are_one_line_value_errors(call, match):
    with pytest.raises(ValueError, match=match) as info:
        call()
    assert "\n" not in str(info.value)


def test_drive_none_is_an_unsupported_model():
    with pytest.raises(UnsupportedModelError):
        ms.effective_friction(ms.Model(P), amplitude=Y0)


def test_curve_layout_units_and_attributes():
    model = punch()
    ds = ms.effective_friction_curve(model, SPEEDS)
    assert dict(ds.sizes) == {"velocity": SPEEDS.size}
    np.testing.assert_array_equal(ds.velocity.values, SPEEDS)
    assert ds.velocity.attrs["units"] == "m s-1"
    for name in ("mu_eff", "ratio", "v_tilde", "stick_fraction", "mu_kinetic", "error"):
        assert ds[name].dims == ("velocity",) and ds[name].attrs["units"] == "1"
        assert ds[name].attrs["long_name"]
    assert ds.mean_friction_force.attrs["units"] == "N"
    assert ds.mean_normal_force.attrs["units"] == "N"
    assert ds.period.dims == () and ds.period.attrs["units"] == "s"
    assert float(ds.period) == pytest.approx(1e-3)
    for key, value in model.to_attrs().items():
        assert ds.attrs[key] == value
    assert ds.attrs["method"] == "exact"
    ds.to_netcdf(engine="scipy")  # serialisable attributes
    assert np.all(np.diff(ds.ratio.values) >= 0.0)  # Coulomb: faster, less reduction


def test_curve_equals_the_points_and_is_even_in_v():
    model = punch(friction=ms.StaticKinetic(0.15, 0.1))
    ds = ms.effective_friction_curve(model, np.r_[SPEEDS, -SPEEDS])
    for i, v in enumerate(SPEEDS):
        point = ms.effective_friction(model.replace(drive=ms.PrescribedVelocity(float(v))))
        assert ds.mu_eff.values[i] == point.mu_eff
        assert ds.stick_fraction.values[i] == point.stick_fraction
        assert ds.v_tilde.values[i] == point.v_tilde
    np.testing.assert_array_equal(ds.mu_eff.values[: SPEEDS.size], ds.mu_eff.values[SPEEDS.size :])


def test_map_rows_are_curves_and_share_the_normal_motion(monkeypatch):
    model = punch()
    betas = np.array([0.2, 0.6, 1.0]) * EXCITATION.mean
    ds = ms.effective_friction_map(model, SPEEDS, "excitation.amplitude", betas)
    assert ds.mu_eff.dims == ("excitation.amplitude", "velocity")
    assert ds["excitation.amplitude"].attrs["units"] == "m"
    assert ds.period.dims == ("excitation.amplitude",)
    row = ms.effective_friction_curve(model.replace(**{"excitation.amplitude": betas[1]}), SPEEDS)
    np.testing.assert_array_equal(ds.mu_eff.values[1], row.mu_eff.values)
    # a tangential axis leaves the normal motion alone: one normal cycle for the whole map
    calls = []
    original = normal_period.normal_cycle
    monkeypatch.setattr(normal_period, "normal_cycle", lambda *a: calls.append(a) or original(*a))
    stiff = ms.effective_friction_map(model, SPEEDS, "tangential.stiffness", [1e5, 1e6, 1e7])
    assert len(calls) == 1 and stiff["tangential.stiffness"].attrs["units"] == "N m-1"
    np.testing.assert_array_equal(stiff.mu_eff.values[1], ms.effective_friction_curve(
        model, SPEEDS).mu_eff.values)  # fmt: skip
    # ṽ ∝ k_t: the stiffer contact is the faster one
    np.testing.assert_allclose(stiff.v_tilde.values[2], 100.0 * stiff.v_tilde.values[0])


def test_forced_map_rows_are_the_curves_bit_for_bit():
    """A map over an excitation field integrates its orbits' first transients side by
    side (normal_period.forced_transients); each row is still the curve alone."""
    model = ms.Model(
        P, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(2.0, 1400.0),
        tangential=ms.TangentialSpring(7e7), drive=ms.PrescribedVelocity(1e-4),
    )  # fmt: skip
    amplitudes = [1.0, 2.5, 4.0]  # N: the last two lose contact
    ds = ms.effective_friction_map(model, SPEEDS, "excitation.amplitude", amplitudes)
    for j, amplitude in enumerate(amplitudes):
        alone = model.replace(**{"excitation.amplitude": amplitude})
        row = ms.effective_friction_curve(alone, SPEEDS)
        np.testing.assert_array_equal(ds.mu_eff.values[j], row.mu_eff.values)
        np.testing.assert_array_equal(ds.period.values[j], row.period.values)
    assert np.all(ds.mu_eff.values[1:] < ds.mu_kinetic.values[1:])  # reduction where it flies


def test_a_map_value_that_is_not_period_one_falls_back_on_its_own_row():
    """The map's normal cycles are computed side by side before its rows; a value whose
    forced response is not period-1 (undamped, 15 N) is carried to its row: a rigid
    contact gets μ_k with <N> = m g (identity 1), the period-1 value beside it stays
    exact, and method='exact' on a compliant contact refuses the map in one line."""
    rigid = ms.Model(P, excitation=ms.HarmonicForce(1.0, 1400.0),
                     drive=ms.PrescribedVelocity(1e-4))  # fmt: skip
    ds = ms.effective_friction_map(rigid, SPEEDS[:2], "excitation.amplitude", [1.0, 15.0])
    assert np.all(ds.mu_eff.values == 0.1) and ds.attrs["method"] == "exact"
    assert np.all(ds.mean_normal_force.values[1] == P.mass * P.g)
    np.testing.assert_allclose(ds.mean_normal_force.values[0], P.mass * P.g, rtol=1e-9)
    alone = ms.effective_friction_curve(rigid, SPEEDS[:2])
    np.testing.assert_array_equal(ds.mean_normal_force.values[0], alone.mean_normal_force.values)
    compliant = rigid.replace(tangential=ms.TangentialSpring(7e7))
    with pytest.raises(ValueError, match=r"method='exact': .*period-1") as error:
        ms.effective_friction_map(
            compliant, SPEEDS[:2], "excitation.amplitude", [1.0, 15.0], method="exact"
        )
    assert "\n" not in str(error.value)


def test_map_over_the_free_vibration_amplitude():
    model = ms.Model(P, tangential=ms.TangentialSpring(1e7), drive=ms.PrescribedVelocity(1e-4))
    amplitudes = np.array([0.0, 0.5, 1.5]) * Y0
    ds = ms.effective_friction_map(model, SPEEDS, "amplitude", amplitudes)
    assert ds.mu_eff.dims == ("amplitude", "velocity") and ds.amplitude.attrs["units"] == "m"
    np.testing.assert_array_equal(ds.ratio.values[0], 1.0)  # A = 0: constant N
    assert np.isnan(ds.period.values[0]) and np.isnan(ds.v_tilde.values[0]).all()
    assert float(ds.period[2]) == pytest.approx(ms.free_period(P, 1.5 * Y0), rel=1e-12)
    assert ds.ratio.values[2, 0] < ds.ratio.values[1, 0] < 1.0  # larger A: more reduction


def test_each_speed_is_bit_identical_whatever_its_company_and_the_thread_count():
    """The speeds of a curve are walked in parallel (contact_point.steady_friction): each
    must give the same bits alone, in another order and on one thread."""
    import numba

    model = ms.Model(P, tangential=ms.TangentialSpring(1e7), friction=ms.StaticKinetic(0.2, 0.1),
                     drive=ms.PrescribedVelocity(1e-4))  # fmt: skip
    speeds = np.geomspace(1e-6, 1e-2, 41)
    whole = ms.effective_friction_curve(model, speeds, amplitude=1.2 * Y0).mu_eff.values
    order = np.random.default_rng(3).permutation(speeds.size)
    shuffled = ms.effective_friction_curve(model, speeds[order], amplitude=1.2 * Y0)
    np.testing.assert_array_equal(shuffled.mu_eff.values, whole[order])
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        single = ms.effective_friction_curve(model, speeds[5:6], amplitude=1.2 * Y0)
    finally:
        numba.set_num_threads(threads)
    np.testing.assert_array_equal(single.mu_eff.values, whole[5:6])


@pytest.mark.parametrize(
    "model",
    [
        ms.Model(P, damping=ms.Viscous(0.1), tangential=ms.TangentialSpring(1e7),
                 friction=ms.StaticKinetic(0.2, 0.1), drive=ms.PrescribedVelocity(1e-4)),
        punch(excitation=ms.PrescribedPenetration(mean=1e-7, amplitude=0.0, frequency=1e3)),
    ],
)  # fmt: skip
def test_constant_normal_force_gives_the_kinetic_coefficient(model):
    """A damped free vibration decays to N = m g; a constant penetration holds N0."""
    result = ms.effective_friction(model, amplitude=Y0 if model.excitation is None else None)
    assert result.mu_eff == 0.1 and result.ratio == 1.0 and result.error == 0.0
    assert math.isnan(result.v_tilde) and math.isnan(result.period)
    expected = P.mass * P.g if model.excitation is None else 10.0
    assert result.mean_normal_force == pytest.approx(expected, rel=1e-15)


def test_time_average_agrees_with_the_exact_path():
    model = punch(excitation=ms.PrescribedPenetration(mean=1e-7, amplitude=1.5e-7,
                                                      frequency=1000.0))  # fmt: skip
    exact = ms.effective_friction(model)
    averaged = ms.effective_friction(model, method="time_average", transient=2e-3, window=8e-3)
    assert averaged.method == "time_average" and exact.method == "exact"
    assert averaged.mu_eff == pytest.approx(exact.mu_eff, rel=1e-10)
    assert averaged.stick_fraction == pytest.approx(exact.stick_fraction, abs=1e-9)
    assert averaged.error < 1e-10 and math.isnan(averaged.v_tilde)


def test_force_drives_and_non_period_one_motion_take_the_time_average():
    forced = ms.HarmonicForce(amplitude=15.0, frequency=1400.0)  # not period-1 (undamped)
    model = ms.Model(P, excitation=forced, tangential=ms.TangentialSpring(7e7),
                     drive=ms.PrescribedVelocity(1e-4))  # fmt: skip
    with pytest.raises(ValueError, match="method='exact'"):
        ms.effective_friction(model, method="exact")
    result = ms.effective_friction(model, transient=0.01, window=0.02)
    assert result.method == "time_average" and 0.0 < result.ratio < 1.0 and result.error > 0.0
    pushed = ms.effective_friction(
        ms.Model(P, damping=ms.HuntCrossley(0.05), tangential=ms.TangentialSpring(7e7),
                 excitation=ms.HarmonicForce(amplitude=5.0, frequency=1400.0),
                 drive=ms.ConstantForce(-0.3)), transient=0.01, window=0.02,
    )  # fmt: skip
    assert pushed.method == "time_average"
    # F_t along the drive (towards -x here) balances |F| on average, up to m Δẋ / window
    assert pushed.mean_friction_force == pytest.approx(0.3, rel=1e-2)
