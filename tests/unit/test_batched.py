"""The batched RK4 kernel: lane by lane the single-trajectory rk4 kernel, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from microslip import Parameters, simulate
from microslip.analysis.steady_state import stick_slip_cycle
from microslip.integrators import integrate
from microslip.integrators.batched import BatchResult, simulate_batch, time_grid
from microslip.model.coefficients import FORCE, SIZE, pack

PAPER = Parameters()
Y0 = PAPER.static_deflection
T0 = PAPER.natural_period
DT = T0 / 200
MU_MG = PAPER.static_friction_force


def _lanes(params, forces, amplitudes):
    """Coefficients and paper initial states (rest at the top) for (F, A) pairs."""
    forces = np.asarray(forces, dtype=float)
    amplitudes = np.asarray(amplitudes, dtype=float)
    coeffs = np.repeat(pack(params, 0.0)[None, :], forces.size, axis=0)
    coeffs[:, FORCE] = forces
    states = np.zeros((forces.size, 4))
    states[:, 0] = params.static_deflection - amplitudes
    return coeffs, states


def _mixed_set():
    """Stick only, stick-slip, loss of contact, F = 0, F = μ m g and F > μ m g."""
    pairs = [
        (0.0, Y0 / 3),
        (0.0, 1.3 * Y0),
        (0.2, Y0 / 3),  # below the motion threshold: sticks for ever
        (0.5, Y0 / 3),
        (0.5, 2 * Y0 / 3),
        (0.5, Y0),
        (0.5, 1.3 * Y0),  # momentary loss of contact
        (0.9, 0.0),  # no vibration, below μ m g: rest
        (0.95, 1.3 * Y0),
        (MU_MG, Y0 / 2),
        (1.2, 2 * Y0 / 3),  # F > μ m g: slides for ever
        (1.2, 0.0),
        (PAPER.motion_threshold(0.5 * Y0), 0.5 * Y0),  # exactly at the threshold
        (PAPER.motion_threshold(0.5 * Y0) * (1 + 1e-9), 0.5 * Y0),
    ]
    forces, amplitudes = zip(*pairs, strict=True)
    return np.array(forces), np.array(amplitudes)


def _scalar_final(params, force, amplitude, duration, dt):
    run = simulate(
        params, force=force, amplitude=amplitude, duration=duration, method="rk4", dt=dt,
        save_every=10**9,
    )  # fmt: skip
    state = np.array(
        [run.y[-1], run.ydot[-1], run.x[-1], run.xdot[-1], run.u[-1], run.spring_force[-1]]
    )
    return state, run.t[-1], run.direction[-1], run.event_t.size


@pytest.fixture(scope="module")
def mixed():
    forces, amplitudes = _mixed_set()
    coeffs, states0 = _lanes(PAPER, forces, amplitudes)
    duration = 6.3 * T0
    return forces, amplitudes, coeffs, states0, duration


def test_matches_scalar_rk4_kernel_bit_for_bit(mixed):
    forces, amplitudes, coeffs, states0, duration = mixed
    result = simulate_batch(coeffs, states0, duration, DT)
    assert isinstance(result, BatchResult)
    assert result.n_switches.sum() > 20  # the set really switches
    for k in range(forces.size):
        state, t_last, direction, n_events = _scalar_final(
            PAPER, forces[k], amplitudes[k], duration, DT
        )
        # No FMA contraction and the same operations: identical bits, not just close.
        np.testing.assert_array_equal(result.states[k], state, err_msg=f"lane {k}")
        assert result.t_final[k] == t_last
        assert result.direction[k] == direction
        assert result.n_switches[k] == n_events


@pytest.mark.parametrize(
    "changes",
    [{"mass": 2.0}, {"mass": 3.0, "mu": 0.3}, {"m2": 1.5}, {"mu": 0.0}],
    ids=["pow2-mass", "any-mass", "m2=1.5", "mu=0"],
)
def test_other_parameter_sets_match_scalar_kernel(changes):
    params = PAPER.replace(**changes)
    y0 = params.static_deflection
    top = params.mu * params.mass * params.g
    forces = np.array([0.0, 0.3 * top, 0.6 * top, 0.6 * top, 1.1 * top + 0.01])
    amplitudes = np.array([0.5 * y0, 0.5 * y0, 0.9 * y0, 1.3 * y0, 0.5 * y0])
    coeffs, states0 = _lanes(params, forces, amplitudes)
    dt = params.natural_period / 150
    duration = 4.2 * params.natural_period
    result = simulate_batch(coeffs, states0, duration, dt, block=8)
    for k in range(forces.size):
        state, _t, _d, n_events = _scalar_final(params, forces[k], amplitudes[k], duration, dt)
        np.testing.assert_array_equal(result.states[k], state, err_msg=f"lane {k}")
        assert result.n_switches[k] == n_events


def test_random_states_match_scalar_kernel():
    """Arbitrary states, both sliding directions, negative forces, any dt."""
    rng = np.random.default_rng(7)
    n = 48
    omega = PAPER.natural_angular_frequency
    coeffs = np.repeat(pack(PAPER, 0.0)[None, :], n, axis=0)
    coeffs[:, FORCE] = rng.uniform(-1.2, 1.2, n)
    coeffs[::5, FORCE] = 0.0
    states0 = np.zeros((n, 4))
    states0[:, 0] = Y0 * rng.uniform(-0.5, 2.5, n)
    states0[:, 1] = Y0 * omega * rng.uniform(-1.0, 1.0, n)
    states0[:, 3] = 0.1 * Y0 * omega * rng.uniform(-1.0, 1.0, n)
    states0[::3, 3] = 0.0
    dt = T0 / 77
    duration = 4 * T0 + 0.37 * dt
    result = simulate_batch(coeffs, states0, duration, dt, block=16)
    for k in range(n):
        raw = integrate("rk4", coeffs[k], tuple(states0[k]), 0.0, duration, dt=dt,
                        save_every=10**9)  # fmt: skip
        np.testing.assert_array_equal(result.states[k], raw.states[-1], err_msg=f"lane {k}")
        assert result.t_final[k] == raw.t[-1]
        assert result.direction[k] == raw.direction[-1]
        assert result.n_switches[k] == raw.event_t.size


def test_independent_of_block_size_order_and_padding(mixed):
    _forces, _amplitudes, coeffs, states0, duration = mixed
    reference = simulate_batch(coeffs, states0, duration, DT, block=64)
    rng = np.random.default_rng(3)
    order = rng.permutation(coeffs.shape[0])
    for block in (1, 3, 8, 16):
        result = simulate_batch(coeffs[order], states0[order], duration, DT, block=block)
        np.testing.assert_array_equal(result.states, reference.states[order])
        np.testing.assert_array_equal(result.direction, reference.direction[order])
        np.testing.assert_array_equal(result.n_switches, reference.n_switches[order])
    # A lane alone, or among many copies of other lanes, gets the same bits.
    for k in (3, 6, 10):
        alone = simulate_batch(coeffs[k], states0[k], duration, DT)
        np.testing.assert_array_equal(alone.states[0], reference.states[k])
        crowd = np.r_[np.zeros(37, dtype=int), k, np.full(30, 6)]
        mixed_run = simulate_batch(coeffs[crowd], states0[crowd], duration, DT, block=32)
        np.testing.assert_array_equal(mixed_run.states[37], reference.states[k])


def test_x_never_decreases_for_nonnegative_force(mixed):
    forces, _amplitudes, coeffs, states0, _duration = mixed
    assert np.all(forces >= 0.0)
    # Runs to t = j·dt follow the same grid, so they sample one trajectory.
    previous = np.zeros(forces.size)
    for j in range(7, 1400, 61):
        result = simulate_batch(coeffs, states0, j * DT, DT)
        x = result.states[:, 2]
        assert np.all(x >= previous)
        assert np.all(result.states[:, 3] >= 0.0)
        previous = x


def test_mean_velocity_approaches_the_steady_cycle():
    """x(T)/T differs from the exact steady mean by at most the transient (a period)."""
    forces = np.array([0.5, 0.5, 0.7])
    amplitudes = np.array([Y0 / 3, 2 * Y0 / 3, 1.3 * Y0])
    coeffs, states0 = _lanes(PAPER, forces, amplitudes)
    duration = 40 * T0
    result = simulate_batch(coeffs, states0, duration, DT)
    for k in range(forces.size):
        cycle = stick_slip_cycle(PAPER, force=forces[k], amplitude=amplitudes[k])
        error = abs(result.mean_velocity[k] - cycle.mean_velocity) * duration
        assert error <= 2.0 * cycle.slip_distance


def test_time_grid_matches_the_core_clipping_rule():
    grid = time_grid(10 * DT, DT)
    assert grid.size == 10 and grid[-1] == 10 * DT
    grid = time_grid(10.5 * DT, DT)
    assert grid.size == 11 and grid[-1] == 10.5 * DT and grid[-2] == 10 * DT
    grid = time_grid(10 * DT + 1e-12 * DT, DT)  # within 1e-9 dt of the end: clipped
    assert grid.size == 10 and grid[-1] == 10 * DT + 1e-12 * DT


def test_broadcast_coefficients_and_result_fields():
    c = pack(PAPER, 0.5)
    states0 = np.array([[Y0 - 0.3 * Y0, 0.0, 0.0, 0.0], [Y0 - 0.6 * Y0, 0.0, 0.0, 0.0]])
    result = simulate_batch(c, states0, 3 * T0, DT)
    assert result.states.shape == (2, 6)  # body (y, ydot, x, xdot), contact point (u, f)
    assert result.n_steps == time_grid(3 * T0, DT).size
    np.testing.assert_array_equal(result.mean_velocity, result.states[:, 2] / (3 * T0))
    np.testing.assert_array_equal(result.t_final, 3 * T0)
    assert np.all(result.n_flagged >= result.n_switches // 2)


@pytest.mark.parametrize(
    ("coeffs", "states0", "t_end", "dt", "block", "match"),
    [
        (pack(PAPER, 0.5), np.zeros((2, 3)), 1e-3, DT, 8, "states0"),
        (np.zeros((3, SIZE)), np.zeros((2, 4)), 1e-3, DT, 8, "rows"),
        (np.zeros(SIZE + 1), np.zeros((2, 4)), 1e-3, DT, 8, "coeffs"),
        (pack(PAPER, 0.5), np.full((1, 4), np.nan), 1e-3, DT, 8, "finite"),
        (pack(PAPER, 0.5), np.zeros((1, 4)), 0.0, DT, 8, "t_end"),
        (pack(PAPER, 0.5), np.zeros((1, 4)), 1e-3, -DT, 8, "dt"),
        (pack(PAPER, 0.5), np.zeros((1, 4)), 1e-3, DT, 0, "block"),
    ],
)
def test_rejects_bad_input(coeffs, states0, t_end, dt, block, match):
    with pytest.raises(ValueError, match=match):
        simulate_batch(coeffs, states0, t_end, dt, block=block)


def test_backward_sliding_reversals_and_stops_inside_a_step_match_scalar_kernel():
    """F < 0, reversals in flight and in contact, and a slip phase inside one step."""
    threshold = PAPER.motion_threshold(0.5 * Y0) * (1.0 + 3e-5)  # slips of ~T0/330
    lanes = [
        (-0.5, (Y0 - Y0 / 3, 0.0, 0.0, 0.0)),  # backward stick-slip
        (-0.5, (-0.3 * Y0, 0.0, 0.0, 0.0)),  # backward, with flights
        (-0.3, (-0.3 * Y0, 0.0, 0.0, 1.7531e-5)),  # forward, reverses in flight
        (-1.2, (Y0 / 3, 0.0, 0.0, 2e-4)),  # forward, reverses in contact
        (0.5, (Y0 / 3, 0.0, 0.0, -2e-4)),  # backward against F > 0: stops, sticks
        (threshold, (0.5 * Y0, 0.0, 0.0, 0.0)),  # release and stop in one step
        (-threshold, (0.5 * Y0, 0.0, 0.0, 0.0)),
    ]
    coeffs = np.repeat(pack(PAPER, 0.0)[None, :], len(lanes), axis=0)
    coeffs[:, FORCE] = [force for force, _state in lanes]
    states0 = np.array([state for _force, state in lanes])
    duration = 6.37 * T0
    result = simulate_batch(coeffs, states0, duration, T0 / 100, block=8)
    for k in range(len(lanes)):
        raw = integrate("rk4", coeffs[k], tuple(states0[k]), 0.0, duration, dt=T0 / 100,
                        save_every=10**9)  # fmt: skip
        assert raw.event_t.size >= 3
        np.testing.assert_array_equal(result.states[k], raw.states[-1], err_msg=f"lane {k}")
        assert result.direction[k] == raw.direction[-1]
        assert result.n_switches[k] == raw.event_t.size
    assert np.all(result.states[:4, 2] < 0.0)  # F < 0 lanes end behind their start
