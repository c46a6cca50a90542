"""Floquet multipliers of ``periodic_orbit`` against a finite-difference monodromy matrix.

The reference perturbs the state at t = 0 by ±1e-5 (scaled) in each component and
integrates one period with scipy (DOP853, rtol 1e-12, contact switches as events, so
the saltation at each switch is in the difference quotient); the eigenvalues of the
central-difference matrix are the multipliers to ~1e-8. They must agree with the code's
within 1e-6. Liouville: the smooth flow contracts areas by exp(−∫ ∂r/∂η' dτ) over the
contact, and the switches (touchdown at δ = 0, separation at N_raw = 0, where the
acceleration is continuous) have unit saltation determinant, so λ1 λ2 = exp(−∫_contact
∂N/∂ẏ dt / m), checked on the finite-difference matrix too. Along the continued branch
of the folded curve, stability changes exactly at the reported folds, where the largest
multiplier crosses 1.
"""

import itertools

import numpy as np
import pytest
from forced_reference import folded_model, periodic_cases, steady_case, swept_state
from orbit_quadrature import orbit_average

import microslip as ms

F0 = ms.Parameters().natural_frequency


def _match(code, fd):
    code, fd = np.asarray(code, dtype=complex), np.asarray(fd, dtype=complex)
    assert code.shape == fd.shape == (2,)
    return min(np.max(np.abs(code[list(p)] - fd)) for p in itertools.permutations(range(2)))


def _liouville(orbit, ref):
    """exp(−∫ ∂(N/m)/∂ẏ dt) over the contact, with the reference's law."""

    def rate(t, y, yd):
        tau = t * ref.omega
        u = ref.from_si(y, yd)
        if ref.indicator(tau, u) <= 0.0:
            return 0.0
        if ref.damping == "kv":
            return ref.k * ref.omega
        if ref.damping == "hc":
            return ref.k * ref.raw(tau, u)[1] * ref.omega
        return 0.0

    return np.exp(-orbit_average(orbit, rate) * orbit.period)


def _check(orbit, ref, u):
    fd_matrix = ref.monodromy(u)
    fd = np.linalg.eigvals(fd_matrix)
    assert _match(orbit.multipliers, fd) < 1e-6, (orbit.multipliers, fd)
    det = _liouville(orbit, ref)
    assert np.linalg.det(fd_matrix) == pytest.approx(det, rel=1e-6)
    assert abs(np.prod(orbit.multipliers)) == pytest.approx(det, rel=1e-6)
    assert orbit.max_multiplier == pytest.approx(np.max(np.abs(fd)), abs=1e-6)


@pytest.mark.parametrize("direction", ["up", "down"])
def test_multipliers_on_both_branches(direction):
    ref, u, _summary = swept_state(direction)
    orbit = ms.periodic_orbit(folded_model(), initial_state=ref.to_si(u), transient_periods=0)
    _check(orbit, ref, u)


@pytest.mark.parametrize("name", sorted(periodic_cases()))
def test_multipliers_with_damping_laws_and_contact_loss(name):
    model, ref, u, _summary = steady_case(name)
    _check(ms.periodic_orbit(model), ref, u)


def test_stability_changes_exactly_at_folds():
    ds = ms.forced_response(folded_model(), frequencies=(0.6 * F0, 1.45 * F0))
    folds = sorted(int(i) for i in ds.attrs["folds"])
    stable = np.asarray(ds.stable, dtype=bool)
    mm = np.asarray(ds.max_multiplier, dtype=float)
    assert len(folds) == 2
    # stable, unstable between the folds, stable again
    assert stable[: folds[0]].all() and stable[folds[1] + 1 :].all()
    assert not stable[folds[0] + 1 : folds[1]].any()
    assert folds[1] - folds[0] >= 2
    changes = np.flatnonzero(stable[1:] != stable[:-1])
    for i in changes:  # a change between points i and i+1 touches a fold
        assert i in folds or i + 1 in folds, (i, folds)
    for i in folds:  # the largest multiplier crosses 1 there
        assert (mm[i - 1] - 1.0) * (mm[i + 1] - 1.0) < 0.0
        assert abs(mm[i] - 1.0) < abs(mm[i - 1] - 1.0) + abs(mm[i + 1] - 1.0)
    assert np.all((mm < 1.0 + 1e-9) == stable)
