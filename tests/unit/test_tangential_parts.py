"""The tangential parts (docs/design.md): field checks, refusals, packed slots, and the
paper's composition spelled out giving bit-identical output."""

import math

import numpy as np
import pytest

import microslip as ms
from microslip.model import coefficients as co

P = ms.Parameters()
KN = P.contact_stiffness


@pytest.mark.parametrize(
    ("make", "field"),
    [
        (lambda: ms.TangentialSpring(-1.0), "tangential.stiffness"),
        (lambda: ms.Model(P, tangential=ms.TangentialSpring(1e-7 * KN)), "tangential.stiffness"),
        (lambda: ms.Model(P, tangential=ms.TangentialSpring(1e7 * KN)), "tangential.stiffness"),
        (lambda: ms.MindlinSpring(0.0), "tangential.ratio"),
        (lambda: ms.MindlinSpring(11.0), "tangential.ratio"),
        (lambda: ms.StaticKinetic(math.nan, 0.1), "friction.mu_static"),
        (lambda: ms.StaticKinetic(0.15, -0.1), "friction.mu_kinetic"),
        (lambda: ms.Stribeck(0.15, 0.1, velocity=0.0), "friction.velocity"),
        (lambda: ms.Stribeck(0.15, 0.1, exponent=20.0), "friction.exponent"),
        (lambda: ms.HarmonicDrive(amplitude=-1.0), "drive.amplitude"),
        (lambda: ms.Model(P, drive=ms.HarmonicDrive(frequency=1e-3)), "drive.frequency"),
        (lambda: ms.Model(P, drive=ms.HarmonicDrive(mean=1e9)), "drive.mean"),
        (lambda: ms.Model(P, drive=ms.SpringDrive(stiffness=1.0)), "drive.stiffness"),
        (lambda: ms.Model(P, drive=ms.SpringDrive(velocity=-1e9)), "drive.velocity"),
        (lambda: ms.Model(P, drive=ms.PrescribedVelocity(1e9)), "drive.velocity"),
        (lambda: ms.Model(P, drive=ms.ConstantForce(-1e9)), "drive.force"),
    ],
)
def test_out_of_range_fields_are_refused_by_name(make, field):
    with pytest.raises(ValueError, match=field.replace(".", r"\.")) as info:
        make()
    assert "\n" not in str(info.value)


def test_static_coefficient_at_least_kinetic():
    with pytest.raises(
        ValueError, match=r"friction\.mu_static=0\.1 must be >= friction\.mu_kinetic"
    ):
        ms.StaticKinetic(mu_static=0.1, mu_kinetic=0.15)
    with pytest.raises(ValueError, match="mu_static"):
        ms.Stribeck(mu_static=0.1, mu_kinetic=0.15)
    model = ms.Model(P, friction=ms.StaticKinetic(0.15, 0.1))
    with pytest.raises(ValueError, match="mu_static"):
        model.replace(**{"friction.mu_kinetic": 0.2})
    assert ms.StaticKinetic(0.1, 0.1).mu_static == 0.1  # equal is Coulomb-like, allowed


def test_stribeck_needs_a_rigid_contact():
    with pytest.raises(ValueError, match="Stribeck needs tangential=Rigid"):
        ms.Model(P, tangential=ms.TangentialSpring(KN), friction=ms.Stribeck())
    with pytest.raises(ValueError, match="Stribeck needs tangential=Rigid"):
        ms.Model(P, friction=ms.Stribeck()).replace(tangential=ms.MindlinSpring())
    ms.Model(P, tangential=ms.Rigid(), friction=ms.Stribeck())  # fine


def test_force_argument_conflicts_with_a_drive():
    for drive in (ms.ConstantForce(0.5), ms.SpringDrive(), ms.PrescribedVelocity()):
        with pytest.raises(ValueError, match="conflicts with the model's drive"):
            ms.simulate(ms.Model(P, drive=drive), force=0.5, duration=1e-3, amplitude=0.0)
    with pytest.raises(ValueError, match="force is required"):
        ms.simulate(ms.Model(P), duration=1e-3, amplitude=0.0)


@pytest.mark.parametrize("friction", [ms.StaticKinetic(), ms.Stribeck()])
@pytest.mark.parametrize("name", ["mu", "params.mu"])
def test_mu_is_refused_with_a_law_of_its_own(friction, name):
    model = ms.Model(P, friction=friction)
    with pytest.raises(ValueError, match=r"friction\.mu_static / friction\.mu_kinetic"):
        model.replace(**{name: 0.2})
    assert model.replace(**{"friction.mu_static": 0.2}).friction.mu_static == 0.2
    assert ms.Model(P, friction=ms.Coulomb()).replace(mu=0.2).params.mu == 0.2


def test_dotted_names_and_units():
    model = ms.Model(P, friction=ms.Stribeck(), drive=ms.SpringDrive())
    fields = {
        **model.numeric_fields(),
        **ms.Model(P, tangential=ms.TangentialSpring(1e8)).numeric_fields(),
    }
    assert fields["tangential.stiffness"] == (1e8, "N m-1")
    assert fields["friction.velocity"][1] == "m s-1"
    assert fields["drive.stiffness"][1] == "N m-1"
    assert fields["drive.velocity"][1] == "m s-1"
    assert model.replace(**{"drive.velocity": 2e-4}).drive.velocity == 2e-4


def test_packed_slots():
    c = ms.Model(
        P,
        tangential=ms.Rigid(),
        friction=ms.Stribeck(0.3, 0.2, velocity=1e-3, exponent=1.5),
        drive=ms.HarmonicDrive(mean=0.1, amplitude=0.7, frequency=500.0),
    ).pack()
    assert c.size == co.SIZE
    assert c[co.TANGENTIAL_KIND] == 0.0
    c_t = ms.Model(P, tangential=ms.TangentialSpring(2e8)).pack(0.0)
    assert (c_t[co.TANGENTIAL_KIND], c_t[co.TANGENTIAL_STIFFNESS]) == (1.0, 2e8)
    assert (c[co.FRICTION_KIND], c[co.MU_STATIC], c[co.MU]) == (2.0, 0.3, 0.2)
    assert (c[co.STRIBECK_VELOCITY], c[co.STRIBECK_EXPONENT]) == (1e-3, 1.5)
    assert (c[co.DRIVE_KIND], c[co.FORCE], c[co.DRIVE_AMPLITUDE]) == (1.0, 0.1, 0.7)
    assert c[co.DRIVE_OMEGA] == pytest.approx(2 * math.pi * 500.0, rel=1e-15)
    c = ms.Model(
        P, tangential=ms.MindlinSpring(0.5), friction=ms.StaticKinetic(0.25, 0.2),
        drive=ms.SpringDrive(stiffness=3e5, velocity=-2e-3),
    ).pack()  # fmt: skip
    assert (c[co.TANGENTIAL_KIND], c[co.TANGENTIAL_STIFFNESS]) == (2.0, 0.5)
    assert (c[co.FRICTION_KIND], c[co.MU_STATIC], c[co.MU]) == (1.0, 0.25, 0.2)
    assert (c[co.DRIVE_KIND], c[co.DRIVE_AMPLITUDE], c[co.DRIVE_VELOCITY]) == (2.0, 3e5, -2e-3)
    c = ms.Model(P, drive=ms.PrescribedVelocity(3e-4)).pack()
    assert (c[co.DRIVE_KIND], c[co.DRIVE_VELOCITY]) == (3.0, 3e-4)
    c = ms.Model(P, drive=ms.ConstantForce(0.4)).pack()
    assert (c[co.DRIVE_KIND], c[co.FORCE]) == (0.0, 0.4)
    paper = ms.Model(P).pack(0.4)
    assert (paper[co.TANGENTIAL_KIND], paper[co.FRICTION_KIND], paper[co.DRIVE_KIND]) == (0, 0, 0)
    assert paper[co.MU_STATIC] == paper[co.MU] == P.mu  # Coulomb: μ_s = μ_k = μ
    np.testing.assert_array_equal(paper, c)  # ConstantForce(F) packs as force=F


def _same(a, b):
    for name in ("t", "y", "ydot", "x", "xdot", "u", "spring_force", "direction", "event_t",
                 "event_kind", "event_states"):  # fmt: skip
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    np.testing.assert_array_equal(a.Ft, b.Ft)
    np.testing.assert_array_equal(a.N, b.N)


@pytest.mark.parametrize("method", ["event", "rk4"])
@pytest.mark.parametrize(("force", "fraction"), [(0.5, 1.3), (0.3, 0.5), (-0.6, 0.8)])
def test_paper_parts_spelled_out_are_bit_identical(method, force, fraction):
    amplitude = fraction * P.static_deflection
    spelled = ms.Model(
        P, tangential=ms.Rigid(), friction=ms.Coulomb(), drive=ms.ConstantForce(force)
    )
    assert spelled.is_paper is False  # it has a drive part, but the same laws
    kwargs = {"duration": 0.005, "amplitude": amplitude, "method": method}
    _same(ms.simulate(spelled, **kwargs), ms.simulate(ms.Model(P), force=force, **kwargs))


@pytest.mark.parametrize(
    "friction",
    [
        ms.Coulomb(),
        ms.StaticKinetic(mu_static=0.15, mu_kinetic=0.1),
        ms.Stribeck(mu_static=0.15, mu_kinetic=0.1, velocity=1e-3, exponent=0.5),
        ms.Stribeck(mu_static=0.3, mu_kinetic=0.07, velocity=2e-4, exponent=2.0),
    ],
)
def test_the_kinetic_coefficient_at_rest_is_the_laws_at_speed_zero(friction):
    """kinetic_coefficient_at_rest, the compliant contact point's kinetic limit written
    without Stribeck's power and exponential, gives kinetic_coefficient(0, c)'s bits:
    μ_k, or Stribeck's μ(0) = μ_s (to rounding)."""
    from microslip.integrators.kernel import as_tuple
    from microslip.model.friction import kinetic_coefficient, kinetic_coefficient_at_rest

    c = as_tuple(ms.Model(P, friction=friction).pack(0.3))
    at_rest = kinetic_coefficient_at_rest(c)
    assert at_rest == kinetic_coefficient(0.0, c)
    expected = friction.mu_static if isinstance(friction, ms.Stribeck) else c[co.MU]
    assert at_rest == pytest.approx(expected, rel=1e-15)
