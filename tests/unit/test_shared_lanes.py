"""The shared-normal kernel's pieces: the tape's polynomial algebra, determinism of the
lanes whatever their company, order or threads, and its use by the time-domain map."""

from __future__ import annotations

import numba
import numpy as np
import pytest

import microslip as ms
from microslip.integrators import normal_tape as nt
from microslip.integrators import rigid_lane_law as law
from microslip.integrators.shared_lanes import run_shared
from microslip.simulation import initial_state_from_amplitude

PARAMS = ms.Parameters()
T0 = PARAMS.natural_period
RNG = np.random.default_rng(7)


def test_quartic_interpolates_its_five_conditions():
    a = nt._quartic(2.0, -0.5, 1.3, 0.7, 0.25)
    p = np.polynomial.Polynomial(a)
    dp = p.deriv()
    np.testing.assert_allclose([p(0), dp(0), p(0.5), p(1), dp(1)], [2.0, -0.5, 1.3, 0.7, 0.25],
                               rtol=0, atol=1e-14)  # fmt: skip


@pytest.mark.parametrize("seed", range(40))
def test_integrals_extremes_and_critical_points_of_random_quartics(seed):
    """P, P' against numpy's polynomial, I, K against its integrals; min/max and the
    roots of P' against a dense grid (the fast monotone path and the bracketed roots of
    P' both get exercised)."""
    rng = np.random.default_rng(seed)
    a = tuple(rng.normal(size=5) * [1.0, 1.0, 4.0, 8.0, 6.0])
    p = np.polynomial.Polynomial(a)
    for tau in (0.0, 0.3, 1.0):
        assert nt.poly(a, tau) == pytest.approx(p(tau), abs=1e-13)
        assert nt.poly_rate(a, tau) == pytest.approx(p.deriv()(tau), abs=1e-13)
        assert nt.integral(a, tau) == pytest.approx(p.integ()(tau), abs=1e-13)
        assert nt.double_integral(a, tau) == pytest.approx(p.integ(2)(tau), abs=1e-13)
    p_min, p_max, n_crit, *crit = nt._extremes(a)
    grid = np.linspace(0.0, 1.0, 200001)
    values = p(grid)
    assert p_min == pytest.approx(values.min(), abs=1e-9)
    assert p_max == pytest.approx(values.max(), abs=1e-9)
    roots = sorted(r.real for r in p.deriv().roots() if abs(r.imag) < 1e-12 and 0 < r.real < 1)
    assert n_crit == len(roots)
    np.testing.assert_allclose(crit[:n_crit], roots, atol=1e-12)


@pytest.mark.parametrize(
    "a, roots",
    [((0.0,) * 5, []), ((0.0, 0.0, 1e-300, -1e-300, 0.0), [2.0 / 3.0]),
     ((0.0, 0.0, 0.0, 0.0, -1.0), [])],
)  # fmt: skip
def test_extremes_of_a_piece_in_flight_and_of_pieces_that_start_at_zero(a, roots):
    """P = 0 (a piece in flight: a third of a forced tape's rows near resonance) takes
    its own short path; a P that starts at 0 with P'(0) = 0 but is not 0 must not (a
    shortcut on the first coefficients would lose the critical point at τ = 2/3)."""
    p = np.polynomial.Polynomial(a)
    grid = np.linspace(0.0, 1.0, 30001)
    p_min, p_max, n_crit, *crit = nt._extremes(a)
    assert p_min == pytest.approx(p(grid).min(), abs=1e-315)
    assert p_max == pytest.approx(p(grid).max(), abs=1e-315)
    assert n_crit == len(roots)
    np.testing.assert_allclose(crit[:n_crit], roots, atol=1e-12)


@pytest.mark.parametrize("slope", [1e-3, 1e-6, 1e-9])
def test_release_is_the_first_point_strictly_below_the_level_where_p_is_flat(slope):
    """A stick release at the first τ with P(τ) < |F|/μ_s strictly, even where P is
    flat to rounding over many tolerances (a slope of 1e-9 N over a piece at P ~ 1 N:
    P - level is exactly 0 over ~1e-7 of the piece). A finder that takes an exact zero
    for the far side fails the first assertion, one that overshoots the second."""
    a = (1.0, -slope, 0.0, 0.0, 0.0)  # P = 1 - slope τ [N]
    level = 1.0 - 0.37 * slope  # P crosses it near τ = 0.37
    crit = (0, 0.0, 0.0, 0.0)
    tau = law._first_below(a, crit, 0.0, level)
    assert nt.poly(a, tau) < level
    # Just before it, P is not below the level (within the tolerance).
    assert nt.poly(a, tau - 2.0 * law._TAU_TOLERANCE) >= level
    assert tau == pytest.approx(0.37, abs=1e-16 / slope + 1e-12)


def _lanes(n_setups=5, n_forces=7):
    model = ms.Model(PARAMS)
    amplitudes = np.linspace(0.0, 2.8e-7, n_setups)
    normal0 = np.array([initial_state_from_amplitude(PARAMS, a)[:2] for a in amplitudes])
    coeffs = np.repeat(nt.normal_coefficients(model.pack(0.0))[None, :], n_setups, axis=0)
    groups = np.repeat(np.arange(n_setups), n_forces)
    forces = np.tile(np.linspace(-0.9, 0.95, n_forces), n_setups)
    mu_s = np.full(forces.size, 0.12)
    mu_k = np.full(forces.size, 0.1)
    return coeffs, normal0, groups, forces, mu_s, mu_k


def _free_periods(normal0):
    """T(A) [s] of each free set-up started at rest at y0 - A (0 for A = 0: no cycle)."""
    amplitudes = PARAMS.static_deflection - normal0[:, 0]
    return np.array([ms.free_period(PARAMS, a) if a > 0.0 else 0.0 for a in amplitudes])


@pytest.mark.parametrize("repeated", [False, True])
def test_lanes_bit_identical_whatever_their_company_order_and_threads(repeated):
    """Also on repeated tapes (``repeated``: ~6 periods), where lanes that repeat a period
    are parked and moved about (shared_lanes._run_cycle): a lane that came back to
    another's column, or whose parking hung on the others, would break it."""
    coeffs, normal0, groups, forces, mu_s, mu_k = _lanes()
    periods = _free_periods(normal0) if repeated else None
    args = (0.004, T0 / 200, None, None, periods)
    whole = run_shared(coeffs, normal0, groups, forces, mu_s, mu_k, *args)
    assert np.any(whole[3] > 2)  # lanes do switch (stick-slip)
    perm = RNG.permutation(forces.size)
    shuffled = run_shared(coeffs, normal0, groups[perm], forces[perm], mu_s[perm], mu_k[perm],
                          *args)  # fmt: skip
    for a, b in zip(whole, shuffled, strict=True):
        assert np.array_equal(a[perm], b)
    # One lane alone, on its own set-up: the same bits.
    for lane in (3, 17, 30):
        g = groups[lane]
        alone = run_shared(coeffs[g : g + 1], normal0[g : g + 1], [0], forces[lane : lane + 1],
                           mu_s[lane : lane + 1], mu_k[lane : lane + 1], *args[:4],
                           None if periods is None else periods[g : g + 1])  # fmt: skip
        assert alone[0][0] == whole[0][lane] and alone[1][0] == whole[1][lane]
    threads = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        single = run_shared(coeffs, normal0, groups, forces, mu_s, mu_k, *args)
    finally:
        numba.set_num_threads(threads)
    for a, b in zip(whole, single, strict=True):
        assert np.array_equal(a, b)


def test_repeating_lanes_take_their_remaining_periods_at_once():
    """On a free vibration's repeated tape (~30 periods) a lane that starts a period as
    it started the last one takes its remaining periods at once (park=True, the
    default). Against every lane stepped through every period (park=False): the same ẋ,
    mode and counts bit for bit, x within 1e-12 of the largest |x|. One period too many or
    too few is a whole period's Δx (~3 % of x); parking a lane that does not repeat
    changes its ẋ or mode; a lane put back in another's column swaps values."""
    coeffs, normal0, groups, forces, mu_s, mu_k = _lanes(n_setups=5, n_forces=9)
    periods = _free_periods(normal0)
    x0 = np.where(np.arange(forces.size) % 4 == 1, 1e-6, 0.0)  # x never feeds back
    v0 = np.where(np.arange(forces.size) % 5 == 2, -2e-5, 0.0)  # some start sliding
    run = (coeffs, normal0, groups, forces, mu_s, mu_k, 30.5 * periods.max(), T0 / 200, x0, v0)
    parked = run_shared(*run, periods=periods)
    stepped = run_shared(*run, periods=periods, park=False)
    for name, a, b in zip(
        ("v", "mode", "switches", "flagged"), parked[1:], stepped[1:], strict=True
    ):
        assert np.array_equal(a, b), name
    assert np.abs(parked[0] - stepped[0]).max() <= 1e-12 * np.abs(stepped[0]).max()
    assert np.any(parked[0] != stepped[0])  # the shortcut was taken (else the same bits)
    assert (stepped[3] > 40).sum() > 10  # lanes stick and slip every period
    creeping = stepped[3] > 40
    assert np.all(np.abs(stepped[0][creeping] - x0[creeping]) > 0.0)


def test_zero_force_lane_never_moves():
    coeffs, normal0, groups, forces, mu_s, mu_k = _lanes(n_setups=5, n_forces=1)
    forces[:] = 0.0
    x, v, mode, switches, _ = run_shared(coeffs, normal0, groups, forces, mu_s, mu_k, 0.003,
                                         T0 / 100)  # fmt: skip
    assert np.all(x == 0.0) and np.all(v == 0.0) and np.all(mode == 0.0)
    assert np.all(switches == 0)


def test_time_map_does_not_depend_on_chunking():
    """velocity_map(method="time") runs the shared kernel per chunk: the same bits for
    one chunk or several."""
    forces = np.linspace(0.2, 0.9, 5)
    amplitudes = np.linspace(0.0, 3e-7, 6)
    options = {"method": "time", "duration": 0.002}
    one = ms.velocity_map(PARAMS, forces=forces, amplitudes=amplitudes, **options)
    parts = [
        ms.velocity_map(PARAMS, forces=forces, amplitudes=amplitudes[k : k + 2], **options)
        for k in range(0, 6, 2)
    ]
    joined = np.concatenate([np.asarray(p.values) for p in parts], axis=-1)
    assert np.array_equal(np.asarray(one.values), joined)
    assert np.any(np.asarray(one.values) > 0.0)
