"""The exact steady state of the compliant contact point (effective_friction, "exact")
against time integrations that share none of its code: ``simulate`` (the full model,
event method; averaged here with Gauss–Legendre sums between its switching instants)
and the scipy contact-point reference (contact_point_reference.py, N(t) written out).

Mindlin's stiffness (k_t = λ dN/dδ) and static/kinetic friction on the three tabulated
or closed-form normal motions: a damped forced orbit, the free vibration, a prescribed
penetration with loss of contact (docs/theory/friction_reduction.md).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from contact_point_reference import ContactPoint, average

import microslip as ms

GX, GW = np.polynomial.legendre.leggauss(10)
P = ms.Parameters()  # the paper's contact, m2 = 2
Y0 = P.static_deflection
PUNCH = ms.Parameters(m2=1.0, c_n=1e8, area=1.0)


def simulated_mu_eff(model, period, periods, average_over, **start):
    """∫F_t dt / ∫N dt over the last ``average_over`` of ``periods`` normal periods."""
    end = periods * period
    first = ms.simulate(model, duration=end, rtol=1e-12, **start)
    t0 = end - average_over * period
    events = first.event_t[(first.event_t > t0) & (first.event_t < end)]
    cuts = np.unique(np.r_[np.linspace(t0, end, 64 * average_over + 1), events])
    half, mid = 0.5 * np.diff(cuts), 0.5 * (cuts[1:] + cuts[:-1])
    nodes = (mid[:, None] + half[:, None] * GX).ravel()
    weights = (half[:, None] * GW).ravel()
    run = ms.simulate(model, duration=end, rtol=1e-12, t_eval=nodes, **start)
    return float(weights @ -run.Ft) / float(weights @ run.N)


def test_mindlin_on_a_damped_forced_orbit_against_simulate():
    model = ms.Model(
        P, damping=ms.HuntCrossley(0.05), tangential=ms.MindlinSpring(0.8),
        excitation=ms.HarmonicForce(amplitude=5.0, frequency=1400.0),
        drive=ms.PrescribedVelocity(1e-4),
    )  # fmt: skip
    exact = ms.effective_friction(model)
    assert exact.method == "exact" and 0.3 < exact.ratio < 0.9  # a real reduction
    y, ydot = ms.periodic_orbit(model.replace(tangential=None, drive=None)).y0_state
    simulated = simulated_mu_eff(model, 1 / 1400.0, 6, 2, initial_state=(y, ydot, 0.0, 1e-4))
    assert exact.mu_eff == pytest.approx(simulated, rel=1e-10)


@pytest.mark.parametrize(
    ("tangential", "amplitude"),
    [(ms.TangentialSpring(1e7), 0.6 * Y0), (ms.MindlinSpring(0.8), 1.5 * Y0)],
)
def test_static_kinetic_on_the_free_vibration_against_simulate(tangential, amplitude):
    """μ_s > μ_k: the spring force drops at each slip start; the steady cycle may span
    several periods, so the simulation is averaged over 12 of them."""
    model = ms.Model(P, tangential=tangential, friction=ms.StaticKinetic(0.2, 0.1),
                     drive=ms.PrescribedVelocity(2e-5))  # fmt: skip
    exact = ms.effective_friction(model, amplitude=amplitude)
    assert exact.ratio < 0.8
    simulated = simulated_mu_eff(model, exact.period, 16, 12, amplitude=amplitude)
    assert exact.mu_eff == pytest.approx(simulated, rel=1e-10)


def test_mindlin_prescribed_penetration_with_loss_of_contact_against_the_reference():
    """m2 = 1.5: k_t = λ m2 S c_n δ^0.5 vanishes at touchdown with N and Ṅ."""
    p = ms.Parameters(m2=1.5)
    sc, mean, beta, freq, lam = p.stiffness_coefficient, p.static_deflection, 1.3, 1000.0, 0.8
    omega = 2 * math.pi * freq

    def delta(t):
        return mean * (1.0 + beta * math.cos(omega * t))

    def rate(t):
        return 1.5 * sc * max(delta(t), 0.0) ** 0.5 * (-mean * beta * omega * math.sin(omega * t))

    for velocity in (2e-7, 1.2e-6):  # ṽ = 0.14 (stuck at touchdown), 0.86 (sliding there)
        model = ms.Model(p, tangential=ms.MindlinSpring(lam), drive=ms.PrescribedVelocity(velocity),
                         excitation=ms.PrescribedPenetration(mean=mean, amplitude=beta * mean,
                                                             frequency=freq))  # fmt: skip
        exact = ms.effective_friction(model)
        reference = average(ContactPoint(
            normal=lambda t: sc * max(delta(t), 0.0) ** 1.5, normal_rate=rate,
            stiffness=lambda t: lam * 1.5 * sc * max(delta(t), 0.0) ** 0.5, contact=delta,
            velocity=velocity, mu_static=p.mu, mu_kinetic=p.mu, period=1 / freq,
            force_scale=sc * mean**1.5,
        ), periods=3)  # fmt: skip
        assert exact.ratio < 0.99 and exact.stick_fraction > 0.1
        assert exact.mu_eff == pytest.approx(reference["mu_eff"], rel=1e-8)
        assert exact.stick_fraction == pytest.approx(reference["stick_fraction"], abs=1e-8)
        # Mindlin, elastic: the critical speed is λ v / (μ max δ̇) = 1
        assert exact.v_tilde == pytest.approx(lam * velocity / (p.mu * mean * beta * omega))


def flat_punch(beta: float, velocity: float) -> tuple[ms.Model, ContactPoint]:
    """A static/kinetic flat punch (μ_s = 0.15, μ_k = 0.1) and its reference problem."""
    k_n, mean, freq, kt = PUNCH.stiffness_coefficient, 1e-7, 1000.0, 1e6
    omega = 2 * math.pi * freq
    model = ms.Model(
        PUNCH, tangential=ms.TangentialSpring(kt), friction=ms.StaticKinetic(0.15, 0.1),
        excitation=ms.PrescribedPenetration(mean=mean, amplitude=beta * mean, frequency=freq),
        drive=ms.PrescribedVelocity(velocity),
    )  # fmt: skip

    def delta(t):
        return mean * (1.0 + beta * math.cos(omega * t))

    problem = ContactPoint(
        normal=lambda t: k_n * max(delta(t), 0.0),
        normal_rate=lambda t: -k_n * mean * beta * omega * math.sin(omega * t),
        stiffness=lambda t: kt, contact=delta, velocity=velocity, mu_static=0.15,
        mu_kinetic=0.1, period=1 / freq, force_scale=k_n * mean,
    )  # fmt: skip
    return model, problem


@pytest.mark.parametrize("beta", [0.6, 1.4])
def test_static_kinetic_flat_punch_against_the_reference(beta):
    """β = 0.6: a steady cycle of two normal periods (a slip every other period): one
    period of the reference alone misses μ_eff by 3 %, two give it."""
    model, problem = flat_punch(beta, 2e-4)
    exact = ms.effective_friction(model)
    reference = average(problem, periods=8, last=2)
    assert exact.mu_eff == pytest.approx(reference["mu_eff"], rel=1e-9)
    one_period = average(problem, periods=8, last=1)["mu_eff"]
    if beta < 1.0:
        assert abs(one_period / exact.mu_eff - 1.0) > 0.01
    else:
        assert exact.mu_eff == pytest.approx(one_period, rel=1e-9)


@pytest.mark.parametrize(
    ("velocity", "cycle"), [(1e-6, 251), (1e-5, 26), (3.1622776601683795e-5, 8)]
)
def test_static_kinetic_long_cycles_with_grazing_slips(velocity, cycle):
    """Slow drives: the point sticks for many periods until f grazes μ_s N_min (the margin
    dips below 0 for a moment, between any two sample points); the steady cycle spans
    ``cycle`` normal periods (the exact path takes the whole stuck periods in one step).
    The reference integrates every period and finds the grazes at the margin's minima."""
    model, problem = flat_punch(0.5, velocity)
    exact = ms.effective_friction(model)
    reference = average(problem, periods=2 * cycle + 10, last=cycle)
    assert exact.mu_eff == pytest.approx(reference["mu_eff"], rel=1e-9)
    assert exact.stick_fraction == pytest.approx(reference["stick_fraction"], abs=1e-9)
    shorter = average(problem, periods=2 * cycle + 10, last=cycle - 1)["mu_eff"]
    assert abs(shorter / exact.mu_eff - 1.0) > 1e-6  # the cycle length matters
