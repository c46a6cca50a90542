"""docs/model-facts.md, fact 5, eq. (4.2), Figs. 4 and 6: when does the slider move at all?

Under a constant F >= 0 the slider moves iff F > μ min|R| = μ S c_n max(y0 − A, 0)^m2, the
friction limit at the highest point of the normal vibration; with loss of contact
(A > y0) any F > 0 moves it ("vibrating items drifting on a resting tabletop"). It never
moves backwards. The threshold is written out here from the paper's formula.
"""

import math

import numpy as np
import pytest

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection
DURATION = 0.02  # ≈ 27–29 normal periods
SLIP_START = ms.integrators.EVENT_NAMES.index("slip_start")


def threshold(params, amplitude):
    y0 = (params.mass * params.g / (params.area * params.c_n)) ** (1.0 / params.m2)
    return params.mu * params.area * params.c_n * max(y0 - amplitude, 0.0) ** params.m2


@pytest.mark.parametrize("method", ["event", "rk4"])
@pytest.mark.parametrize("fraction", [0.0, 1 / 3, 2 / 3, 0.9])
def test_just_below_the_threshold_the_slider_never_moves(method, fraction):
    force = threshold(P, fraction * Y0) * (1.0 - 1e-6)
    r = ms.simulate(P, force=force, amplitude=fraction * Y0, duration=DURATION, method=method)
    assert np.all(r.x == 0.0)
    assert np.all(r.xdot == 0.0)
    assert np.all(r.direction == 0.0)
    assert not np.any(r.event_kind == SLIP_START)
    assert np.all(r.Ft == -force)  # static equilibrium: F_tr = F (Fig. 5)
    assert ms.mean_velocity(P, force=force, amplitude=fraction * Y0) == 0.0


@pytest.mark.parametrize(("method", "excess"), [("event", 1e-6), ("rk4", 1e-5)])
@pytest.mark.parametrize("fraction", [1 / 3, 2 / 3, 0.9])
def test_just_above_the_threshold_it_slips_at_every_top(method, excess, fraction):
    amplitude = fraction * Y0
    force = threshold(P, amplitude) * (1.0 + excess)
    r = ms.simulate(P, force=force, amplitude=amplitude, duration=DURATION, method=method)
    assert r.x[-1] > 0.0
    # It slips from t = 0 (it starts at the top) and is released again near every top,
    # t = k T: that needs the dip of μ|R| below F, a double crossing inside one step,
    # to be found.
    tops = math.floor(DURATION / ms.free_period(P, amplitude))
    releases = r.event_t[r.event_kind == SLIP_START]
    assert releases.size == tops
    assert ms.mean_velocity(P, force=force, amplitude=amplitude) > 0.0
    # (RK4 at T0/200 resolves the top to ~1e-9 y0 only: with excess 1e-6 it misses some of
    # the releases at A = 0.9 y0, where the threshold is most sensitive to y.)


@pytest.mark.parametrize("method", ["event", "rk4"])
@pytest.mark.parametrize("fraction", [1.0, 1.3, 2.0])
def test_with_loss_of_contact_any_force_moves_it(method, fraction):
    amplitude = fraction * Y0
    assert threshold(P, amplitude) == 0.0
    r = ms.simulate(P, force=1e-9, amplitude=amplitude, duration=DURATION, method=method)
    assert r.x[-1] > 0.0
    tops = math.floor(DURATION / ms.free_period(P, amplitude))
    assert np.count_nonzero(r.event_kind == SLIP_START) == tops
    # ... but no force, no motion (even in flight, where the friction limit is 0).
    r0 = ms.simulate(P, force=0.0, amplitude=amplitude, duration=DURATION, method=method)
    assert np.all(r0.x == 0.0) and np.all(r0.xdot == 0.0)
    if fraction > 1.0:
        assert np.any(r0.state == 2)


@pytest.mark.parametrize("m2", [1.5, 3.0])
def test_threshold_for_other_exponents(m2):
    p = ms.Parameters(m2=m2, mu=0.2)
    y0 = p.static_deflection
    for fraction in (0.25, 0.75):
        amplitude = fraction * y0
        limit = threshold(p, amplitude)
        assert p.motion_threshold(amplitude) == pytest.approx(limit, rel=1e-13)
        below = ms.simulate(p, force=limit * (1 - 1e-6), amplitude=amplitude, duration=0.01)
        above = ms.simulate(p, force=limit * (1 + 1e-6), amplitude=amplitude, duration=0.01)
        assert np.all(below.x == 0.0)
        assert above.x[-1] > 0.0


@pytest.mark.parametrize("method", ["event", "rk4"])
@pytest.mark.parametrize("force", [0.05, 0.3, 0.5, 0.9, 1.5])
@pytest.mark.parametrize("fraction", [0.0, 0.5, 1.0, 1.5])
def test_never_moves_backwards(method, force, fraction):
    r = ms.simulate(P, force=force, amplitude=fraction * Y0, duration=0.01, method=method)
    assert np.all(np.diff(r.x) >= 0.0)
    assert np.all(r.xdot >= 0.0)
    assert np.all(r.direction >= 0.0)
    moves = force > threshold(P, fraction * Y0)
    assert (r.x[-1] > 0.0) == moves


def test_exactly_at_the_threshold_it_never_moves():
    """F = μ S c_n (y0 − A)^m2 exactly: (2.2) still sticks (|F| <= μ|R|), v = 0.

    Binary data make the threshold exact in any order of evaluation: m g = 16 N,
    S c_n = 2^44 N/m², y0 = 2^-20 m, A = y0/2, μ = 1/8, threshold 0.5 N.
    """
    p = ms.Parameters(mass=2.0, g=8.0, area=2.0**-8, c_n=2.0**52, m2=2.0, mu=0.125)
    amplitude = 2.0**-21
    assert p.static_deflection == 2.0**-20
    assert threshold(p, amplitude) == 0.5
    assert ms.mean_velocity(p, force=0.5, amplitude=amplitude) == 0.0
    cycle = ms.stick_slip_cycle(p, force=0.5, amplitude=amplitude)
    assert (cycle.slip_time, cycle.slip_distance, cycle.peak_velocity) == (0.0, 0.0, 0.0)
    assert math.isnan(cycle.release_time)
    assert ms.velocity_map(p, forces=[0.5], amplitudes=[amplitude]).item() == 0.0
    # One unit in the last place above it, the slider is released at the top.
    above = ms.stick_slip_cycle(p, force=math.nextafter(0.5, 1.0), amplitude=amplitude)
    assert above.release_time == pytest.approx(above.period, rel=1e-6)
