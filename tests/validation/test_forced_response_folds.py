"""A folded frequency-response curve (MODEL.md identity 4: softening, bends left, folds).

Pseudo-arclength continuation passes both folds in either direction, ends exactly at
the requested frequency, and the Floquet stability changes exactly at the folds (a
real multiplier through +1, so no period doubling), where the frequency turns back.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

import microslip as ms
from microslip.analysis.forced_response import forced_response

P = ms.Parameters()
F0 = P.natural_frequency
MODEL = ms.Model(P, ms.Viscous(0.02), ms.HarmonicForce(0.6, F0))


@functools.cache
def _curve(start, end):
    return forced_response(MODEL, frequencies=(start * F0, end * F0))


@pytest.fixture(params=[(0.6, 1.45), (1.45, 0.6)], ids=["up", "down"])
def curve(request):
    start, end = request.param
    return start, end, _curve(start, end)


def test_curve_runs_from_start_to_exact_end(curve):
    start, end, ds = curve
    assert float(ds.frequency[0]) == start * F0
    assert float(ds.frequency[-1]) == end * F0
    assert ds.attrs["complete"] == 1


def test_stability_changes_exactly_at_the_two_folds(curve):
    _, _, ds = curve
    folds = list(ds.attrs["folds"])
    assert len(folds) == 2
    stable = ds.stable.values
    changes = [i for i in range(1, stable.size) if stable[i] != stable[i - 1]]
    assert changes == folds
    assert not bool(ds.period_doubling.any())
    # The frequency turns back at each fold: its increments change sign there only.
    turns = np.nonzero(np.diff(np.sign(np.diff(ds.frequency.values))))[0] + 1
    assert all(min(abs(t - i) for i in folds) <= 1 for t in turns) and len(turns) == 2
    # Between the folds (the middle branch) a multiplier is outside the unit circle;
    # next to each fold it is close to +1.
    inner = slice(min(folds), max(folds))
    assert not stable[inner].any() and stable[: min(folds)].all() and stable[max(folds) :].all()
    for i in folds:
        assert abs(float(ds.max_multiplier[i]) - 1.0) < 0.05
        assert abs(float(ds.max_multiplier[i - 1]) - 1.0) < 0.05


def test_fold_frequencies_agree_between_directions():
    up, down = _curve(0.6, 1.45), _curve(1.45, 0.6)
    f_up = sorted(float(up.frequency[i]) for i in up.attrs["folds"])
    f_down = sorted(float(down.frequency[i]) for i in down.attrs["folds"])
    # Unrefined folds: the nearest branch points, a small arclength step apart.
    assert np.allclose(f_up, f_down, rtol=1e-3)
    assert 0.90 * F0 < f_up[0] < f_up[1] < 0.97 * F0
    peak_up, peak_down = float(up.amplitude.max()), float(down.amplitude.max())
    assert abs(peak_up - peak_down) <= 1e-4 * peak_up
