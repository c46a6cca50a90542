"""Sweeps over a Model's dotted field names: dims, units, values, refusals, store identity."""

from __future__ import annotations

import numpy as np
import pytest

import microslip as ms
from microslip.analysis.steady_state import mean_velocity
from microslip.sweeps import StoreMismatchError, SweepSpec, run_sweep, sweep, velocity_map
from microslip.sweeps.store import SweepStore

P = ms.Parameters()
FORCED = ms.Model(P, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(0.5, 1400.0))
FREQS = [1300.0, 1450.0]
RATIOS = [0.03, 0.05]
FORCES = np.array([0.5, 0.8, 0.9])


def test_frequency_by_damping_sweep_equals_scalar_calls():
    da = sweep(FORCED, {"excitation.frequency": FREQS, "damping.ratio": RATIOS}, force=FORCES)
    assert da.dims == ("excitation.frequency", "damping.ratio", "force")
    assert da.shape == (2, 2, 3)
    assert da.attrs["units"] == "m s-1"
    assert da["excitation.frequency"].attrs["units"] == "Hz"
    assert da["damping.ratio"].attrs["units"] == "1"
    assert da["force"].attrs["units"] == "N"
    assert da.attrs["excitation"] == "HarmonicForce" and da.attrs["damping"] == "Viscous"
    for i, f in enumerate(FREQS):
        for j, zeta in enumerate(RATIOS):
            model = FORCED.replace(**{"excitation.frequency": f, "damping.ratio": zeta})
            for k, force in enumerate(FORCES):
                assert da.values[i, j, k] == mean_velocity(model, force=force)
    assert (da.values > 0).sum() >= 6  # the map is not trivially zero


def test_params_prefix_and_velocity_map_frequencies():
    da = sweep(FORCED, {"params.mu": [0.1, 0.12]}, force=[0.8])
    assert da.dims == ("mu", "force")
    assert da.values[1, 0] == mean_velocity(FORCED.replace(mu=0.12), force=0.8)
    assert da.values[1, 0] < da.values[0, 0]  # more friction, slower
    vmap = velocity_map(FORCED, forces=[0.8, 0.9], frequencies=FREQS)
    assert vmap.dims == ("excitation.frequency", "force")
    assert vmap.values[1, 1] == mean_velocity(
        FORCED.replace(**{"excitation.frequency": FREQS[1]}), force=0.9
    )


def test_free_damped_model_keeps_the_amplitude_axis():
    model = ms.Model(P, damping=ms.Viscous(0.1))
    with pytest.warns(RuntimeWarning, match="F > mu m g"):
        da = sweep(model, {"damping.ratio": [0.1, 0.2]}, force=[0.5, 1.0], amplitude=[0.0, 1e-7])
    assert da.dims == ("damping.ratio", "force", "amplitude")
    assert np.all(da.values[:, 0, :] == 0.0) and np.all(np.isinf(da.values[:, 1, :]))


@pytest.mark.parametrize(
    ("model", "axes", "amplitude", "message"),
    [
        (FORCED, {"stiffness": [1.0]}, None, r"^unknown parameter 'stiffness' in sweep; known: "),
        (FORCED, {"damping.ratio": [0.05, 20.0]}, None, r"^damping.ratio=20.0 \[1\] is outside"),
        (FORCED, {"excitation.frequency": [1e9]}, None, r"^excitation.frequency=1000000000.0"),
        (ms.Model(P), {"damping.ratio": [0.1]}, 1e-7, r"^'damping.ratio': this model has no"),
        (FORCED, None, [1e-7], r"^amplitude applies to the free vibration"),
        (ms.Model(P), None, None, r"^amplitude \[m\] is required"),
        (FORCED, {"mu": [0.1], "params.mu": [0.2]}, None, r"^'mu' is given twice"),
    ],
)
def test_refusals_come_before_any_computing(model, axes, amplitude, message, monkeypatch):
    def never(*args, **kwargs):
        raise AssertionError("computed before validating")

    monkeypatch.setattr("microslip.sweeps.runner.compute_chunk", never)
    with pytest.raises(ValueError, match=message) as error:
        sweep(model, axes, force=[0.5], amplitude=amplitude)
    assert "\n" not in str(error.value)


def test_part_values_are_checked_against_every_parameter_set():
    # 4000 Hz is within 1e3 f0 for the paper's contact, but not for a much softer one.
    soft = P.replace(c_n=P.c_n * 1e-4)
    assert soft.natural_frequency * 1e3 < 5e5 < P.natural_frequency * 1e3
    with pytest.raises(ValueError, match=r"excitation.frequency=500000.0 .* at c_n="):
        SweepSpec.build(
            FORCED, {"c_n": [P.c_n, soft.c_n], "excitation.frequency": [1400.0, 5e5]}, [0.5]
        )


def test_store_fingerprint_includes_the_model(tmp_path):
    spec = SweepSpec.build(FORCED, {"excitation.frequency": FREQS}, [0.8])
    other = SweepSpec.build(
        FORCED.replace(**{"damping.ratio": 0.04}), {"excitation.frequency": FREQS}, [0.8]
    )
    assert spec.fingerprint() != other.fingerprint()
    assert other.differences(spec.definition()) == ["model"]
    store = tmp_path / "run.zarr"
    first = run_sweep(spec, store=store)
    again = run_sweep(spec, store=store)  # resumed: nothing recomputed, same numbers
    assert np.array_equal(first["mean_velocity"].values, again["mean_velocity"].values)
    with pytest.raises(StoreMismatchError, match="differs in: model"):
        SweepStore(store, other)


def test_time_method_on_a_forced_model_approaches_the_steady_mean():
    steady = sweep(FORCED, None, force=[0.8, 0.9]).values
    durations = (0.04, 0.08)  # 56 and 112 excitation periods
    x = [sweep(FORCED, None, force=[0.8, 0.9], method="time", duration=d) for d in durations]
    assert x[0].dims == ("force",)
    # x(T) = v T + b once the transient (time constant 1/(ζ ω0) = 2 ms) is over: the
    # difference of two runs removes the transient's offset b.
    slope = (x[1].values * durations[1] - x[0].values * durations[0]) / (
        durations[1] - durations[0]
    )
    assert np.allclose(slope, steady, rtol=1e-3)
    assert not np.allclose(x[0].values, steady, rtol=1e-3)  # the offset is really there
