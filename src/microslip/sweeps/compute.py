"""Computing one chunk of a sweep: a pure function of (spec, chunk key), safe to ship to Dask."""

from __future__ import annotations

import numpy as np

from microslip.analysis.steady_state import ORBIT_STEPS, mean_velocity_grid
from microslip.model.coefficients import FORCE, pack
from microslip.simulation import DEFAULT_RK4_STEPS_PER_PERIOD, initial_state_from_amplitude
from microslip.sweeps.spec import ChunkKey, SweepSpec


def compute_chunk(spec: SweepSpec, key: ChunkKey) -> np.ndarray:
    """Mean velocity [m/s] on the chunk's (force, amplitude) block.

    "steady": the exact long-time mean (inf where F > μ m g). "time": x(T)/T after a
    batched RK4 run of duration T from the paper's initial state (rest at the top).
    Each point is computed independently of the chunking, so results are bit-identical
    however the sweep is split or distributed.
    """
    params = spec.params_at(key)
    forces = np.asarray(spec.forces)
    amplitudes = np.asarray(spec.amplitudes[spec.amplitude_slice(key)])
    if spec.method == "steady":
        out = np.empty((forces.size, amplitudes.size))
        if not mean_velocity_grid(forces, amplitudes, pack(params, 0.0), ORBIT_STEPS, out):
            raise RuntimeError(f"orbit table overflow in chunk {key}")
        return out
    from microslip.integrators.batched import simulate_batch

    dt = spec.dt if spec.dt is not None else params.natural_period / DEFAULT_RK4_STEPS_PER_PERIOD
    coeffs = np.repeat(pack(params, 0.0)[None, :], forces.size * amplitudes.size, axis=0)
    coeffs[:, FORCE] = np.repeat(forces, amplitudes.size)
    states0 = np.array(
        [initial_state_from_amplitude(params, a) for a in amplitudes] * forces.size, dtype=float
    )
    result = simulate_batch(coeffs, states0, spec.duration, dt)
    return (result.states[:, 2] / spec.duration).reshape(forces.size, amplitudes.size)
