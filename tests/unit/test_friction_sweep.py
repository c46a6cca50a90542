"""Effective-friction sweeps of kinematically driven models, and the refusals of the
mean-velocity analyses for tangential parts they do not cover."""

from __future__ import annotations

import math

import numpy as np
import pytest

import microslip as ms

PUNCH = ms.Parameters(m2=1.0, c_n=1e8, area=1.0)
MEAN, FREQ, KT = 1e-7, 1000.0, 1e6


def punch_model(velocity: float = 1e-4) -> ms.Model:
    return ms.Model(
        PUNCH,
        excitation=ms.PrescribedPenetration(mean=MEAN, amplitude=0.5 * MEAN, frequency=FREQ),
        tangential=ms.TangentialSpring(KT),
        drive=ms.PrescribedVelocity(velocity),
    )


def test_sweep_of_a_kinematic_model_gives_mu_eff_point_by_point():
    model = punch_model()
    v = np.array([1e-5, 1e-4, 1e-3])
    a = np.array([0.2, 0.5, 0.9]) * MEAN
    result = ms.sweep(model, {"drive.velocity": v, "excitation.amplitude": a})
    assert result.name == "mu_eff" and result.dims == ("drive.velocity", "excitation.amplitude")
    assert result.attrs["units"] == "1"
    assert result["drive.velocity"].attrs["units"] == "m s-1"
    for i, vi in enumerate(v):
        for j, aj in enumerate(a):
            point = model.replace(**{"drive.velocity": vi, "excitation.amplitude": aj})
            assert result.values[i, j] == ms.effective_friction(point).mu_eff
    # the reduction grows with the amplitude at a slow drive (1 - beta D, D > 0)
    assert np.all(np.diff(result.values[0]) < 0)


def test_kinematic_sweep_refuses_what_it_cannot_honour():
    model = punch_model()
    with pytest.raises(ValueError, match=r"force=0\.5 does not apply"):
        ms.sweep(model, {"drive.velocity": [1e-4]}, force=0.5)
    with pytest.raises(ValueError, match="store="):
        ms.sweep(model, {"drive.velocity": [1e-4]}, store="x.zarr")
    with pytest.raises(ValueError, match="method='time'"):
        ms.sweep(model, {"drive.velocity": [1e-4]}, method="time")


@pytest.mark.parametrize(
    "part",
    [{"tangential": ms.TangentialSpring(1e7)}, {"friction": ms.StaticKinetic(0.15, 0.1)},
     {"drive": ms.SpringDrive(1e5, 1e-4)}],
)  # fmt: skip
def test_mean_velocity_and_sweep_refuse_tangential_parts(part):
    """The reflected process (identity 5) needs a rigid contact, Coulomb friction and a
    constant force: anything else is refused, never answered with the paper's value."""
    model = ms.Model(ms.Parameters(), **part)
    with pytest.raises(ms.UnsupportedModelError, match="mean_velocity does not support"):
        ms.mean_velocity(model, force=0.5, amplitude=3e-7)
    with pytest.raises(ms.UnsupportedModelError, match="sweep does not support"):
        ms.sweep(model, force=[0.5], amplitude=[3e-7])


def test_effective_friction_refuses_force_drives():
    model = ms.Model(ms.Parameters(), tangential=ms.TangentialSpring(1e7))
    with pytest.raises(ms.UnsupportedModelError, match="PrescribedVelocity"):
        ms.effective_friction(model, amplitude=3e-7)
    assert math.isnan(ms.effective_friction(punch_model(), amplitude=None).v_tilde) is False
