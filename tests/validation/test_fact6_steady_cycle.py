"""docs/model-facts.md, fact 6, Figs. 5 and 7: the steady stick–slip cycle and the mean velocity.

For F < μ m g the slider sticks once per normal period and, from its first stick on, the
motion is exactly periodic, so between two stick starts k > j >= 1 (the 0-th one ends
the start-up slide from rest at the top, which is not a steady slip)

    v = (x_k − x_j) / (t_k − t_j).

``mean_velocity`` / ``stick_slip_cycle`` compute the steady cycle semi-analytically; here
they are checked against long event-driven runs of ``simulate`` and against the
independent scipy reference, and their limits (no motion, no steady state) are checked.
"""

import math
import warnings

import numpy as np
import pytest

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection
TIGHT = {"rtol": 1e-12, "atol": 1e-14}
STICK_START = ms.integrators.EVENT_NAMES.index("stick_start")
SLIP_START = ms.integrators.EVENT_NAMES.index("slip_start")
FRACTIONS = [1 / 3, 2 / 3, 1.0, 1.3]
CASES = [(a, f) for a in FRACTIONS for f in (0.2, 0.5, 0.9) if f > P.motion_threshold(a * Y0)]


def steady_velocity(times, xs):
    assert times.size >= 3
    return (xs[-1] - xs[1]) / (times[-1] - times[1])


@pytest.mark.parametrize(("fraction", "force"), CASES)
def test_mean_velocity_matches_a_long_simulation(fraction, force):
    amplitude = fraction * Y0
    v = ms.mean_velocity(P, force=force, amplitude=amplitude)
    assert v > 0.0
    r = ms.simulate(P, force=force, amplitude=amplitude, duration=0.05, **TIGHT)  # ≈ 60–74 T
    stops = r.event_kind == STICK_START
    v_sim = steady_velocity(r.event_t[stops], r.event_states[stops, 2])
    assert v_sim == pytest.approx(v, rel=1e-8)  # measured <= 1.5e-9
    # Exactly periodic after the first stick: stick starts are one free period apart.
    period = ms.free_period(P, amplitude)
    np.testing.assert_allclose(np.diff(r.event_t[stops][1:]), period, rtol=1e-9)


@pytest.mark.parametrize(("fraction", "force"), CASES)
def test_mean_velocity_at_default_tolerances(fraction, force):
    amplitude = fraction * Y0
    v = ms.mean_velocity(P, force=force, amplitude=amplitude)
    r = ms.simulate(P, force=force, amplitude=amplitude, duration=0.05)
    stops = r.event_kind == STICK_START
    # measured <= 1.5e-7 (A = y0/3, F = 0.5 N: the smallest slips), mostly ~1e-8
    assert steady_velocity(r.event_t[stops], r.event_states[stops, 2]) == pytest.approx(v, rel=1e-6)


@pytest.mark.parametrize(("fraction", "force"), [(a, 0.5) for a in FRACTIONS] + [(1.3, 0.2)])
def test_mean_velocity_matches_scipy(reference, fraction, force):
    amplitude = fraction * Y0
    ref = reference(P, force=force, amplitude=amplitude, t_eval=[0.0, 0.02])
    times, xs = ref.events_of("stick_start")
    v_ref = steady_velocity(times, xs)
    assert ms.mean_velocity(P, force=force, amplitude=amplitude) == pytest.approx(v_ref, rel=1e-9)


@pytest.mark.parametrize(("fraction", "force"), CASES)
def test_stick_slip_cycle_is_consistent_with_the_simulation(fraction, force):
    amplitude = fraction * Y0
    cycle = ms.stick_slip_cycle(P, force=force, amplitude=amplitude)
    period = ms.free_period(P, amplitude)
    assert cycle.period == pytest.approx(period, rel=1e-12)
    assert cycle.slip_distance / cycle.period == pytest.approx(cycle.mean_velocity, rel=1e-15)
    assert cycle.mean_velocity == ms.mean_velocity(P, force=force, amplitude=amplitude)
    assert cycle.slip_time + cycle.stick_time == pytest.approx(cycle.period, rel=1e-15)
    assert 0.0 < cycle.slip_time < cycle.period
    assert cycle.moves

    r = ms.simulate(P, force=force, amplitude=amplitude, duration=10.5 * period, **TIGHT)
    stops = np.nonzero(r.event_kind == STICK_START)[0]
    starts = np.nonzero(r.event_kind == SLIP_START)[0]
    # Steady slips: released at the cycle's release time after each top (tops at k T) ...
    releases = r.event_t[starts]
    phase = releases - np.round((releases - cycle.release_time) / period) * period
    np.testing.assert_allclose(phase, cycle.release_time, rtol=0, atol=1e-9 * period)
    # ... for slip_time, sliding slip_distance each.
    steady_stops = r.event_t[stops[1:]]
    np.testing.assert_allclose(
        steady_stops - releases[: steady_stops.size], cycle.slip_time, rtol=0, atol=1e-9 * period
    )
    np.testing.assert_allclose(np.diff(r.event_states[stops, 2]), cycle.slip_distance, rtol=1e-8)
    # The peak speed is reached where μ|R| rises through F again: by time symmetry of the
    # normal motion, T − release_time after a top.
    t_peak = 5 * period + (period - cycle.release_time)
    s = ms.simulate(P, force=force, amplitude=amplitude, duration=t_peak, t_eval=[t_peak], **TIGHT)
    assert s.xdot[0] == pytest.approx(cycle.peak_velocity, rel=1e-8)


@pytest.mark.parametrize("fraction", [0.0, 1 / 3, 2 / 3, 0.9, 0.999])
def test_no_motion_below_the_threshold(fraction):
    amplitude = fraction * Y0
    limit = P.mu * P.area * P.c_n * (Y0 - amplitude) ** 2
    for force in (0.0, 0.5 * limit, limit * (1 - 1e-9)):
        assert ms.mean_velocity(P, force=force, amplitude=amplitude) == 0.0
        cycle = ms.stick_slip_cycle(P, force=force, amplitude=amplitude)
        assert (cycle.slip_distance, cycle.mean_velocity, cycle.slip_time) == (0.0, 0.0, 0.0)
        assert cycle.peak_velocity == 0.0
        assert cycle.stick_time == cycle.period == pytest.approx(ms.free_period(P, amplitude))
        assert not cycle.moves
        assert math.isnan(cycle.release_time)


@pytest.mark.parametrize("fraction", [1 / 3, 2 / 3, 0.9, 0.999])
def test_never_negative_just_above_the_threshold(fraction):
    """The slider never slides backwards: no negative rounding residue (fixed bug)."""
    amplitude = fraction * Y0
    limit = P.motion_threshold(amplitude)
    for excess in np.logspace(-9, -3, 25):
        force = limit * (1.0 + excess)
        v = ms.mean_velocity(P, force=force, amplitude=amplitude)
        cycle = ms.stick_slip_cycle(P, force=force, amplitude=amplitude)
        assert v >= 0.0
        assert cycle.slip_distance >= 0.0 and cycle.peak_velocity >= 0.0


def test_mean_velocity_grows_with_the_force_and_the_amplitude():
    forces = np.linspace(0.05, 0.97, 24)
    rows = []
    for fraction in (0.2, 0.5, 0.8, 1.0, 1.3, 2.0):
        amplitude = fraction * Y0
        v = np.array([ms.mean_velocity(P, force=f, amplitude=amplitude) for f in forces])
        moving = forces > P.motion_threshold(amplitude)
        assert np.all(v[~moving] == 0.0) and np.all(v[moving] > 0.0)
        assert np.all(np.diff(v[moving]) > 0.0)
        rows.append(v)
    rows = np.array(rows)
    assert np.all(np.diff(rows, axis=0) >= 0.0)


@pytest.mark.parametrize("fraction", [0.0, 1 / 3, 1.3])
def test_no_steady_state_above_mu_m_g(fraction):
    force = P.static_friction_force * 1.01
    with pytest.warns(RuntimeWarning, match="exceeds"):
        v = ms.mean_velocity(P, force=force, amplitude=fraction * Y0)
    assert v == math.inf
    with pytest.raises(ValueError, match="force"):
        ms.stick_slip_cycle(P, force=force, amplitude=fraction * Y0)
    # The simulation: once the drift G(t) = (F − μ m g) t/m + μ(ẏ(t) − ẏ(0)) outgrows its
    # periodic part (within the first period) the slider never sticks again, and between
    # equal phases of the normal motion ẋ grows by exactly (F/m − μ g) × time.
    if fraction > 0.0:
        period = ms.free_period(P, fraction * Y0)
        tops = np.arange(2, 15) * period
        r = ms.simulate(P, force=force, amplitude=fraction * Y0, duration=tops[-1], **TIGHT)
        assert not np.any((r.event_kind == STICK_START) & (r.event_t > period))
        s = ms.simulate(
            P, force=force, amplitude=fraction * Y0, duration=tops[-1], t_eval=tops, **TIGHT
        )
        gain = (force / P.mass - P.mu * P.g) * period
        np.testing.assert_allclose(np.diff(s.xdot), gain, rtol=1e-7)


def test_at_mu_m_g_no_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        v = ms.mean_velocity(P, force=P.static_friction_force, amplitude=Y0 / 3)
    assert 0.0 < v < math.inf


@pytest.mark.parametrize("bad", [{"force": -0.1}, {"amplitude": -1e-9}, {"force": math.nan}])
def test_bad_input(bad):
    kwargs = {"force": 0.5, "amplitude": Y0 / 3, **bad}
    with pytest.raises(ValueError, match=next(iter(bad))):
        ms.mean_velocity(P, **kwargs)
    with pytest.raises(ValueError, match=next(iter(bad))):
        ms.stick_slip_cycle(P, **kwargs)
