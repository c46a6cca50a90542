"""Eq. (4.1): without normal vibration (A = 0) the slider is held up to F_t0 = μ m g.

The slider sticks while |F| <= μ|R| (2.2), and at rest at the working point |R| = m g
(2.4): at A = 0 the steady mean velocity is 0 for every F <= μ m g, the equality
included, and there is no steady state above it. The normal period is then the
small-amplitude one, T0 = 2π sqrt(y0 / (m2 g)) (Sec. 3), written out here.
"""

import math

import numpy as np
import pytest

import microslip as ms

PAPER = ms.Parameters()


def params(m2):
    """m = 2.5 kg, g = 3.7 m/s² (m = 1 would hide a swapped m), c_n keeping the paper's y0."""
    c_n = 2.5 * 3.7 / (PAPER.area * PAPER.static_deflection**m2)
    return PAPER.replace(m2=m2, c_n=c_n, mass=2.5, g=3.7)


@pytest.mark.parametrize("m2", [1.5, 2.0, 3.0])
def test_held_up_to_and_at_mu_m_g(m2):
    p = params(m2)
    limit = p.mu * p.mass * p.g
    t0 = 2.0 * math.pi * math.sqrt(p.static_deflection / (m2 * p.g))
    for force in (0.0, 0.5 * limit, limit):
        assert ms.mean_velocity(p, force=force, amplitude=0.0) == 0.0
        cycle = ms.stick_slip_cycle(p, force=force, amplitude=0.0)
        assert cycle.period == pytest.approx(t0, rel=1e-13)
        assert cycle.stick_time == pytest.approx(t0, rel=1e-13)
        assert (cycle.slip_time, cycle.slip_distance, cycle.peak_velocity) == (0.0, 0.0, 0.0)
        assert math.isnan(cycle.release_time)
        assert not cycle.moves


def test_velocity_map_at_zero_amplitude():
    """The grid kernel's A = 0 column: 0 up to μ m g inclusive, inf above."""
    p = params(2.0)
    limit = p.mu * p.mass * p.g
    forces = np.array([0.3 * limit, limit, 1.001 * limit])
    with pytest.warns(RuntimeWarning, match="no steady state"):
        v = ms.velocity_map(p, forces=forces, amplitudes=[0.0, 0.5 * p.static_deflection])
    assert v.values[0, 0] == 0.0 and v.values[1, 0] == 0.0
    assert v.values[2, 0] == math.inf and v.values[2, 1] == math.inf
    assert 0.0 < v.values[1, 1] < math.inf  # vibration frees the slider at F = μ m g


def test_above_mu_m_g_the_warning_names_the_caller():
    p = params(2.0)
    force = p.mu * p.mass * p.g * (1.0 + 1e-9)
    with pytest.warns(RuntimeWarning, match="exceeds") as record:
        assert ms.mean_velocity(p, force=force, amplitude=0.0) == math.inf
    assert record[0].filename == __file__  # points at the user's line, not at microslip
