"""MODEL.md identity 3: small excitation and small damping give the linear oscillator of
stiffness K_n = m2 m g / y0 and damping c = 2 ζ sqrt(K_n m).

Harmonic force P0 sin ωt:  amplitude → P0 / sqrt((K_n − m ω²)² + (c ω)²).

Base motion z = Z sin ωt: with x = y − y0 the linearised law gives
m ẍ + c ẋ + K_n x = K_n z + c ż (Kelvin–Voigt and Hunt–Crossley linearise alike), so

    amplitude → Z sqrt(K_n² + (c ω)²) / sqrt((K_n − m ω²)² + (c ω)²).

How fast: the contact's quadratic and cubic terms change the first harmonic only at
second order (the quadratic term feeds the mean and the 2nd harmonic; these return to
the 1st harmonic at order a², like the backbone shift κ a²), and (y_max − y_min)/2
differs from the first harmonic by O(a²) relative too. So the relative error is
∝ (forcing)²: doubling the forcing must multiply it by 4 (measured with the scipy
reference: 8.87e-7 → 3.55e-6 for P0 = 0.01 → 0.02 N, ratio 4.000). A wrong linear
limit (a wrong K_n, c or ω) leaves an error that does not shrink with the forcing.
"""

import math

import pytest
from forced_reference import base_linear_amplitude, linear_amplitude

import microslip as ms

RATIO = 0.05  # damping ratio
AT = 0.8  # f / f0


def _relative_errors(kind):
    p = ms.Parameters()
    f = AT * p.natural_frequency
    c = 2.0 * RATIO * math.sqrt(p.contact_stiffness * p.mass)
    errors = []
    for level in (1.0, 2.0):
        if kind == "force":
            p0 = 0.01 * level
            model = ms.Model(p, damping=ms.Viscous(RATIO), excitation=ms.HarmonicForce(p0, f))
            closed = linear_amplitude(p.contact_stiffness, p.mass, c, p0, f)
        else:
            z0 = 0.005 * level * p.static_deflection
            model = ms.Model(p, damping=ms.HuntCrossley(RATIO), excitation=ms.BaseMotion(z0, f))
            closed = base_linear_amplitude(p.contact_stiffness, p.mass, c, z0, f)
        errors.append(ms.periodic_orbit(model).amplitude / closed - 1.0)
    return errors


@pytest.mark.parametrize("kind", ["force", "base"])
def test_linear_limit_and_its_rate(kind):
    small, large = _relative_errors(kind)
    assert abs(small) < 1e-4  # 8.9e-7 (force), 2.2e-5 (base) by the scipy reference
    assert 3.6 < large / small < 4.4, (small, large)


def test_reference_matches_the_linear_oscillator_exactly_for_m2_1():
    """The reference itself: with m2 = 1 and no contact loss the law is exactly linear."""
    from forced_reference import NormalReference

    p = ms.Parameters(m2=1.0)
    f = AT * p.natural_frequency
    c = 2.0 * RATIO * math.sqrt(p.contact_stiffness * p.mass)
    model = ms.Model(p, damping=ms.Viscous(RATIO), excitation=ms.HarmonicForce(2.0, f))
    ref = NormalReference(model)
    amplitude = ref.period_summary(ref.steady_orbit(periods=60))["amplitude"]
    closed = linear_amplitude(p.contact_stiffness, p.mass, c, 2.0, f)
    assert amplitude == pytest.approx(closed, rel=1e-11)
