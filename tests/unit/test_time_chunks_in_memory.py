"""An in-memory time sweep's chunks hold at most IN_MEMORY_TIME_CHUNK_LANES lanes
(sweeps/api.py): one chunk of a large map held ~190 B per point (0.8 GB at 2048 x 2048)
and ran slower. The result does not depend on the chunking."""

import numpy as np

import microslip as ms
import microslip.sweeps.api as api

FORCES = np.linspace(0.05, 0.95, 12)
AMPLITUDES = np.linspace(0.0, 3e-7, 10)


def test_in_memory_time_chunks_are_capped_and_give_the_same_bits(monkeypatch):
    options = dict(forces=FORCES, amplitudes=AMPLITUDES, method="time", duration=0.002)
    whole = ms.velocity_map(**options)  # 120 lanes: one chunk under the default cap
    chunks = []
    real_run = api.run_sweep

    def spy(spec, **kwargs):
        chunks.append(spec.amplitude_chunk)
        return real_run(spec, **kwargs)

    monkeypatch.setattr(api, "run_sweep", spy)
    monkeypatch.setattr(api, "IN_MEMORY_TIME_CHUNK_LANES", 50)  # 4 amplitudes of 12 forces
    capped = ms.velocity_map(**options)
    monkeypatch.setattr(api, "IN_MEMORY_TIME_CHUNK_LANES", 5)  # fewer than the forces: 1
    single = ms.velocity_map(**options)
    ms.velocity_map(forces=FORCES, amplitudes=AMPLITUDES)  # steady: one chunk, uncapped
    assert chunks == [4, 1, AMPLITUDES.size]
    assert np.array_equal(capped.values, whole.values)
    assert np.array_equal(single.values, whole.values)
