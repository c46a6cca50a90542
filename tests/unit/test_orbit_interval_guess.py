"""The first guess of the steady map's interval roots (analysis/orbit.py,
``interval_guess``): the inverse cubic Hermite of f through its node values and slopes.

A guess only saves Newton steps (``interval_root`` safeguards the root); these tests
check that it is the fourth-order guess it claims to be (its error in time shrinks as
h^4, in fractions of the interval as h^3), so that a wrong basis or swapped end slopes,
which would quietly cost the map its speed, fail here."""

import math

import numpy as np
import pytest

from microslip.analysis.orbit import interval_guess, interval_root


def _table(h):
    """Nodes of y = sin t [m] every h [s] on [0, 1.2] s: y, ẏ, ÿ."""
    t = np.arange(0.0, 1.2 + h / 2, h)
    return t, np.sin(t), np.cos(t), -np.sin(t)


def _guess_errors(h, w_y, w_v, gamma_per_h, root_time):
    """(cubic, linear) guess errors [fraction of the interval] for the root at
    t* = ``root_time`` of f = w_y y + w_v ẏ + gamma s + const on the interval holding it."""
    t, ys, yds, ydds = _table(h)
    k = int(root_time // h)
    s_true = (root_time - t[k]) / h
    gamma = gamma_per_h * h
    const = -(w_y * math.sin(root_time) + w_v * math.cos(root_time) + gamma * s_true)
    guess = interval_guess(k, w_y, w_v, gamma, const, ys, yds, ydds, h)
    f0 = w_y * ys[k] + w_v * yds[k] + const
    f1 = w_y * ys[k + 1] + w_v * yds[k + 1] + gamma + const
    linear = -f0 / (f1 - f0)
    return abs(guess - s_true), abs(linear - s_true), (k, gamma, const, ys, yds, ydds, s_true)


# (w_y, w_v, gamma per unit h): the release y - y* and the stop -mu ẏ + gamma s + const
ROOTS = {"release": (1.0, 0.0, 0.0), "stop": (0.0, -0.3, 0.2)}


@pytest.mark.parametrize("kind", ROOTS)
def test_the_guess_is_fourth_order(kind):
    """Largest error over roots all along [0.3, 0.8] s, at h and h/2."""
    w_y, w_v, gamma_per_h = ROOTS[kind]
    roots = np.linspace(0.3, 0.8, 101) + 1e-4  # never exactly on a node

    def largest(h):
        errors = [_guess_errors(h, w_y, w_v, gamma_per_h, r)[:2] for r in roots]
        return np.max(errors, axis=0)

    coarse, linear = largest(0.02)
    fine, _ = largest(0.01)
    assert coarse < 1e-3 * linear  # the linear guess is ~1e-3 of the interval off
    assert fine < coarse / 6.0  # h^3 in fractions of the interval: 8 times smaller


def test_newton_from_the_guess_lands_on_the_hermite_root():
    _, _, (k, gamma, const, ys, yds, ydds, s_true) = _guess_errors(0.01, 0.0, -0.3, 0.2, 0.7011)
    guess = interval_guess(k, 0.0, -0.3, gamma, const, ys, yds, ydds, 0.01)
    root = interval_root(k, guess, 0.0, 1.0, 0.0, -0.3, gamma, const, 1e-15, ys, yds, ydds, 0.01)
    assert root == pytest.approx(s_true, abs=1e-9)  # the quintic Hermite's own root


def test_a_slope_that_is_not_positive_falls_back_on_the_linear_guess():
    """At a turning point (ẏ = 0 at a node: df/ds = 0) the inverse has no slope."""
    ys = np.array([0.0, 1.0])
    yds = np.array([0.0, 1.0])  # df/ds = 0 at the first node
    ydds = np.zeros(2)
    assert interval_guess(0, 1.0, 0.0, 0.0, -0.25, ys, yds, ydds, 1.0) == 0.25
