"""mean_velocity_grid: each point computed on its own, bit-identical however it is split.

The map (Fig. 7) must not depend on how a sweep is chunked or on the thread count
(docs/design.md, sweeps), nor on the order of the forces; the single-point cycle
(:func:`microslip.stick_slip_cycle`) reads the same kernel.
"""

from __future__ import annotations

import numba
import numpy as np
import pytest

from microslip import Parameters
from microslip.analysis.steady_state import (
    BATCH_AMPLITUDES,
    ORBIT_STEPS,
    mean_velocity_grid,
    stick_slip_cycle,
)
from microslip.model.coefficients import pack

P = Parameters()
LIMIT = P.static_friction_force  # μ m g [N]
# Forces [N] across the map, at and above μ m g; amplitudes [m] from 0 to loss of contact.
FORCES = np.concatenate([[0.0, 0.05], np.linspace(0.06, 0.95, 45), [LIMIT, 0.99, 1.5]])
AMPLITUDES = np.concatenate([[0.0, 1e-12], np.linspace(1e-9, 3e-7, 2 * BATCH_AMPLITUDES + 7)])


def grid(forces: np.ndarray, amplitudes: np.ndarray, params: Parameters = P) -> np.ndarray:
    out = np.full((forces.size, amplitudes.size), np.nan)
    assert mean_velocity_grid(forces, amplitudes, pack(params, 0.0), ORBIT_STEPS, out)
    return out


@pytest.fixture(scope="module")
def whole() -> np.ndarray:
    return grid(FORCES, AMPLITUDES)


def test_the_grid_covers_every_regime(whole):
    assert not np.isnan(whole).any()
    assert (whole == 0.0).any() and np.isinf(whole).any() and (whole > 0.0).any()
    assert np.isinf(whole[FORCES > LIMIT]).all()
    assert np.isfinite(whole[FORCES <= LIMIT]).all()


@pytest.mark.parametrize("width", [1, 5, BATCH_AMPLITUDES, BATCH_AMPLITUDES + 3])
def test_amplitude_blocks_are_bit_identical(whole, width):
    parts = [grid(FORCES, AMPLITUDES[j : j + width]) for j in range(0, AMPLITUDES.size, width)]
    np.testing.assert_array_equal(np.concatenate(parts, axis=1), whole)


def test_force_subsets_and_order_are_bit_identical(whole):
    order = np.random.default_rng(7).permutation(FORCES.size)
    np.testing.assert_array_equal(grid(FORCES[order], AMPLITUDES), whole[order])
    np.testing.assert_array_equal(grid(FORCES[3:4], AMPLITUDES), whole[3:4])


def test_one_thread_is_bit_identical(whole):
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        single = grid(FORCES, AMPLITUDES)
    finally:
        numba.set_num_threads(threads)
    np.testing.assert_array_equal(single, whole)


@pytest.mark.parametrize("m2", [2.0, 1.5])
def test_grid_equals_the_single_cycle(m2):
    params = Parameters(m2=m2)
    forces = np.array([0.1, 0.4, 0.7, 0.95, params.static_friction_force])
    amplitudes = np.array([0.05, 0.5, 0.99, 1.2]) * params.static_deflection
    values = grid(forces, amplitudes, params)
    for i, force in enumerate(forces):
        for j, amplitude in enumerate(amplitudes):
            cycle = stick_slip_cycle(params, force=float(force), amplitude=float(amplitude))
            assert values[i, j] == cycle.mean_velocity
            assert cycle.mean_velocity == cycle.slip_distance / cycle.period
