"""The parts of a Model: validation, dotted names, the compiled composed normal law."""

import math

import numpy as np
import pytest

from microslip.model.capabilities import UnsupportedModelError, require
from microslip.model.coefficients import MU, MU_STATIC
from microslip.model.composition import PART_TYPES, Model, as_model
from microslip.model.damping import HuntCrossley, Viscous
from microslip.model.excitation import BaseMotion, HarmonicForce, PrescribedPenetration
from microslip.model.normal import (
    normal_acceleration,
    normal_force,
    normal_force_partials,
    normal_force_rate,
    raw_normal_force,
    raw_normal_force_rate,
)
from microslip.model.parameters import Parameters

P = Parameters()
Y0 = P.static_deflection
K_N = P.contact_stiffness
C_CRIT = 2.0 * math.sqrt(K_N * P.mass)  # c for ζ = 1


def test_paper_model_is_default_and_packs_zero_kinds():
    m = Model()
    assert m.is_paper and m.params == P
    c = m.pack(0.5)
    # no part slots set but the static coefficient, the paper's μ (Coulomb: μ_s = μ_k)
    assert c[MU_STATIC] == c[MU] == P.mu
    rest = np.delete(c[7:], MU_STATIC - 7)
    assert rest.tolist() == [0.0] * rest.size
    assert as_model(None) == m and as_model(P) == m and as_model(m) is m


def test_dotted_names_and_replace():
    m = Model(damping=Viscous(0.03), excitation=HarmonicForce(0.5, 1400.0))
    fields = m.numeric_fields()
    assert fields["damping.ratio"] == (0.03, "1")
    assert fields["excitation.amplitude"] == (0.5, "N")
    assert fields["excitation.frequency"] == (1400.0, "Hz")
    m2 = m.replace(**{"damping.ratio": 0.05, "params.mu": 0.2, "excitation.frequency": 900.0})
    assert (m2.damping.ratio, m2.params.mu, m2.excitation.frequency) == (0.05, 0.2, 900.0)
    assert m2.replace(damping=None).damping is None
    with pytest.raises(ValueError, match="no damping part"):
        Model().replace(**{"damping.ratio": 0.1})
    with pytest.raises(ValueError, match=r"unknown model field 'excitation\.phase'"):
        m.replace(**{"excitation.phase": 1.0})


@pytest.mark.parametrize(
    "build, match",
    [
        (lambda: Viscous(ratio=-0.1), r"damping.ratio=-0.1 \[1\] is outside"),
        (lambda: HuntCrossley(ratio=11.0), "damping.ratio=11.0"),
        (lambda: HarmonicForce(amplitude=math.nan), "excitation.amplitude must be finite"),
        (lambda: Model(excitation=HarmonicForce(0.5, 1.0)), "excitation.frequency=1.0 Hz"),
        (lambda: Model(excitation=HarmonicForce(1e7, 1000.0)), "excitation.amplitude=10000000.0 N"),
        (lambda: Model(excitation=BaseMotion(1e-3, 1000.0)), "at most 1e3 y0"),
        (lambda: Model(excitation=PrescribedPenetration(0.0, 0.0, 1000.0)), "mean must be > 0"),
        (lambda: Model(damping=HarmonicForce(0.5, 1000.0)), "damping must be one of"),
        (lambda: Model(params={"mu": 0.1}), "params must be a microslip.Parameters"),
    ],
)
def test_refusals_name_the_field(build, match):
    with pytest.raises(ValueError, match=match):
        build()


def test_registry_lists_every_law():
    assert set(PART_TYPES["damping"]) == {Viscous, HuntCrossley}
    assert set(PART_TYPES["excitation"]) == {HarmonicForce, BaseMotion, PrescribedPenetration}


@pytest.mark.parametrize("law", [Viscous, HuntCrossley])
def test_damped_laws_written_from_their_definitions(law):
    """N_raw at a point against the formulas of docs/design.md, written out here."""
    zeta = 0.2
    c = Model(damping=law(zeta)).pack()
    coeff = zeta * C_CRIT
    delta, rate = 1.3 * Y0, -4e-4
    elastic = P.stiffness_coefficient * delta**2
    expected = elastic + coeff * rate if law is Viscous else elastic * (1 + coeff * rate / 9.81)
    assert raw_normal_force(0.0, delta, rate, c) == pytest.approx(expected, rel=1e-14)
    assert normal_force(0.0, delta, rate, c) == pytest.approx(max(expected, 0.0), rel=1e-14)
    # separation with overlap: a fast rebound makes N_raw negative, N is clipped to 0
    fast = -10.0 * P.mass * 9.81 / coeff
    assert raw_normal_force(0.0, delta, fast, c) < 0.0
    assert normal_force(0.0, delta, fast, c) == 0.0
    assert normal_force(0.0, -1e-9, 1.0, c) == 0.0  # no contact for δ <= 0


@pytest.mark.parametrize("law", [Viscous, HuntCrossley])
def test_laws_agree_when_linearised_at_the_working_point(law):
    """∂N/∂ẏ at δ = y0, δ̇ = 0 is c = 2 ζ sqrt(K_n m) for both laws; ∂N/∂y = K_n."""
    c = Model(damping=law(0.1)).pack()
    dn_dy, dn_dv = normal_force_partials(0.0, Y0, 0.0, c)
    assert dn_dy == pytest.approx(K_N, rel=1e-12)
    assert dn_dv == pytest.approx(0.1 * C_CRIT, rel=1e-12)


@pytest.mark.parametrize(
    "model",
    [
        Model(damping=Viscous(0.3)),
        Model(damping=HuntCrossley(0.3), excitation=BaseMotion(0.5 * Y0, 1800.0)),
        Model(damping=Viscous(0.1), excitation=HarmonicForce(2.0, 1200.0)),
        Model(params=P.replace(m2=1.5), damping=HuntCrossley(0.05)),
    ],
)
def test_partials_and_rate_match_finite_differences(model):
    c = model.pack()
    t, y, v = 1.7e-4, 1.2 * Y0, 3e-4
    hy, hv, ht = 1e-6 * Y0, 1e-6 * abs(v), 1e-9
    dn_dy, dn_dv = normal_force_partials(t, y, v, c)
    fd_y = (normal_force(t, y + hy, v, c) - normal_force(t, y - hy, v, c)) / (2 * hy)
    fd_v = (normal_force(t, y, v + hv, c) - normal_force(t, y, v - hv, c)) / (2 * hv)
    assert dn_dy == pytest.approx(fd_y, rel=1e-7)
    assert dn_dv == pytest.approx(fd_v, rel=1e-6, abs=1e-9 * K_N * Y0 / abs(v))
    # dN/dt along the motion: N at (t ± ht, y ± v ht, v ± a ht)
    a = normal_acceleration(t, y, v, c)
    ahead = normal_force(t + ht, y + v * ht, v + a * ht, c)
    behind = normal_force(t - ht, y - v * ht, v - a * ht, c)
    assert normal_force_rate(t, y, v, c) == pytest.approx((ahead - behind) / (2 * ht), rel=1e-5)


@pytest.mark.parametrize("m2", [2.0, 1.5])
def test_the_raw_rate_continues_past_a_separation_inside_the_overlap(m2):
    """dN_raw/dt where a viscous N_raw < 0 at δ > 0 (fast unloading): N is clipped, its
    rate 0, and the raw rate is the law's own, a finite difference of N_raw along the
    motion; in contact both rates agree."""
    c = Model(params=P.replace(m2=m2), damping=Viscous(0.3)).pack()
    t, y, ht = 0.0, 0.2 * Y0, 1e-10
    elastic = raw_normal_force(t, y, 0.0, c)  # S c_n δ^m2
    damping = elastic - raw_normal_force(t, y, -1.0, c)  # c [N s/m]
    v = -2.0 * elastic / damping  # N_raw = elastic + c v = -elastic
    assert raw_normal_force(t, y, v, c) < 0.0 < y  # separated inside the overlap
    a = normal_acceleration(t, y, v, c)
    ahead = raw_normal_force(t + ht, y + v * ht, v + a * ht, c)
    behind = raw_normal_force(t - ht, y - v * ht, v - a * ht, c)
    central = (ahead - behind) / (2 * ht)
    rate = raw_normal_force_rate(t, y, v, normal_force(t, y, v, c), c)
    assert rate == pytest.approx(central, rel=1e-5)
    assert normal_force_rate(t, y, v, c) == 0.0
    v_in = 1e-3  # loading: in contact
    assert (
        raw_normal_force_rate(t, y, v_in, normal_force(t, y, v_in, c), c)
        == normal_force_rate(t, y, v_in, c)
        != 0.0
    )


def test_excitations_enter_the_normal_equation_with_their_signs():
    f = 1400.0
    w = 2 * math.pi * f
    t = 0.3 / f
    harmonic = Model(excitation=HarmonicForce(0.5, f)).pack()
    # m ÿ = m g + P - N: at the static deflection, ÿ = P/m (P positive downward)
    assert normal_acceleration(t, Y0, 0.0, harmonic) == pytest.approx(
        0.5 * math.sin(w * t), rel=1e-9
    )
    base = Model(excitation=BaseMotion(0.2 * Y0, f)).pack()
    z = 0.2 * Y0 * math.sin(w * t)
    assert normal_force(t, Y0 + z, 0.0, base) == pytest.approx(9.81, rel=1e-12)  # δ = y - z
    prescribed = Model(excitation=PrescribedPenetration(Y0, 0.5 * Y0, f)).pack()
    delta = Y0 * (1 + 0.5 * math.cos(w * t))
    expected = P.stiffness_coefficient * delta**2
    assert normal_force(t, 123.0, 4.0, prescribed) == pytest.approx(expected, rel=1e-12)
    assert normal_acceleration(t, 0.0, 0.0, prescribed) == pytest.approx(
        -0.5 * Y0 * w * w * math.cos(w * t), rel=1e-12
    )


def test_require_refuses_in_one_line():
    m = Model(damping=Viscous(0.1))
    with pytest.raises(UnsupportedModelError, match=r"^free_period does not support damping="):
        require(m, "free_period", allowed={"damping": (None,)}, instead="use simulate")
    require(Model(), "free_period", allowed={"damping": (None,)}, instead="use simulate")


def test_attrs_name_the_parts():
    attrs = Model(excitation=BaseMotion(1e-8, 1000.0)).to_attrs()
    assert attrs["damping"] == "none" and attrs["excitation"] == "BaseMotion"
    assert attrs["excitation_amplitude"] == 1e-8 and attrs["param_mu"] == 0.1
    assert np.isfinite(list(v for v in attrs.values() if isinstance(v, float))).all()


def test_free_vibration_analysis_refuses_a_non_conservative_model():
    from microslip.analysis.free_vibration import free_period, turning_points

    assert free_period(Model(), 0.5 * Y0) == free_period(P, 0.5 * Y0)
    for model in (Model(damping=HuntCrossley(0.01)), Model(excitation=HarmonicForce(0.1, 1e3))):
        with pytest.raises(UnsupportedModelError, match="undamped free vibration only"):
            free_period(model, 0.5 * Y0)
        with pytest.raises(UnsupportedModelError, match="turning_points"):
            turning_points(model, 0.5 * Y0)
