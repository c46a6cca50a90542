"""Hysteresis of the folded resonance curve: the time simulation's frequency sweeps land
on the stable branches that ``forced_response`` reports.

Paper data, Viscous ζ = 0.02, P0 = 0.5 N (softening, m2 = 2): the curve folds between
~0.93 f0 and ~0.96 f0. The scipy reference (``forced_reference``) sweeps the frequency in
steps (0.6 → 0.95 f0 up, 1.45 → 0.95 f0 down; each step starts from the previous steady
state, 80 periods per step, 240 at the last, then a Newton polish that moves the state by
< 1e-3 y0). Up lands on the lower branch (A = 0.285 y0), down on the upper (0.662 y0).
``forced_response(m, frequencies=(0.6 f0, f))`` and ``(1.45 f0, f)`` must end exactly at
f on these orbits within 1e-8 relative. The folds it reports must bracket f and be where
the time simulation jumps: 0.2 % inside a fold the swept branch persists (a sweep in
three steps from f, 300 periods at the last), 0.2 % past it the time simulation leaves
that branch for the other one.
"""

import numpy as np
import pytest
from forced_reference import FOLD_AT, NormalReference, folded_model, swept_state

import microslip as ms

F0 = ms.Parameters().natural_frequency
START = {"up": 0.6, "down": 1.45}


@pytest.fixture(scope="module")
def full_branch():
    return ms.forced_response(folded_model(), frequencies=(0.6 * F0, 1.45 * F0))


@pytest.mark.parametrize("direction", ["up", "down"])
def test_sweep_lands_on_reported_branch(direction):
    ref, _u, summary = swept_state(direction)
    ds = ms.forced_response(folded_model(), frequencies=(START[direction] * F0, FOLD_AT * F0))
    last = ds.isel(point=-1)
    assert float(last.frequency) == pytest.approx(FOLD_AT * F0, rel=1e-12)
    assert bool(last.stable)
    assert float(last.amplitude) == pytest.approx(summary["amplitude"], rel=1e-8)
    assert abs(float(last.y_min) - summary["y_min"]) < 1e-8 * ref.y0
    assert abs(float(last.y_max) - summary["y_max"]) < 1e-8 * ref.y0


def test_the_two_sweeps_differ():
    low = swept_state("up")[2]["amplitude"]
    high = swept_state("down")[2]["amplitude"]
    y0 = ms.Parameters().static_deflection
    assert low < 0.3 * y0 < 0.6 * y0 < high


def _settle_amplitude(ratio, u, periods=300):
    """A/y0 after sweeping from FOLD_AT f0 (state u) to ratio f0 in three steps."""
    for step in np.linspace(FOLD_AT, ratio, 4)[1:]:
        ref = NormalReference(folded_model(step))
        u = ref.settle(u, periods if step == ratio else 60)
    return ref.period_summary(u)["amplitude"] / ref.y0


def test_folds_are_where_the_time_simulation_jumps(full_branch):
    folds = list(full_branch.attrs["folds"])
    assert len(folds) == 2
    f_fold = sorted(float(full_branch.frequency[i]) / F0 for i in folds)
    assert f_fold[0] < FOLD_AT < f_fold[1]
    _, u_low, _ = swept_state("up")
    _, u_high, _ = swept_state("down")
    mid = 0.45  # between the branches (A/y0) near the folds
    # the lower branch ends at the upper fold, the upper branch at the lower fold
    assert _settle_amplitude(f_fold[1] * 0.998, u_low) < mid
    assert _settle_amplitude(f_fold[1] * 1.002, u_low) > mid
    assert _settle_amplitude(f_fold[0] * 1.002, u_high) > mid
    assert _settle_amplitude(f_fold[0] * 0.998, u_high) < mid


def test_branch_is_single_valued_outside_the_band(full_branch):
    f = np.asarray(full_branch.frequency) / F0
    assert f[0] == pytest.approx(0.6, rel=1e-12) and f[-1] == pytest.approx(1.45, rel=1e-12)
    folds = sorted(full_branch.attrs["folds"])
    # frequency increases up to the first fold, decreases to the second, then increases
    # (a fold index is the point nearest the turning point: it may lie on either side)
    assert np.all(np.diff(f[: folds[0]]) > 0.0)
    assert np.all(np.diff(f[folds[0] + 1 : folds[1]]) < 0.0)
    assert np.all(np.diff(f[folds[1] + 1 :]) > 0.0)
