"""Sec. 3 of the paper: static deflection y0 ≈ 2.25e-7 m, K_n = 2 sqrt(m g S c_n), f0 = 1485 Hz.

Also docs/model-facts.md, fact 1: y0 = (m g / (S c_n))^(1/m2) and
f0 = (1/2π) sqrt(m2 g / y0), and the
free vibration tends to f0 as its amplitude goes to zero.
"""

import itertools
import math

import pytest

import microslip as ms

P = ms.Parameters()


def test_static_deflection_is_the_papers_value():
    # "y0 = δ0 = 2.25·10^-7 m" (3 significant figures in the paper).
    assert P.static_deflection == pytest.approx(2.25e-7, abs=0.005e-7)
    assert P.static_deflection == pytest.approx((9.81 / (42.735e-4 * 4.52e16)) ** 0.5, rel=1e-15)
    # Fig. 7 text: loss of contact for A > 0.225 µm.
    assert round(P.static_deflection * 1e6, 3) == 0.225


def test_contact_stiffness_and_natural_frequency_are_the_papers():
    k_n = 2.0 * math.sqrt(1.0 * 9.81 * 42.735e-4 * 4.52e16)
    assert P.contact_stiffness == pytest.approx(k_n, rel=1e-14)
    f0 = math.sqrt(k_n / 1.0) / (2.0 * math.pi)
    assert P.natural_frequency == pytest.approx(f0, rel=1e-14)
    assert round(P.natural_frequency) == 1485  # "f0 = 1485 Hz"


def test_static_friction_force_is_the_papers():
    assert P.static_friction_force == pytest.approx(0.981, rel=1e-15)  # F_t0 = μ m g, eq. (4.1)


@pytest.mark.parametrize("m2", [1.0, 1.5, 2.0, 3.0])
def test_fact1_small_amplitude_frequency(m2):
    p = ms.Parameters(m2=m2)
    y0 = (p.mass * p.g / (p.area * p.c_n)) ** (1.0 / m2)
    f0 = math.sqrt(m2 * p.g / y0) / (2.0 * math.pi)
    assert p.natural_frequency == pytest.approx(f0, rel=1e-13)
    assert ms.free_frequency(p, amplitude=0.0) == pytest.approx(f0, rel=1e-13)
    # The free vibration's frequency tends to f0 (the error is O(a²), Lindstedt–Poincaré).
    for a in (1e-3, 1e-4):
        assert ms.free_frequency(p, amplitude=a * y0) / f0 - 1.0 == pytest.approx(
            -(m2 - 1.0) * (2.0 * m2 + 1.0) * a * a / 48.0, rel=0.05, abs=1e-11
        )


def test_frequency_falls_as_the_amplitude_grows():
    # Sec. 3: "As the amplitude rises ... the frequency decreases (Fig. 2b,c)".
    y0 = P.static_deflection
    freqs = [ms.free_frequency(P, amplitude=a * y0) for a in (0.0, 0.01, 1 / 3, 2 / 3, 1, 1.3, 2)]
    assert all(later < earlier for earlier, later in itertools.pairwise(freqs))
    assert freqs[0] == pytest.approx(P.natural_frequency, rel=1e-14)
