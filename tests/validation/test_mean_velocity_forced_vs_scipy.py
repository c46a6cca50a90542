"""MODEL.md identity 5 under excitation: ``mean_velocity(model, force=0.5)`` on the stable
periodic orbit against a long event-driven scipy simulation of the full system.

The reference (``sliding_reference.SlidingReference``) integrates normal + tangential
motion together (rigid tangential contact, Coulomb μ, constant F), with every contact,
stick→slip (μ N falls to F) and slip→stop (ẋ = 0) switch a terminal event, from the
normal steady state reached from rest (the scipy fixed point) with the slider at rest;
after the first stick the motion repeats every period, and the mean velocity is Δx/Δt
between the second stick and the last one a whole number of periods later (6 periods:
the 12-period value differs by 4e-13 relative). Viscous ζ = 0.05, P0 = 3 N at 0.8 f0
(A = 0.46 y0, no contact loss): v = 1.3980e-5 m/s.
"""

import pytest
from forced_reference import NormalReference
from sliding_reference import SlidingReference

import microslip as ms


@pytest.fixture(scope="module")
def case():
    p = ms.Parameters()
    model = ms.Model(
        p, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(3.0, 0.8 * p.natural_frequency)
    )
    ref = NormalReference(model)
    u = ref.steady_orbit(periods=100)
    return model, SlidingReference(ref, 0.5).mean_velocity(u, periods=6)


def test_mean_velocity_under_excitation(case):
    model, v_ref = case
    assert v_ref > 0.0
    assert ms.mean_velocity(model, force=0.5) == pytest.approx(v_ref, rel=1e-8)
