"""Pseudo-arclength continuation of F(u, λ) = 0 (generic; knows nothing of the model).

The branch x = (u, λ) is followed with a tangent predictor x + ds·τ and a Newton
corrector on the bordered system

    [ ∂F/∂u  ∂F/∂λ ] Δx = -[ F            ]
    [       τᵀ     ]        [ τ·(x - x_p) ]

(Keller's pseudo-arclength; Seydel, *Practical Bifurcation and Stability Analysis*), so
it passes through folds where ∂F/∂u is singular. The new tangent solves the same bordered
matrix with right-hand side (0, 1), which keeps its orientation. A fold is where the
λ-component of the tangent changes sign. Newton stops when the error left, estimated from
its rate of convergence, is within the tolerance (:class:`NewtonStop`). The branch stops
exactly at λ_end the first time it gets there: the step that passes λ_end is replaced by
a Newton correction in u at λ = λ_end from the interpolated state. Work in scaled
variables (u and λ of order one).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Branch", "ContinuationError", "NewtonStop", "continue_branch", "correct_at"]

Residual = Callable[[np.ndarray, float], tuple[np.ndarray, np.ndarray, np.ndarray]]


class ContinuationError(ValueError):
    """The corrector failed repeatedly (the step fell below its minimum)."""


@dataclass
class Branch:
    """Points of a continued branch.

    Attributes
    ----------
    u : list of ndarray
        States on the branch.
    lam : list of float
        Parameter values.
    folds : list of int
        Indices i of the points just past a fold (the fold lies between i - 1 and i).
    complete : bool
        True when the branch reached λ_end (False: stopped at ``max_points``).
    """

    u: list = field(default_factory=list)
    lam: list = field(default_factory=list)
    folds: list = field(default_factory=list)
    complete: bool = False


class NewtonStop:
    """The stopping test of one Newton iteration, at relative tolerance ``tol``: call
    :meth:`converged` after each update.

    An iterate is accepted when its update is within tol * max(1, |x|) (max norms), or
    when the error left is: with the updates shrinking at least geometrically at the rate
    r of the last two, it is below the tail of the series, r/(1 - r) times the last
    update (the test of scipy's Radau corrector). Under Newton's quadratic convergence
    the tail passes one iteration before the update does, and each iteration costs a
    residual: a period of the normal flow for a forced response.
    """

    def __init__(self, tol: float) -> None:
        self.tol = tol
        # The last update over its tolerance (None before the first): > 1 at acceptance
        # when the tail, not the update itself, passed.
        self.ratio: float | None = None

    def converged(self, step: np.ndarray, x: np.ndarray) -> bool:
        """Whether ``x``, just updated by ``step``, is within the tolerance."""
        previous = self.ratio
        bound = self.tol * max(1.0, float(np.max(np.abs(x))))
        self.ratio = float(np.max(np.abs(step))) / bound
        if self.ratio <= 1.0:
            return True
        if previous is None or previous <= 0.0:
            return False
        rate = self.ratio / previous
        return rate < 1.0 and rate / (1.0 - rate) * self.ratio <= 1.0


def correct_at(
    residual: Residual, u: np.ndarray, lam: float, *, tol: float = 1e-11, max_iter: int = 12
) -> np.ndarray | None:
    """Newton in u at fixed λ from ``u``; the solution, or None without convergence."""
    u = np.array(u, dtype=float)
    stop = NewtonStop(tol)
    for _ in range(max_iter):
        f, jac, _ = residual(u, lam)
        try:
            step = np.linalg.solve(jac, -f)
        except np.linalg.LinAlgError:
            return None
        if not np.all(np.isfinite(step)):
            return None
        u = u + step
        if stop.converged(step, u):
            return u
    return None


def _tangent(jac: np.ndarray, f_lam: np.ndarray, previous: np.ndarray) -> np.ndarray:
    n = jac.shape[0]
    bordered = np.zeros((n + 1, n + 1))
    bordered[:n, :n] = jac
    bordered[:n, n] = f_lam
    bordered[n] = previous
    rhs = np.zeros(n + 1)
    rhs[n] = 1.0
    tau = np.linalg.solve(bordered, rhs)
    return tau / np.linalg.norm(tau)


def continue_branch(
    residual: Residual,
    u0: np.ndarray,
    lam0: float,
    lam_end: float,
    *,
    step: float = 0.01,
    min_step: float = 1e-7,
    max_step: float = 0.05,
    max_points: int = 2000,
    tol: float = 1e-11,
    max_iter: int = 8,
) -> Branch:
    """Follow F(u, λ) = 0 from the solution (u0, λ0) until λ = λ_end.

    Parameters
    ----------
    residual : callable
        ``residual(u, lam) -> (F, ∂F/∂u, ∂F/∂λ)``.
    u0, lam0 : ndarray, float
        A solution (corrected at λ0 first).
    lam_end : float
        Where to stop, exactly, the first time the branch gets there.
    step, min_step, max_step : float
        Initial, smallest and largest arclength step (scaled variables).
    max_points : int
        Cap on the number of points (the branch is then incomplete).
    tol : float
        Relative error of a corrected point: its last Newton update, or the error left
        after it as estimated from the rate of convergence (:class:`NewtonStop`).
    max_iter : int
        Corrector iterations before the step is halved.

    Raises
    ------
    ContinuationError
        When the corrector fails with a step below ``min_step``.
    """
    u = correct_at(residual, u0, lam0, tol=tol)
    if u is None:
        raise ContinuationError(f"no solution at the start, lambda = {lam0!r}")
    branch = Branch(u=[u], lam=[float(lam0)])
    direction = 1.0 if lam_end > lam0 else -1.0
    if lam_end == lam0:
        branch.complete = True
        return branch
    n = u.size
    _, jac, f_lam = residual(u, lam0)
    e_lam = np.zeros(n + 1)
    e_lam[n] = direction
    tau = _tangent(jac, f_lam, e_lam)
    x = np.append(u, lam0)
    ds = step
    while len(branch.lam) < max_points:
        predicted = x + ds * tau
        xn = predicted.copy()
        ok = False
        iterations = 0
        stop = NewtonStop(tol)
        for _ in range(max_iter):
            iterations += 1
            f, jac, f_lam = residual(xn[:n], xn[n])
            bordered = np.zeros((n + 1, n + 1))
            bordered[:n, :n] = jac
            bordered[:n, n] = f_lam
            bordered[n] = tau
            rhs = -np.append(f, tau @ (xn - predicted))
            try:
                dx = np.linalg.solve(bordered, rhs)
            except np.linalg.LinAlgError:
                break
            if not np.all(np.isfinite(dx)):
                break
            xn = xn + dx
            if stop.converged(dx, xn):
                ok = True
                break
        if not ok:
            ds *= 0.5
            if ds < min_step:
                raise ContinuationError(
                    f"continuation failed near lambda = {x[n]:.12g}: the corrector did not "
                    f"converge with a step below {min_step:g}"
                )
            continue
        if (xn[n] - lam_end) * direction >= 0.0:
            # Passed λ_end: correct onto it from the state interpolated between x and xn.
            w = (lam_end - x[n]) / (xn[n] - x[n]) if xn[n] != x[n] else 1.0
            u_end = correct_at(residual, x[:n] + w * (xn[:n] - x[:n]), lam_end, tol=tol)
            if u_end is None:
                ds *= 0.5
                if ds < min_step:
                    raise ContinuationError(f"no solution at the end, lambda = {lam_end!r}")
                continue
            branch.u.append(u_end)
            branch.lam.append(float(lam_end))
            branch.complete = True
            return branch
        new_tau = _tangent(jac, f_lam, tau)
        if new_tau[n] * tau[n] < 0.0:
            branch.folds.append(len(branch.lam))
        branch.u.append(xn[:n].copy())
        branch.lam.append(float(xn[n]))
        x, tau = xn, new_tau
        # The step follows the corrector's effort, counted as the updates the test
        # |Δx| <= tol alone would have taken: one more than were made when the rate
        # test stopped it (the points, and so the curve's resolution, are those of that
        # test).
        effort = iterations if stop.ratio <= 1.0 else iterations + 1
        if effort <= 2:
            ds = min(1.5 * ds, max_step)
        elif effort >= 5:
            ds *= 0.7
    return branch
