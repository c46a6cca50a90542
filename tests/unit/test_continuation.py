"""Pseudo-arclength continuation on closed-form curves (no model involved)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from microslip.analysis.continuation import ContinuationError, continue_branch, correct_at


def _cubic(u, lam):
    """F = u³ - u - λ: an S-curve with folds at u = ∓1/√3, λ = ±2/(3√3)."""
    x = u[0]
    return np.array([x**3 - x - lam]), np.array([[3.0 * x * x - 1.0]]), np.array([-1.0])


LAM_FOLD = 2.0 / (3.0 * math.sqrt(3.0))


def test_passes_both_folds_and_ends_exactly():
    branch = continue_branch(_cubic, np.array([-1.3]), -1.0, 1.0, step=0.05, max_step=0.1)
    assert branch.complete and branch.lam[-1] == 1.0
    u = np.array([v[0] for v in branch.u])
    lam = np.array(branch.lam)
    assert np.max(np.abs(u**3 - u - lam)) <= 1e-12
    assert abs(u[-1] - 1.324717957244746) <= 1e-12  # the upper root of u³ - u = 1
    assert len(branch.folds) == 2
    for i, sign in zip(branch.folds, (1.0, -1.0), strict=True):
        # The fold lies between points i-1 and i: u passes ∓1/√3 there.
        lo, hi = sorted((u[i - 1], u[i]))
        assert lo <= -sign / math.sqrt(3.0) <= hi
        assert abs(lam[i] - sign * LAM_FOLD) < 0.01


def test_stops_the_first_time_it_reaches_the_end():
    branch = continue_branch(_cubic, np.array([-1.3]), -1.0, 0.2, step=0.05)
    assert branch.complete and branch.lam[-1] == 0.2 and not branch.folds
    x = branch.u[-1][0]
    assert x < -1.0 / math.sqrt(3.0) and abs(x**3 - x - 0.2) <= 1e-12  # lower branch


def test_runs_backward():
    branch = continue_branch(_cubic, np.array([1.3]), 1.0, -1.0, step=0.05)
    assert branch.complete and branch.lam[-1] == -1.0 and len(branch.folds) == 2
    assert abs(branch.u[-1][0] + 1.324717957244746) <= 1e-12


def test_circle_turns_back():
    # F = u² + λ² - 1 from (-√0.75, -0.5) toward λ = 2: the branch folds at λ = 1 and
    # never gets there; the point cap stops it (incomplete).
    def circle(u, lam):
        return np.array([u[0] ** 2 + lam**2 - 1.0]), np.array([[2.0 * u[0]]]), np.array([2.0 * lam])

    branch = continue_branch(
        circle, np.array([-math.sqrt(0.75)]), -0.5, 2.0, step=0.1, max_points=40
    )
    assert not branch.complete and len(branch.lam) == 40
    assert max(branch.lam) <= 1.0 + 1e-12 and len(branch.folds) >= 1


def test_corrector_failure_is_a_clear_error():
    def broken(u, lam):
        if lam > 0.5:
            return np.array([np.nan]), np.array([[1.0]]), np.array([1.0])
        return np.array([u[0] - lam]), np.array([[1.0]]), np.array([-1.0])

    with pytest.raises(ContinuationError, match="corrector did not converge"):
        continue_branch(broken, np.array([0.0]), 0.0, 1.0, step=0.1)


def test_newton_stops_on_its_rate_of_convergence():
    # Quadratic convergence: the error left after the second update is estimated from the
    # rate and passes, so a point costs about two residuals, not three (the test
    # |Δx| <= tol alone needed a third), and the points are as accurate as before.
    calls = []

    def counted(u, lam):
        calls.append(lam)
        return _cubic(u, lam)

    branch = continue_branch(counted, np.array([-1.3]), -1.0, 1.0, step=0.01, max_step=0.02)
    u = np.array([v[0] for v in branch.u])
    assert branch.complete and len(branch.folds) == 2
    assert np.max(np.abs(u**3 - u - np.array(branch.lam))) <= 1e-12
    per_point = len(calls) / len(branch.lam)
    assert per_point <= 2.2, per_point  # 2.05 here; 2.99 with the test |Δx| <= tol


def test_a_slowly_converging_corrector_is_not_stopped_early():
    # A Jacobian twice too large halves each Newton update: linear convergence at rate
    # 1/2, where the error left after an update is as large as the update itself. The
    # corrector must go on until that error, not only the update's rate-scaled size,
    # is within the tolerance.
    root = 1.324717957244746  # of u³ - u = 1
    tol = 1e-11

    def doubled(u, lam):
        f, jac, f_lam = _cubic(u, lam)
        return f, 2.0 * jac, f_lam

    for start in (1.2, 1.25, 1.3, 1.4, 1.5, 2.0):
        u = correct_at(doubled, np.array([start]), 1.0, tol=tol, max_iter=200)
        assert u is not None
        assert abs(u[0] - root) <= 1.2 * tol * root, (start, u[0] - root)
