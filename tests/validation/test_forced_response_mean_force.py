"""MODEL.md identity 1: ⟨N⟩ = m g over every periodic forced orbit (eq. 2.4 averaged).

Averaging m ÿ = m g + P(t) - N over a period of a periodic orbit gives ⟨N⟩ = m g, with
damping, with any excitation and with loss of contact. N(t) is evaluated on the orbit's
dense output and integrated by Gauss–Legendre on each node interval (the contact
switches are nodes, so each piece is smooth).
"""

from __future__ import annotations

import numpy as np
import pytest

import microslip as ms
from microslip.analysis.orbit_table import orbit_state
from microslip.analysis.periodic import periodic_orbit
from microslip.model.normal import normal_force

P = ms.Parameters()
F0 = P.natural_frequency
Y0 = P.static_deflection

CASES = {
    "viscous": ms.Model(P, ms.Viscous(0.02), ms.HarmonicForce(0.6, 0.9 * F0)),
    "hunt-crossley": ms.Model(P, ms.HuntCrossley(0.05), ms.HarmonicForce(1.0, 1.2 * F0)),
    "base-motion": ms.Model(P, ms.Viscous(0.05), ms.BaseMotion(0.05 * Y0, 0.6 * F0)),
    "contact-loss": ms.Model(P, ms.Viscous(0.05), ms.HarmonicForce(3.0, 0.95 * F0)),
    "contact-loss-hunt-crossley": ms.Model(P, ms.HuntCrossley(0.1), ms.HarmonicForce(5.0, F0)),
    "prescribed": ms.Model(P, None, ms.PrescribedPenetration(Y0, 0.0, F0)),
}


def _mean_force(model, orbit):
    c = model.pack(0.0)
    nodes, weights = np.polynomial.legendre.leggauss(10)
    total = 0.0
    for k in range(orbit.t.size - 1):
        a, b = orbit.t[k], orbit.t[k + 1]
        if b <= a:
            continue
        for x, w in zip(nodes, weights, strict=True):
            t = 0.5 * (a + b) + 0.5 * (b - a) * x
            y, yd = orbit_state(t, orbit.t, orbit.y, orbit.ydot, orbit.accel_start, orbit.accel_end)
            total += 0.5 * (b - a) * w * normal_force(t, y, yd, c)
    return total / orbit.period


@pytest.mark.parametrize("name", list(CASES))
def test_mean_normal_force_is_weight(name):
    model = CASES[name]
    orbit = periodic_orbit(model)
    if name.startswith("contact-loss"):
        assert orbit.contact_lost and orbit.N_min == 0.0
    else:
        assert not orbit.contact_lost
    mean = _mean_force(model, orbit)
    assert abs(mean - P.mass * P.g) <= 1e-9 * P.mass * P.g
