"""In-process forced time sweeps compute several chunks in one shared-normal run.

One chunk of a forced model is one normal set-up; alone, its run keeps one core busy,
so the in-process runner batches them (``runner.LOCAL_BATCH``). A set-up's lanes depend
on nothing else in the run, so the batch must give each chunk the same bits as
computing it alone, including chunks whose RK4 steps differ (a swept excitation
frequency changes the period the step resolves).
"""

from __future__ import annotations

import numpy as np

import microslip as ms
from microslip.sweeps import runner
from microslip.sweeps.compute import compute_chunk, compute_chunks
from microslip.sweeps.spec import SweepSpec

P = ms.Parameters()
MODEL = ms.Model(P, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(2.0, 1400.0))
FORCES = np.linspace(0.05, 0.95, 7)
AXES = {"excitation.amplitude": [0.5, 3.0, 5.0], "excitation.frequency": [800.0, 1400.0, 2500.0]}


def _spec():
    return SweepSpec.build(MODEL, AXES, FORCES, method="time", duration=0.01)


def test_a_batch_gives_each_chunk_its_bits_alone():
    spec = _spec()
    keys = list(spec.chunks())
    assert len(keys) == 9
    steps = {SweepSpec.step_period(spec.model_at(key)) for key in keys}
    assert len(steps) == 2  # T0, and 1/2500 Hz shorter than T0: two step sizes
    batched = compute_chunks(spec, keys[::-1])  # any order
    for key, block in zip(keys[::-1], batched, strict=True):
        alone = compute_chunk(spec, key)
        assert block.shape == (FORCES.size, 1)
        np.testing.assert_array_equal(block, alone)
    assert len({block.tobytes() for block in batched}) == 9  # nine different chunks


def test_the_in_process_sweep_batches_forced_time_chunks(monkeypatch):
    sizes = []
    real = runner.compute_chunks

    def recording(spec, keys, progress=None):
        sizes.append(len(keys))
        return real(spec, keys, progress)

    monkeypatch.setattr(runner, "compute_chunks", recording)
    monkeypatch.setattr(runner, "LOCAL_BATCH", 4)
    result = ms.sweep(MODEL, AXES, force=FORCES, method="time", duration=0.01)
    assert sizes == [4, 4]  # and the ninth chunk alone, through compute_chunk
    spec = _spec()
    for key in spec.chunks():
        np.testing.assert_array_equal(result.values[key[0], key[1]], compute_chunk(spec, key)[:, 0])
