"""Few normal set-ups with many lanes run as copies that share out the lanes
(integrators/setup_copies.py): the plan, and the same bits as one set-up per thread for
the rigid, spring and Mindlin lane kernels, hand-backs and progress included."""

from __future__ import annotations

import numpy as np
import pytest

import microslip as ms
from microslip.integrators import threads
from microslip.integrators.mindlin_lanes import run_mindlin_lanes
from microslip.integrators.normal_tape import normal_coefficients
from microslip.integrators.setup_copies import MIN_LANES_PER_COPY, SetupCopies
from microslip.integrators.shared_lanes import LaneStalledError, run_shared
from microslip.integrators.spring_lanes import run_spring_lanes
from microslip.simulation import initial_state_from_amplitude

P = ms.Parameters()
Y0 = P.static_deflection
DT = P.natural_period / 200.0


def test_the_plan_fills_the_threads_with_copies_of_enough_lanes():
    groups = np.zeros(4 * MIN_LANES_PER_COPY, dtype=np.int64)
    plan = SetupCopies.plan(groups, 1, n_threads=16)
    assert plan.copies == 4  # 16 threads, but each copy keeps MIN_LANES_PER_COPY lanes
    np.testing.assert_array_equal(plan.source, [0, 0, 0, 0])
    np.testing.assert_array_equal(plan.lane_copy[:6], [0, 1, 2, 3, 0, 1])  # interleaved
    assert np.all(np.diff(plan.lane_copy[plan.order]) >= 0)
    assert np.bincount(plan.lane_copy).tolist() == [MIN_LANES_PER_COPY] * 4
    # Two set-ups on 5 threads: two copies each (5 // 2), set-up 1's lanes in copies 2, 3.
    groups = np.repeat([0, 1], 2 * MIN_LANES_PER_COPY)
    plan = SetupCopies.plan(groups, 2, n_threads=5)
    assert plan.copies == 2
    np.testing.assert_array_equal(plan.source, [0, 0, 1, 1])
    assert set(plan.lane_copy[groups == 1]) == {2, 3}
    # As many set-ups as threads, or too few lanes: the set-ups themselves.
    assert SetupCopies.plan(groups, 2, n_threads=2).copies == 1
    assert SetupCopies.plan(np.zeros(MIN_LANES_PER_COPY), 1, n_threads=8).copies == 1


def test_statuses_and_progress_are_counted_by_set_up():
    plan = SetupCopies.plan(np.repeat([0, 1], 4 * MIN_LANES_PER_COPY), 2, n_threads=6)
    assert plan.copies == 3
    np.testing.assert_array_equal(plan.status(np.array([0, 0, 0, 0, 5, 9])), [0, 5])
    told = []
    plan.done(told.append)(1)
    assert told == [pytest.approx(1 / 3)]
    values = np.arange(plan.lane_copy.size, dtype=float)
    np.testing.assert_array_equal(plan.unorder(values[plan.order]), values)


@pytest.fixture
def as_threads(monkeypatch):
    """Run with a given thread count (the copies follow it; the helper threads too)."""

    def set_count(count):
        monkeypatch.setattr(threads, "thread_count", lambda: count)

    return set_count


def _set_ups(model, amplitudes):
    coeffs = normal_coefficients(model.pack(0.0))
    normal0 = np.array([initial_state_from_amplitude(model.params, a)[:2] for a in amplitudes])
    return np.repeat(coeffs[None], len(amplitudes), axis=0), normal0


FORCES = np.linspace(0.05, 0.95, 3 * MIN_LANES_PER_COPY)


def _run(kernel, model, amplitudes, duration, periods=None):
    """The kernel's per-lane results for every force at every amplitude (set-up-major),
    μ_s = 0.15 > μ_k = 0.1."""
    coeffs, normal0 = _set_ups(model, amplitudes)
    groups = np.repeat(np.arange(len(amplitudes)), FORCES.size)
    forces = np.tile(FORCES, len(amplitudes))
    args = (groups, forces, 0.15, 0.1, duration, DT)
    if kernel == "rigid":
        return run_shared(coeffs, normal0, *args, periods=periods)
    ratio = [0.8235] * len(amplitudes)
    if kernel == "spring":
        return run_spring_lanes(coeffs, normal0, [P.contact_stiffness] * len(amplitudes), *args,
                                periods=periods)  # fmt: skip
    return run_mindlin_lanes(coeffs, normal0, ratio, *args, periods=periods)


@pytest.mark.parametrize("kernel", ["rigid", "spring", "mindlin"])
@pytest.mark.parametrize("repeated", [False, True], ids=["stepped", "repeated"])
def test_copies_give_the_bits_of_one_set_up_per_thread(as_threads, kernel, repeated):
    """One set-up with flights (A = 1.3 y0) and one in contact: on 1 thread each runs
    whole; on 6 threads each runs as 3 copies of 64 lanes. Every result of every lane
    (x, ẋ, mode, the counts; f on a spring) is the same bits; on the repeated tape of a
    free vibration (periods given) too, where lanes park."""
    model = ms.Model(P, tangential={"rigid": None, "spring": ms.TangentialSpring(
        P.contact_stiffness), "mindlin": ms.MindlinSpring(0.8235)}[kernel])  # fmt: skip
    amplitudes = [1.3 * Y0, 0.5 * Y0]
    periods = [ms.free_period(P, a) for a in amplitudes] if repeated else None
    duration = 30 * P.natural_period
    as_threads(1)
    whole = _run(kernel, model, amplitudes, duration, periods)
    as_threads(6)
    assert SetupCopies.plan(np.repeat([0, 1], FORCES.size), 2).copies == 3
    copied = _run(kernel, model, amplitudes, duration, periods)
    assert np.abs(whole[0]).max() > 0.0 and np.any(whole[-2] > 0)  # motion and switches
    for a, b in zip(whole, copied, strict=True):
        np.testing.assert_array_equal(a, b)


def test_a_copied_mindlin_hand_back_names_the_set_up_and_keeps_the_others(as_threads):
    """Without windows (as on the GPU) a Hertz set-up that leaves contact is handed back
    by its copies: the error names the set-up (not a copy), and the other set-up's
    results come as on one thread. With them (the CPU's default) its copies cross its
    flights and every lane has the bits of one thread."""
    params = ms.Parameters(m2=1.5)
    model = ms.Model(params, tangential=ms.MindlinSpring(0.8235))
    coeffs = normal_coefficients(model.pack(0.0))
    y0 = params.static_deflection
    normal0 = np.array([[y0, 0.0], initial_state_from_amplitude(params, 1.4 * y0)[:2]])
    dt = params.natural_period / 200.0
    groups = np.repeat([0, 1], FORCES.size)
    args = (np.array([coeffs, coeffs]), normal0, [0.8235, 0.8235], groups,
            np.tile(FORCES, 2), 0.1, 0.1, 1e-3, dt)  # fmt: skip
    outcomes, windowed = [], []
    for count in (1, 6):
        as_threads(count)
        with pytest.raises(LaneStalledError, match="set-up 1") as info:
            run_mindlin_lanes(*args, windowed=False)
        outcomes.append(info.value)
        windowed.append(run_mindlin_lanes(*args))
    assert [list(e.setups) for e in outcomes] == [[1], [1]]
    kept = groups == 0
    for a, b in zip(outcomes[0].partial, outcomes[1].partial, strict=True):
        np.testing.assert_array_equal(a[kept], b[kept])
    for a, b in zip(windowed[0], windowed[1], strict=True):
        np.testing.assert_array_equal(a, b)
    assert windowed[0][4][~kept].sum() > 0  # the flying set-up's lanes switched


def test_a_copied_run_reports_its_set_ups(as_threads):
    """Progress counts set-ups: two set-ups as three copies each report 2 in all (not
    6), in the parts run_ranges polls."""
    as_threads(6)
    coeffs, normal0 = _set_ups(ms.Model(P), [Y0, 0.5 * Y0])
    told = []
    run_shared(coeffs, normal0, np.repeat([0, 1], FORCES.size), np.tile(FORCES, 2), 0.1, 0.1,
               1e-3, DT, on_done=told.append)  # fmt: skip
    assert told and sum(told) == pytest.approx(2.0)
