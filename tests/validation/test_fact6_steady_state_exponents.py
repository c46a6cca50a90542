"""docs/model-facts.md, fact 6 for interface exponents m2 != 2: the exact steady stick–slip cycle.

``mean_velocity``, ``stick_slip_cycle`` and ``velocity_map`` are checked against the
reflected process of the free drift G(t) = ∫ (F − μ|R|)/m dt (eqs. 2.2, 2.5), with the
normal motion (2.3)–(2.4) integrated by scipy's DOP853 (``reflected_process.py``, which
shares no code with microslip), for m2 = 1, 10/9, 1.5, 2.5, 3, several forces and
amplitudes, with and without loss of contact (A > y0). The release height
y* = (F/(μ S c_n))^(1/m2) depends on m2: code that fixes it at m2 = 2 passes every
test at the paper's data and fails here.
"""

import math

import numpy as np
import pytest
from reflected_process import reflected_cycle
from scipy_reference import steady_mean_velocity

import microslip as ms

EXPONENTS = [1.0, 10 / 9, 1.5, 2.5, 3.0]
PAPER = ms.Parameters()


def params(m2, **changes):
    """The paper's data with ``changes``, exponent m2 and c_n keeping the paper's y0 [m]."""
    base = PAPER.replace(**changes)
    c_n = base.mass * base.g / (base.area * PAPER.static_deflection**m2)
    return base.replace(m2=m2, c_n=c_n)


FRACTIONS = [0.3, 0.8, 1.3]  # A / y0; 1.3: loss of contact
PHIS = [0.3, 0.7, 0.95]  # F / (μ m g)


def tolerance(m2, fraction):
    """Relative accuracy of microslip's steady state, as measured against the reference.

    In contact (A < y0), or for the smooth laws m2 = 1, 2, 3 (and 2.5, smooth enough):
    <= 6e-12 (measured). With loss of contact and m2 = 10/9 or 1.5, |R| ∝ y^m2 is not
    smooth at touchdown, where microslip's orbit table takes fixed 5th-order steps from
    y = 0: the period is off by 4.6e-9 (10/9) and 4.3e-10 (1.5), the mean velocity by
    8.6e-8 and 6.4e-9 (measured; a known limitation of the table, not of this test).
    """
    if fraction > 1.0 and m2 < 2.0 and m2 != 1.0:
        return 2e-7 if m2 < 1.2 else 2e-8
    return 1e-10


def cases():
    out = []
    for m2 in EXPONENTS:
        p = params(m2)
        for fraction in FRACTIONS:
            for phi in PHIS:
                force = phi * p.static_friction_force
                if force > p.motion_threshold(fraction * p.static_deflection):
                    out.append((m2, fraction, phi))
    return out


CASES = cases()


def test_the_cases_cover_each_exponent_with_and_without_contact_loss():
    for m2 in EXPONENTS:
        assert {f for e, f, _ in CASES if e == m2} == set(FRACTIONS)


@pytest.mark.parametrize(("m2", "fraction", "phi"), CASES)
def test_stick_slip_cycle_matches_the_reflected_process(m2, fraction, phi):
    p = params(m2)
    amplitude = fraction * p.static_deflection
    force = phi * p.static_friction_force
    ref = reflected_cycle(p, force=force, amplitude=amplitude)
    assert ref.repeat_error < 1e-11  # the reference's own cycle is periodic
    rel = tolerance(m2, fraction)
    cycle = ms.stick_slip_cycle(p, force=force, amplitude=amplitude)
    assert cycle.period == pytest.approx(ref.period, rel=rel)
    assert cycle.slip_time == pytest.approx(ref.slip_time, rel=rel)
    assert cycle.stick_time == pytest.approx(ref.period - ref.slip_time, rel=rel)
    assert cycle.slip_distance == pytest.approx(ref.slip_distance, rel=rel)
    assert cycle.peak_velocity == pytest.approx(ref.peak_velocity, rel=rel)
    assert cycle.mean_velocity == pytest.approx(ref.mean_velocity, rel=rel)
    assert cycle.release_time == pytest.approx(ref.release_time, rel=0, abs=rel * ref.period)
    assert ms.mean_velocity(p, force=force, amplitude=amplitude) == cycle.mean_velocity


@pytest.mark.parametrize(("m2", "fraction"), [(1.5, 0.8), (2.5, 1.3), (1.0, 0.7)])
def test_other_mass_gravity_and_friction(m2, fraction):
    """m, g and μ enter separately (m = 1 kg hides a swapped m)."""
    p = params(m2, mass=2.5, g=3.7, mu=0.3)
    amplitude = fraction * p.static_deflection
    force = 0.6 * p.static_friction_force
    ref = reflected_cycle(p, force=force, amplitude=amplitude)
    cycle = ms.stick_slip_cycle(p, force=force, amplitude=amplitude)
    rel = tolerance(m2, fraction)
    got = (cycle.period, cycle.slip_time, cycle.slip_distance, cycle.peak_velocity)
    want = (ref.period, ref.slip_time, ref.slip_distance, ref.peak_velocity)
    np.testing.assert_allclose(got, want, rtol=rel, atol=0)


@pytest.mark.parametrize("m2", EXPONENTS)
def test_velocity_map_matches_the_reflected_process(m2):
    """The parallel grid kernel is a separate code path from ``mean_velocity``."""
    p = params(m2, mu=0.15, mass=0.4, g=12.0)
    y0 = p.static_deflection
    phis = np.array([0.5, 0.9])
    fractions = np.array([0.6, 1.3])
    v = ms.velocity_map(p, forces=phis * p.static_friction_force, amplitudes=fractions * y0).values
    for i, phi in enumerate(phis):
        for j, fraction in enumerate(fractions):
            force = phi * p.static_friction_force
            amplitude = fraction * y0
            if force <= p.motion_threshold(amplitude):
                assert v[i, j] == 0.0
                continue
            ref = reflected_cycle(p, force=force, amplitude=amplitude)
            assert v[i, j] == pytest.approx(ref.mean_velocity, rel=tolerance(m2, fraction))


@pytest.mark.parametrize("m2", [10 / 9, 1.5, 2.5])
def test_release_at_the_exponent_dependent_height(m2):
    """Sliding starts where μ S c_n y^m2 = F on the rising branch, for this m2."""
    p = params(m2, mu=0.2)
    amplitude = 0.7 * p.static_deflection
    force = 0.6 * p.static_friction_force
    cycle = ms.stick_slip_cycle(p, force=force, amplitude=amplitude)
    r = ms.simulate(
        p,
        force=force,
        amplitude=amplitude,
        duration=cycle.release_time + 2.0 * cycle.period,
        t_eval=[cycle.release_time + cycle.period],
        rtol=1e-12,
        atol=1e-14,
    )
    height = (force / (p.mu * p.area * p.c_n)) ** (1.0 / m2)
    assert r.y[0] == pytest.approx(height, rel=1e-9)
    assert r.ydot[0] < 0.0  # rising (y is positive downward)


@pytest.mark.parametrize(("m2", "fraction"), [(1.5, 0.8), (2.5, 1.3)])
def test_the_reference_agrees_with_the_event_driven_scipy_reference(m2, fraction):
    """Two independent scipy methods (reflected process, stick/slip events) agree."""
    p = params(m2)
    amplitude = fraction * p.static_deflection
    force = 0.7 * p.static_friction_force
    ref = reflected_cycle(p, force=force, amplitude=amplitude)
    events = steady_mean_velocity(p, force, amplitude, rtol=1e-12)
    assert ref.mean_velocity == pytest.approx(events, rel=1e-9)


@pytest.mark.parametrize("m2", EXPONENTS)
def test_threshold_and_above_it_for_other_exponents(m2):
    """v = 0 exactly just below μ S c_n (y0 − A)^m2, and the right v just above."""
    p = params(m2)
    y0 = p.static_deflection
    amplitude = 0.5 * y0
    limit = p.mu * p.area * p.c_n * (y0 - amplitude) ** m2
    assert ms.mean_velocity(p, force=limit * (1.0 - 1e-7), amplitude=amplitude) == 0.0
    force = limit * 1.05
    ref = reflected_cycle(p, force=force, amplitude=amplitude)
    v = ms.mean_velocity(p, force=force, amplitude=amplitude)
    assert v > 0.0
    assert v == pytest.approx(ref.mean_velocity, rel=1e-9)
    assert math.isfinite(v)
