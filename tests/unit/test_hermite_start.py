"""bracket.hermite_start: the first trial of a located crossing from the values and
rates at the bracket's ends (the root of their cubic Hermite interpolant).

On a cubic the interpolant is the function itself, so the start must be its root to
rounding: a rate scaled to the wrong bracket length, a sign slip in the Newton step or a
swapped basis function would land elsewhere. Where there is nothing to improve on, the
false-position trial passes through unchanged."""

import math

import pytest

from microslip.integrators.bracket import hermite_start


def _cubic(theta):
    """g(θ) = (θ - 0.45)(1 + 2θ²) and dg/dθ: one real root, at θ = 0.45."""
    return (theta - 0.45) * (1.0 + 2.0 * theta * theta), 1.0 + 6.0 * theta * theta - 1.8 * theta


@pytest.mark.parametrize(("lo", "hi"), [(0.0, 1.0), (0.2, 0.7), (0.4, 0.46)])
def test_a_cubic_starts_on_its_root(lo, hi):
    (f_lo, r_lo), (f_hi, r_hi) = _cubic(lo), _cubic(hi)
    false_position = hi - f_hi * (hi - lo) / (f_hi - f_lo)
    assert abs(false_position - 0.45) > 1e-4 * (hi - lo)  # something to improve on
    theta = hermite_start(false_position, lo, hi, f_lo, f_hi, r_lo, r_hi)
    assert theta == pytest.approx(0.45, abs=1e-14)


def test_a_smooth_crossing_starts_far_closer_than_false_position():
    """sin on [0.5, 1.5] crossing at 1 (the kind of function a lift-off's gap is over a
    step): the start's error is O(d^4), false position's O(d^2)."""
    lo, hi = 0.5, 1.5
    g = lambda x: math.sin(math.pi * x)  # noqa: E731
    rate = lambda x: math.pi * math.cos(math.pi * x)  # noqa: E731
    false_position = hi - g(hi) * (hi - lo) / (g(hi) - g(lo))
    theta = hermite_start(false_position, lo, hi, g(lo), g(hi), rate(lo), rate(hi))
    assert abs(theta - 1.0) < 0.05 * abs(false_position - 1.0) or false_position == 1.0


def test_without_rates_or_with_a_root_outside_the_start_is_false_positions():
    (f_lo, r_lo), (f_hi, r_hi) = _cubic(0.2), _cubic(0.7)
    assert hermite_start(0.5, 0.2, 0.7, f_lo, f_hi, math.nan, r_hi) == 0.5
    assert hermite_start(0.5, 0.2, 0.7, f_lo, f_hi, r_lo, math.nan) == 0.5
    # Rates that bend the interpolant's root out of the bracket: the start stays put.
    assert hermite_start(0.5, 0.0, 1.0, -1.0, 1.0, -50.0, -50.0) == 0.5
