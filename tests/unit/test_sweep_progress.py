"""Progress inside a chunk: a time run's set-ups move the bar as they end
(threads.run_ranges' on_done, compute.Progress, runner._advance), so a long chunk no
longer holds it still; once a chunk is saved the bar stands on the chunks saved."""

from __future__ import annotations

import threading

import numpy as np
import pytest

import microslip as ms
from microslip.integrators import threads
from microslip.sweeps import SweepSpec, runner
from microslip.sweeps.compute import compute_chunk, compute_chunks

FORCES = [0.3, 0.6, 1.2]


def test_run_ranges_reports_each_range_once():
    lock = threading.Lock()
    reported = []

    def on_done(k):
        with lock:
            reported.append(k)

    threads.run_ranges(lambda lo, hi: None, 37, per_task=5, on_done=on_done)
    assert sorted(reported) == [2] + [5] * 7


@pytest.mark.parametrize(
    "model",
    [
        ms.Model(),
        ms.Model(tangential=ms.TangentialSpring(ms.Parameters().contact_stiffness)),
        ms.Model(tangential=ms.MindlinSpring(0.8)),
    ],
    ids=["rigid", "spring", "mindlin"],
)
def test_a_time_chunk_reports_its_setups(model):
    spec = SweepSpec.build(model, None, FORCES, [0.0, 1e-7, 2e-7, 3e-7], method="time",
                           duration=0.002, amplitude_chunk=4)  # fmt: skip
    fractions = []
    with_progress = compute_chunk(spec, (0,), fractions.append)
    assert fractions == [0.25] * 4  # one set-up per amplitude, each once
    assert np.array_equal(with_progress, compute_chunk(spec, (0,)))  # the same bits


def test_a_batch_of_forced_chunks_reports_its_share():
    forced = ms.Model(damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(3.0, 1400.0))
    spec = SweepSpec.build(forced, {"excitation.amplitude": [1.0, 2.0, 3.0, 4.0]}, FORCES,
                           None, method="time", duration=0.002)  # fmt: skip
    keys = list(spec.chunks())
    fractions = []
    compute_chunks(spec, keys, fractions.append)
    assert len(fractions) == len(keys) and sum(fractions) == pytest.approx(1.0)


class RecordingBar:
    """The parts of a tqdm bar that the runner uses, recording where it stood."""

    def __init__(self, total, initial, show):
        self.total, self.n, self.disable, self.seen = total, initial, not show, []

    def update(self, amount):
        self.n += amount
        self.seen.append(self.n)

    def refresh(self):
        self.seen.append(self.n)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


def test_the_bar_moves_inside_a_chunk_and_ends_on_the_chunks(monkeypatch):
    bars = []
    monkeypatch.setattr(runner, "_progress", lambda *a: bars.append(RecordingBar(*a)) or bars[-1])
    spec = SweepSpec.build(None, None, FORCES, [0.0, 1e-7, 2e-7, 3e-7, 4e-7, 5e-7],
                           method="time", duration=0.002, amplitude_chunk=3)  # fmt: skip
    runner.run_sweep(spec, progress=True)
    (bar,) = bars
    assert bar.n == spec.n_chunks == 2
    inside = [n for n in bar.seen if 0 < n < 1]
    assert len(inside) >= 2  # set-ups of the first chunk moved it before it was saved
    assert bar.seen == sorted(bar.seen)  # never backwards
