"""The spring-lane kernel (integrators/spring_lanes.py) at constant N, where the contact
point on its spring has a closed form, and its determinism and input checks. The
Mindlin-lane kernel (integrators/mindlin_lanes.py) runs the same constant-N cases: at
rest k_t = λ K_n is constant, so with λ = 1 its lanes must follow the same closed forms
(its own tests: tests/unit/test_mindlin_lanes.py).

At rest in the static deflection (A = 0) the normal force is m g throughout. From rest
with a relaxed spring the body oscillates on k_t about F/k_t: x = (F/k_t)(1 - cos ωt),
ω = sqrt(k_t/m), while |f| = F(1 - cos ωt) <= μ_s N. Above μ_s N/2 the spring force
reaches μ_s N at cos ωt1 = 1 - μ_s N/F: the point slips with f = μ_k N, the body
decelerates at (μ_k N - F)/m until ẋ = u̇ = 0 and sticks again with f = μ_k N, then
oscillates about F/k_t with the amplitude (μ_k N - F)/k_t, never reaching μ_s N again.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import microslip as ms
from microslip.integrators import spring_lane_law as law
from microslip.integrators.mindlin_lanes import run_mindlin_lanes
from microslip.integrators.normal_tape import normal_coefficients
from microslip.integrators.spring_lanes import run_spring_lanes
from microslip.simulation import initial_state_from_amplitude

P = ms.Parameters()
K_T = P.contact_stiffness
OMEGA = math.sqrt(K_T / P.mass)
N = P.mass * P.g
DT = 2.0 * math.pi / OMEGA / 200.0


KERNELS = ("spring", "mindlin")


def _run(forces, amplitudes, duration, mu_s=P.mu, mu_k=P.mu, stiffness=K_T, kernel="spring"):
    """x(duration) [m] per lane, amplitude-major then force, and the switch counts; the
    Mindlin kernel with λ = stiffness / K_n (k_t = stiffness at rest)."""
    model = ms.Model(P, tangential=ms.TangentialSpring(stiffness))
    normal0 = np.array([initial_state_from_amplitude(P, a)[:2] for a in amplitudes])
    coeffs = np.repeat(normal_coefficients(model.pack(0.0))[None], len(amplitudes), axis=0)
    groups = np.repeat(np.arange(len(amplitudes)), len(forces))
    run, parameter = run_spring_lanes, stiffness
    if kernel == "mindlin":
        run, parameter = run_mindlin_lanes, stiffness / P.contact_stiffness
    out = run(coeffs, normal0, [parameter] * len(amplitudes), groups,
              np.tile(forces, len(amplitudes)), mu_s, mu_k, duration, DT)  # fmt: skip
    return out[0], out[4]


@pytest.mark.parametrize("kernel", KERNELS)
def test_stick_is_the_oscillator_on_the_spring(kernel):
    """F < μ N/2: x(t) = (F/k_t)(1 - cos ωt) at every duration, no switch."""
    forces = np.array([0.1, 0.3, 0.45])
    for duration in (0.3e-3, 1.1e-3, 2.5e-3):
        x, switches = _run(forces, [0.0], duration, kernel=kernel)
        expected = forces / K_T * (1.0 - np.cos(OMEGA * duration))
        np.testing.assert_allclose(x, expected, rtol=1e-9, atol=1e-12 * forces.max() / K_T)
        assert not switches.any()


@pytest.mark.parametrize("kernel", KERNELS)
def test_release_slip_and_stop_at_constant_normal_force(kernel):
    """μ_s N/2 < F < μ_k N with μ_s = 0.15, μ_k = 0.1: release, slip, stop, stick."""
    mu_s, mu_k, force = 0.15, 0.1, 0.85
    cos_release = 1.0 - mu_s * N / force
    t1 = math.acos(cos_release) / OMEGA
    x1 = mu_s * N / K_T
    v1 = force / K_T * OMEGA * math.sin(OMEGA * t1)
    deceleration = (mu_k * N - force) / P.mass
    t_stop = t1 + v1 / deceleration
    x_stop = x1 + v1 * v1 / (2.0 * deceleration)
    amplitude = (mu_k * N - force) / K_T
    for duration in (0.9 * t1, t_stop + 0.37e-3, t_stop + 2.2e-3):
        x, switches = _run([force], [0.0], duration, mu_s, mu_k, kernel=kernel)
        if duration < t1:
            expected = force / K_T * (1.0 - math.cos(OMEGA * duration))
        else:
            expected = x_stop - amplitude * (1.0 - math.cos(OMEGA * (duration - t_stop)))
        assert x[0] == pytest.approx(expected, rel=1e-9)
        assert switches[0] == (0 if duration < t1 else 2)


@pytest.mark.parametrize("kernel", KERNELS)
def test_a_lane_is_the_same_bits_whatever_the_other_lanes(kernel):
    """The same (force, amplitude) alone, among other forces, in another order or with
    another set-up before it: the same bits (flights at 1.3 y0 included)."""
    amplitudes = [0.7e-7, 1.3 * P.static_deflection]
    forces = np.array([0.2, 0.55, 0.9])
    x_all, switches = _run(forces, amplitudes, 2e-3, kernel=kernel)
    assert switches.max() > 0
    x_alone, _ = _run(forces[[1]], amplitudes[1:], 2e-3, kernel=kernel)
    x_reversed, _ = _run(forces[::-1], amplitudes[::-1], 2e-3, kernel=kernel)
    assert x_alone[0] == x_all[4]
    np.testing.assert_array_equal(x_reversed[:3], x_all[3:][::-1])


def test_bad_input_is_refused_in_one_line():
    coeffs = normal_coefficients(ms.Model(P).pack(0.0))[None]
    normal0 = np.array([[P.static_deflection, 0.0]])
    with pytest.raises(ValueError, match="stiffness must be > 0"):
        run_spring_lanes(coeffs, normal0, [0.0], [0], [0.5], 0.1, 0.1, 1e-3, DT)
    two = np.repeat(coeffs, 2, axis=0)
    with pytest.raises(ValueError, match="non-decreasing"):
        run_spring_lanes(two, np.repeat(normal0, 2, axis=0), [K_T, K_T], [1, 0], [0.5, 0.5],
                         0.1, 0.1, 1e-3, DT)  # fmt: skip


@pytest.mark.parametrize("tau_root", [0.03, 0.3, 0.9])
def test_a_stick_from_its_limit_finds_the_next_release(tau_root):
    """The search that follows every stop: the margin starts at a double zero
    (g = c τ² (τ_r - τ), the limit μ_s P against a constant spring force) and must find
    its next root at τ_r, neither stepping over it nor creeping out of the start."""
    mu_s, force, c = 0.1, 0.5, 0.02
    a = (force / mu_s, 0.0, c * tau_root / mu_s, -c / mu_s, 0.0)
    d0, _, d2, d3 = law.derivative_bounds(a)
    p = (0.0, 0.01, 0.0, 0.0, force, mu_s, 0.0)  # τ_a, θ, e_a = 0, k_t ẋ_a/ω = 0, f_a, μ_s
    noise = 1e-15 * (mu_s * d0 + force)
    tau = law._first_exit(law._STICK, a, p, mu_s * d2, mu_s * d3, noise, 0.0, 1.0)
    assert tau_root <= tau <= tau_root + 1e-9


@pytest.mark.parametrize("ulps", [-4.0, 4.0])
def test_a_stick_off_its_limit_by_rounding_still_finds_the_next_release(ulps):
    """As above with the spring force a few ulps off the limit μ_s P(0), either way:
    what fused multiply-adds leave of μ_s P - μ_k P at a stop (a GPU compiles a*b - c
    as one rounding; docs/theory/numerics.md). Within the rounding the start is inside:
    the search must find τ_r, not a release at 0, which a lane repeats at every stop
    until it stalls (as the spring lanes did on an H100 before the test took the
    rounding into account)."""
    mu_s, force, c, tau_root = 0.1, 0.5, 0.02, 0.3
    a = (force / mu_s, 0.0, c * tau_root / mu_s, -c / mu_s, 0.0)
    d0, _, d2, d3 = law.derivative_bounds(a)
    f_a = force * (1.0 + ulps * 2.0**-52)
    assert (mu_s * a[0] - f_a < 0.0) == (ulps > 0)
    p = (0.0, 0.01, f_a - force, 0.0, f_a, mu_s, 0.0)
    noise = 1e-15 * (mu_s * d0 + f_a)
    bound2 = mu_s * d2 + 1e-4 * abs(f_a - force)
    bound3 = mu_s * d3 + 1e-6 * abs(f_a - force)
    tau = law._first_exit(law._STICK, a, p, bound2, bound3, noise, 0.0, 1.0)
    assert tau_root <= tau <= tau_root + 1e-9


@pytest.mark.parametrize("kernel", KERNELS)
def test_zero_force_lanes_stay_at_rest_through_flights(kernel):
    """F = 0 on a free vibration with a flight every period (and one without): every
    lane stays exactly at x = 0, ẋ = 0 with a relaxed spring, landing and lifting off
    (the stick law's shortcut for a lane at rest on a relaxed spring under F = 0), while
    a lane with F > 0 beside it moves."""
    from microslip.integrators.mindlin_lanes import run_mindlin_lanes

    y0 = P.static_deflection
    amplitudes = [2.5 * y0, 0.5 * y0]
    model = ms.Model(P, tangential=ms.TangentialSpring(K_T))
    normal0 = np.array([initial_state_from_amplitude(P, a)[:2] for a in amplitudes])
    coeffs = np.repeat(normal_coefficients(model.pack(0.0))[None], 2, axis=0)
    run, parameter = (run_spring_lanes, K_T) if kernel == "spring" else (run_mindlin_lanes, 1.0)
    forces = np.array([0.0, 0.0, 0.3, 0.0])
    x, v, f, mode, switches, _ = run(coeffs, normal0, [parameter] * 2, [0, 0, 0, 1], forces,
                                     P.mu, P.mu, 0.004, DT)  # fmt: skip
    rest = forces == 0.0
    assert np.all(x[rest] == 0.0) and np.all(v[rest] == 0.0) and np.all(f[rest] == 0.0)
    assert np.all((mode[rest] == 0.0) | (mode[rest] == 2.0))  # stuck or in flight
    assert switches[0] >= 3  # landed every period (~1 ms)
    assert abs(x[2]) > 0.0


def test_oscillation_series_matches_libm_on_both_sides_of_its_bound():
    """(sin d, cos d - 1) of the stick oscillator: the Taylor series below SERIES_BOUND
    and libm above agree with libm's sin d and -2 sin²(d/2) to a few ulps (both round:
    the worst seen is 2 ulps). A coefficient 10 % off fails near the bound, up to the
    d⁹ term of sin d and the d¹⁰ term of cos d - 1 (relative weights 1.6e-13 and
    3.3e-14 there; the last terms, below 3e-17, only round)."""
    bound = law.SERIES_BOUND
    angles = np.concatenate(
        [np.linspace(-2.0 * bound, 2.0 * bound, 4001), [bound, -bound, 1e-300, 0.0, 1e-9]]
    )
    for d in angles:
        sine, cos_minus_one = law.oscillation(float(d))
        assert sine == pytest.approx(math.sin(d), rel=1e-15, abs=0.0)
        reference = -2.0 * math.sin(0.5 * d) ** 2
        assert cos_minus_one == pytest.approx(reference, rel=1e-15, abs=0.0)


@pytest.mark.parametrize("seed", range(8))
def test_safe_step_stays_within_the_first_order_bound(seed):
    """Where only the first-order proof applies (curvature <= 0), the step is within
    the root of g + r s - M s²/2 (no function of value g, slope r and |g''| <= M can
    vanish before it) and at most 0.2 % short of it, falling (near a root and far from
    one) or rising."""
    rng = np.random.default_rng(seed)
    for _ in range(2000):
        g = 10.0 ** rng.uniform(-12.0, 0.0)
        r = rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(-6.0, 3.0)
        bound2 = 10.0 ** rng.uniform(-6.0, 6.0)
        curvature = -rng.uniform(0.0, bound2)
        step = law.safe_step(g, r, curvature, bound2, 1.0)
        root = math.sqrt(r * r + 2.0 * bound2 * g)
        exact = 2.0 * g / (root - r) if r < 0.0 else (r + root) / bound2
        assert step <= exact * (1.0 + 1e-15)
        assert step >= exact * (1.0 - 2e-3)
