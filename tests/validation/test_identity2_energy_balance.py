"""MODEL.md identity 2: energy balance over a period of a forced steady state.

The body's energy ½ m ẏ² − m g y changes by the work of P and of the contact force,
−∫ N ẏ dt = −∫ N δ̇ dt − ∫ N ż dt (δ = y − z). The moving surface does the work
W_base = −∫ N ż dt on the body through the contact (the surface end of the contact
carries −N), and while in contact N δ̇ = d/dt[S c_n δ^(m2+1)/(m2+1)] + D δ̇, with D
the damping part of N_raw (c δ̇ for Kelvin–Voigt, S c_n δ^m2 c δ̇/(m g) for
Hunt–Crossley). Over one period, therefore,

    ∫ P ẏ dt + W_base = ∫_contact D δ̇ dt + Σ_separations S c_n δ_s^(m2+1)/(m2+1),

the last term being the elastic energy given up where the body leaves the surface
while δ_s > 0 (Kelvin–Voigt separates where N_raw = 0, i.e. inside the overlap; it is 0
when every separation is at δ = 0). Each side is integrated along
``microslip.periodic_orbit`` (Gauss–Legendre on its node intervals, the laws of
``forced_reference``) and compared with the scipy steady orbit's own quadratures.
With ζ = 0 and no excitation, ``simulate`` conserves ½ m ẏ² − m g y + S c_n y^(m2+1)/(m2+1).
"""

import numpy as np
import pytest
from forced_reference import periodic_cases, steady_case
from orbit_quadrature import orbit_average

import microslip as ms


def _orbit_energies(orbit, ref):
    m, g, period = ref.m, ref.g, orbit.period
    scale = m * g * ref.y0  # energy scale of the scaled quadratures [J]

    def scaled(t, y, yd):
        tau = t * ref.omega
        u = ref.from_si(y, yd)
        return tau, u

    def work_in(t, y, yd):
        tau, u = scaled(t, y, yd)
        n = ref.normal_force(t, y, yd) / (m * g)
        return (ref.p(tau) * u[1] - n * ref.surface(tau)[1]) * ref.omega

    def damping_loss(t, y, yd):
        tau, u = scaled(t, y, yd)
        if ref.indicator(tau, u) <= 0.0:
            return 0.0
        raw, el = ref.raw(tau, u)
        return (raw - el) * ref.gap(tau, u)[1] * ref.omega

    def elastic(t, y, yd):
        tau, u = scaled(t, y, yd)
        if ref.indicator(tau, u) <= 0.0:
            return 0.0
        return ref.raw(tau, u)[1] * ref.gap(tau, u)[1] * ref.omega

    return tuple(
        orbit_average(orbit, fn) * period * scale for fn in (work_in, damping_loss, elastic)
    )


@pytest.mark.parametrize("name", sorted(periodic_cases()))
def test_energy_balance_over_a_forced_period(name):
    model, ref, _u, s = steady_case(name)
    # the reference balances (its quadratures ride along the integration)
    w_ref = s["work_P"] + s["work_base"]
    assert w_ref > 0.0
    assert abs(w_ref - s["dissipated"] - s["elastic_balance"]) < 1e-9 * w_ref
    if name == "kv_force" or name.startswith("hc"):  # no separation inside the overlap here
        assert abs(s["elastic_balance"]) < 1e-9 * w_ref
    orbit = ms.periodic_orbit(model)
    w_in, loss, given_up = _orbit_energies(orbit, ref)
    assert abs(w_in - loss - given_up) < 1e-8 * w_in, (name, w_in, loss, given_up)
    assert w_in == pytest.approx(w_ref, rel=1e-7)
    assert loss == pytest.approx(s["dissipated"], rel=1e-7)
    assert orbit.amplitude == pytest.approx(s["amplitude"], rel=1e-8)


@pytest.mark.parametrize("damping", [None, ms.Viscous(ratio=0.0), ms.HuntCrossley(ratio=0.0)])
def test_free_vibration_conserves_energy(damping):
    p = ms.Parameters()
    model = ms.Model(p, damping=damping)
    y0 = p.static_deflection
    amplitude = 1.6 * y0  # with loss of contact
    r = ms.simulate(model, force=0.0, amplitude=amplitude, duration=20.0 * p.natural_period)
    k = p.area * p.c_n
    energy = 0.5 * p.mass * r.ydot**2 - p.mass * p.g * r.y
    energy += k * np.maximum(r.y, 0.0) ** (p.m2 + 1.0) / (p.m2 + 1.0)
    drift = np.max(np.abs(energy - energy[0])) / (p.mass * p.g * y0)
    assert drift < 1e-9
