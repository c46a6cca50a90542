"""Progress inside a chunk: a time run's set-ups move the bar as they go (their share of
the tape, threads.report, polled by threads.run_ranges into on_done; compute.Progress,
runner._advance), so a long chunk, or a single long set-up, no longer holds it still;
once a chunk is saved the bar stands on the chunks saved."""

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
    # The set-ups' ends (and their progress) are told as run_ranges polls: in parts
    # that add up to the chunk.
    assert fractions and all(f > 0.0 for f in fractions)
    assert sum(fractions) == pytest.approx(1.0)
    assert np.array_equal(with_progress, compute_chunk(spec, (0,)))  # the same bits


def test_a_batch_of_forced_chunks_reports_its_share():
    forced = ms.Model(damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(3.0, 1400.0))
    spec = SweepSpec.build(forced, {"excitation.amplitude": [1.0, 2.0, 3.0, 4.0]}, FORCES,
                           None, method="time", duration=0.002)  # fmt: skip
    keys = list(spec.chunks())
    fractions = []
    compute_chunks(spec, keys, fractions.append)
    assert fractions and sum(fractions) == pytest.approx(1.0)


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
    """A damped map of two chunks (~0.2 s of work; run_ranges polls every ms here)."""
    bars = []
    monkeypatch.setattr(runner, "_progress", lambda *a: bars.append(RecordingBar(*a)) or bars[-1])
    monkeypatch.setattr(threads, "POLL_S", 0.001)
    spec = SweepSpec.build(ms.Model(damping=ms.Viscous(0.01)), None, FORCES,
                           [0.0, 1e-7, 2e-7, 3e-7, 4e-7, 5e-7], method="time", duration=0.5,
                           amplitude_chunk=3)  # fmt: skip
    runner.run_sweep(spec, progress=True)
    (bar,) = bars
    assert bar.n == spec.n_chunks == 2
    inside = [n for n in bar.seen if 0 < n < 1]
    assert len(inside) >= 2  # set-ups of the first chunk moved it before it was saved
    assert bar.seen == sorted(bar.seen)  # never backwards


@pytest.mark.parametrize("kind", ["rigid", "spring", "mindlin"])
def test_a_single_long_set_up_reports_progress_before_it_ends(kind, monkeypatch):
    """One set-up of one lane over a long damped run: the kernel writes its share of the
    tape done into its progress slot (threads.report), and run_ranges tells on_done of it
    every POLL_S (10 ms here, so that a fast machine polls too), so the bar moves before
    the set-up ends; the reports add up to one set-up, never going back."""
    from microslip.integrators.mindlin_lanes import run_mindlin_lanes
    from microslip.integrators.normal_tape import normal_coefficients
    from microslip.integrators.shared_lanes import run_shared
    from microslip.integrators.spring_lanes import run_spring_lanes

    monkeypatch.setattr(threads, "POLL_S", 0.01)
    p = ms.Parameters()
    tangential = {"rigid": None, "spring": ms.TangentialSpring(p.contact_stiffness),
                  "mindlin": ms.MindlinSpring(0.8)}[kind]  # fmt: skip
    model = ms.Model(p, damping=ms.Viscous(0.01), tangential=tangential)
    coeffs = normal_coefficients(model.pack(0.0))[None]
    normal0 = np.array([[0.5 * p.static_deflection, 0.0]])
    duration = {"rigid": 2.0, "spring": 1.0, "mindlin": 1.0}[kind]  # ~0.5 s of work each
    args = ([0], [1.2], 0.1, 0.1, duration, p.natural_period / 200.0)
    told = []
    if kind == "rigid":
        run_shared(coeffs, normal0, *args, on_done=told.append)
    elif kind == "spring":
        run_spring_lanes(coeffs, normal0, [p.contact_stiffness], *args, on_done=told.append)
    else:
        run_mindlin_lanes(coeffs, normal0, [0.8], *args, on_done=told.append)
    assert len(told) >= 3, told  # reports before the end
    assert all(step > 0.0 for step in told)
    assert sum(told) == pytest.approx(1.0)
    assert told[0] < 1.0


def _marks_item_1(lo, hi, stop):
    """A range kernel that gives up item 1 (threads.hand_back) and finishes the rest."""
    for item in range(lo, hi):
        if item == 1:
            threads.hand_back(stop, item)


@pytest.mark.parametrize("watched", [True, False], ids=["polled", "range-ends"])
def test_an_item_handed_back_is_not_counted_done(watched):
    """run_ranges counts an ended range's items done but those its kernel handed back,
    whether it polls the slots (main thread) or tells each range as it ends."""
    stop = threads.stop_flag(4)
    lock = threading.Lock()
    told = []

    def on_done(k):
        with lock:
            told.append(k)

    threads.run_ranges(_marks_item_1, 4, stop, per_task=1, stop=stop, on_done=on_done,
                       interruptible=watched)  # fmt: skip
    assert sum(told) == pytest.approx(3.0)


def test_a_set_up_handed_back_reports_the_batched_run(monkeypatch):
    """A Hertz Mindlin set-up that leaves contact (m2 = 1.5, A > y0) handed back by the
    lanes runs on the batched RK4 kernel, ~100 times their cost: the bar moves while it
    runs (each block's share of the grid, polled), and the reports add up to the chunk,
    the set-up that stays on the lanes (A < y0) included, never going back. (The CPU
    lanes cross such flights themselves; without windows they hand the set-up back, as
    the GPU lanes do and as a window that does not fit the rows in sight does.)"""
    from functools import partial

    from microslip.integrators import mindlin_lanes

    monkeypatch.setattr(threads, "POLL_S", 0.01)
    monkeypatch.setattr(mindlin_lanes, "run_mindlin_lanes",
                        partial(mindlin_lanes.run_mindlin_lanes, windowed=False))  # fmt: skip
    model = ms.Model(ms.Parameters(m2=1.5), tangential=ms.MindlinSpring(0.8235))
    y0 = model.params.static_deflection
    spec = SweepSpec.build(model, None, np.linspace(0.1, 0.9, 16), [0.5 * y0, 1.4 * y0],
                           method="time", duration=0.005, amplitude_chunk=2)  # fmt: skip
    fractions = []
    with_progress = compute_chunk(spec, (0,), fractions.append)
    assert len(fractions) >= 4, fractions  # not only the lanes' end and the batch's
    assert all(f > 0.0 for f in fractions)
    assert sum(fractions) == pytest.approx(1.0)
    assert np.array_equal(with_progress, compute_chunk(spec, (0,)))  # the same bits
