"""simulate_batch on lanes of other models than the paper's: the generic scalar kernel
step, the same as simulate(method="rk4"), mixed with paper lanes in one block."""

from __future__ import annotations

import numpy as np

import microslip as ms
from microslip.integrators.batched import simulate_batch

P = ms.Parameters()
Y0 = P.static_deflection
DT = P.natural_period / 200
DURATION = 2e-3
MODELS = [
    ms.Model(P),
    ms.Model(P, damping=ms.Viscous(ratio=0.05),
             excitation=ms.HarmonicForce(amplitude=1.5 * P.mass * P.g, frequency=1300.0)),
    ms.Model(P, damping=ms.HuntCrossley(ratio=0.1)),
    ms.Model(P, excitation=ms.BaseMotion(amplitude=0.4 * Y0, frequency=1400.0)),
]  # fmt: skip


def test_mixed_models_match_simulate_rk4():
    coeffs = np.array([m.pack(0.5) for m in MODELS])
    states = np.array([[Y0 - 1.3 * Y0, 0, 0, 0], [Y0, 0, 0, 0], [Y0 - 2.0 * Y0, 0, 0, 0],
                       [Y0, 0, 0, 0]])  # fmt: skip
    batch = simulate_batch(coeffs, states, DURATION, DT, block=8)
    for k, model in enumerate(MODELS):
        r = ms.simulate(model, force=0.5, duration=DURATION, method="rk4", dt=DT,
                        initial_state=states[k])  # fmt: skip
        final = np.array([r.y[-1], r.ydot[-1], r.x[-1], r.xdot[-1]])
        scale = np.array([Y0, np.max(np.abs(r.ydot)), max(np.max(np.abs(r.x)), Y0),
                          max(np.max(np.abs(r.xdot)), 1e-9)])  # fmt: skip
        np.testing.assert_allclose(batch.states[k, :4] / scale, final / scale, rtol=0, atol=1e-12)
        assert batch.direction[k] == r.direction[-1]
        assert batch.n_switches[k] >= 1
    # Lanes of other models than the paper's are redone by the scalar kernel every step.
    assert np.all(batch.n_flagged[1:] == batch.n_steps)
    assert batch.n_flagged[0] < batch.n_steps
