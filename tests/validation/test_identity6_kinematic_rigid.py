"""Identity 6 (docs/theory/friction_reduction.md): a body driven at a prescribed velocity
on a rigid tangential contact slides all the time, so F_t = μ(|v|) N at every instant and
μ_eff = <F_t>/<N> = μ(|v|) for every normal motion: free (with loss of contact), forced
(damped and undamped, with loss of contact, also not period-1), prescribed.

Checked on the exact path and, independently, from a time integration (simulate): the
friction force pointwise and the ratio of Simpson integrals over a window.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import simpson

import microslip as ms

P = ms.Parameters()  # the paper's contact: m2 = 2, μ = 0.1
Y0 = P.static_deflection
PUNCH = ms.Parameters(m2=1.0, c_n=1e8, area=1.0)

CASES = {
    "free, contact lost": (ms.Model(P), 1.5 * Y0),
    "forced undamped, contact lost, not period-1": (
        ms.Model(P, excitation=ms.HarmonicForce(amplitude=15.0, frequency=1400.0)), None),
    "forced viscous, contact lost": (
        ms.Model(P, damping=ms.Viscous(0.05),
                 excitation=ms.HarmonicForce(amplitude=12.0, frequency=1400.0)), None),
    "prescribed, contact lost": (
        ms.Model(PUNCH, excitation=ms.PrescribedPenetration(mean=1e-7, amplitude=1.5e-7,
                                                            frequency=1000.0)), None),
}  # fmt: skip


def _window(model: ms.Model, amplitude) -> tuple[np.ndarray, dict]:
    period = model.excitation.period if model.excitation else ms.free_period(P, amplitude)
    t = np.linspace(20 * period, 30 * period, 20_001)
    return t, ({} if amplitude is None else {"amplitude": amplitude})


@pytest.mark.parametrize("name", list(CASES))
@pytest.mark.parametrize("velocity", [2e-4, -3e-5])
def test_rigid_kinematic_drive_gives_mu_exactly(name, velocity):
    base, amplitude = CASES[name]
    model = base.replace(drive=ms.PrescribedVelocity(velocity))
    exact = ms.effective_friction(model, amplitude=amplitude)
    assert exact.method == "exact"
    assert exact.mu_eff == model.params.mu and exact.ratio == 1.0
    assert exact.stick_fraction == 0.0
    # time integration: F_t along the drive equals μ N at every sample, loss of contact too
    t, kwargs = _window(model, amplitude)
    run = ms.simulate(model, duration=t[-1], t_eval=t, **kwargs)
    along = -np.sign(velocity) * run.Ft
    assert run.N.min() == 0.0  # the contact is lost in every case
    np.testing.assert_allclose(along, model.params.mu * run.N, rtol=1e-14, atol=0.0)
    ratio = simpson(along, x=t) / simpson(run.N, x=t)
    assert ratio == pytest.approx(exact.mu_eff, rel=1e-13)
    # <N> of the exact path: m g for a body (identity 1), the quadrature of δ(t) if prescribed
    if not isinstance(model.excitation, ms.PrescribedPenetration):
        assert exact.mean_normal_force == pytest.approx(P.mass * P.g, rel=1e-9)
    else:
        period = model.excitation.period
        tt = np.linspace(0.0, period, 200_001)
        n = PUNCH.stiffness_coefficient * np.maximum(1e-7 + 1.5e-7 * np.cos(2e3 * np.pi * tt), 0)
        assert exact.mean_normal_force == pytest.approx(simpson(n, x=tt) / period, rel=1e-9)


def test_static_kinetic_and_stribeck_rigid_give_their_sliding_coefficient():
    """μ_eff is the kinetic coefficient at the drive speed: μ_k (not μ_s), and Stribeck's
    μ(|v|) (not μ(0) = μ_s, not μ(∞) = μ_k), from the exact path and a simulation."""
    amplitude = 1.5 * Y0
    stribeck = ms.Stribeck(mu_static=0.2, mu_kinetic=0.1, velocity=1e-4, exponent=2.0)
    for friction, velocity, expected in (
        (ms.StaticKinetic(0.2, 0.1), 3e-4, 0.1),
        (stribeck, 1e-4, 0.1 + 0.1 * np.exp(-1.0)),
        (stribeck, -2e-4, 0.1 + 0.1 * np.exp(-4.0)),
    ):
        model = ms.Model(P, friction=friction, drive=ms.PrescribedVelocity(velocity))
        exact = ms.effective_friction(model, amplitude=amplitude)
        assert exact.mu_eff == pytest.approx(expected, rel=1e-15)
        assert exact.mu_kinetic == exact.mu_eff and exact.ratio == 1.0
        t, kwargs = _window(model, amplitude)
        run = ms.simulate(model, duration=t[-1], t_eval=t, **kwargs)
        along = -np.sign(velocity) * run.Ft
        assert simpson(along, x=t) / simpson(run.N, x=t) == pytest.approx(expected, rel=1e-13)


def test_a_stribeck_curve_is_mu_of_each_drive_speed():
    """Over a curve of drive speeds each point is μ(|v|) of its own speed (the velocity
    axis is evaluated in one compiled loop: a shifted or shared index would fail)."""
    stribeck = ms.Stribeck(mu_static=0.3, mu_kinetic=0.1, velocity=2e-4, exponent=1.5)
    model = ms.Model(P, friction=stribeck, drive=ms.PrescribedVelocity(1e-4))
    speeds = np.array([-8e-4, -1e-4, 5e-5, 2e-4, 3e-3])
    curve = ms.effective_friction_curve(model, speeds, amplitude=1.5 * Y0)
    expected = 0.1 + 0.2 * np.exp(-((np.abs(speeds) / 2e-4) ** 1.5))
    np.testing.assert_allclose(curve.mu_eff.values, expected, rtol=1e-15)
    np.testing.assert_array_equal(curve.mu_kinetic.values, curve.mu_eff.values)


def test_identity6_fails_for_a_compliant_contact():
    """The identity needs the rigid contact: the same free vibration with a finite k_t
    reduces friction (so the checks above can tell the two apart)."""
    model = ms.Model(P, tangential=ms.TangentialSpring(1e6), drive=ms.PrescribedVelocity(1e-4))
    result = ms.effective_friction(model, amplitude=1.5 * Y0)
    assert result.ratio < 0.5 and result.stick_fraction > 0.1
