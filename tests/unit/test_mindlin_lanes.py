"""The Mindlin-lane kernel (integrators/mindlin_lanes.py, mindlin_lane_law.py): its
per-piece stiffness and fundamental series against closed forms and a separate scipy
integration, a release that only the vector pass's curvature bound can find, and its
input checks. (At constant N, where k_t = λ K_n is constant, its lanes follow a spring's
closed forms and are the same bits whatever the other lanes:
tests/unit/test_spring_lanes.py runs those cases on both kernels.)

At rest in the static deflection (A = 0) N = m g and k_t = λ dN/dδ(y0) = λ K_n
throughout: from rest with a relaxed spring x = (F/k_t)(1 - cos ωt), ω = sqrt(k_t/m);
above μ_s N/2 the point releases at f = μ_s N, slides with f = μ_k N, stops and sticks
(tests/unit/test_spring_lanes.py derives the same closed forms).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import microslip as ms
from microslip.integrators import mindlin_lane_law as law
from microslip.integrators import normal_tape as nt
from microslip.integrators import threads
from microslip.integrators.mindlin_lanes import run_mindlin_lanes
from microslip.integrators.normal_tape import normal_coefficients
from microslip.simulation import initial_state_from_amplitude

P = ms.Parameters()
RATIO = 0.8235
K_T = RATIO * P.contact_stiffness
OMEGA = math.sqrt(K_T / P.mass)
N = P.mass * P.g
DT = 2.0 * math.pi / OMEGA / 200.0
C = normal_coefficients(ms.Model(P, tangential=ms.MindlinSpring(RATIO)).pack(0.0))


def _run(forces, amplitudes, duration, mu_s=P.mu, mu_k=P.mu, dt=DT):
    """x(duration) [m] per lane, amplitude-major then force, and the switch counts."""
    normal0 = np.array([initial_state_from_amplitude(P, a)[:2] for a in amplitudes])
    coeffs = np.repeat(C[None], len(amplitudes), axis=0)
    groups = np.repeat(np.arange(len(amplitudes)), len(forces))
    out = run_mindlin_lanes(coeffs, normal0, [RATIO] * len(amplitudes), groups,
                            np.tile(forces, len(amplitudes)), mu_s, mu_k, duration, dt)  # fmt: skip
    return out[0], out[4]


def _piece(amplitude, t0, h):
    """A tape row of the free normal vibration of amplitude A [m] from t0 [s] over h [s]
    (its end states from the closed-form-free RK4 of scipy at rtol 1e-13), and the
    piece vector written from it."""
    y0, v0 = initial_state_from_amplitude(P, amplitude)[:2]

    def rhs(t, z):
        delta = max(z[0], 0.0)
        return [z[1], P.g - P.stiffness_coefficient * delta**P.m2 / P.mass]

    sol = solve_ivp(rhs, (0.0, t0 + h), [y0, v0], method="DOP853", rtol=1e-13, atol=1e-20,
                    dense_output=True)  # fmt: skip
    tape = np.zeros((1, nt.ROW))
    tape[0, nt.T0], tape[0, nt.H] = t0, h
    for col_y, col_v, col_a, t in ((nt.Y_START, nt.YDOT_START, nt.YDDOT_START, t0),
                                   (nt.Y_END, nt.YDOT_END, nt.YDDOT_END, t0 + h)):  # fmt: skip
        y, v = sol.sol(t)
        tape[0, col_y], tape[0, col_v], tape[0, col_a] = y, v, rhs(t, [y, v])[1]
    piece = np.zeros(law.PIECE)
    law.set_setup(piece, P.mass, P.g, RATIO)
    a = (N, 0.0, 0.0, 0.0, 0.0)
    assert law.set_piece(piece, a, tape, 0, C) == 0
    return piece, sol


def test_stiffness_quartic_follows_the_mindlin_stiffness_inside_a_piece():
    """k_t(τ) against λ dN/dδ = λ m2 c δ^(m2-1) on the exact normal motion (scipy) at 21
    points of a piece of the default step: within 1e-9 relative (O(h⁵); a wrong node,
    fit or Hermite state gives 1e-3 or worse)."""
    h = P.natural_period / 200.0
    piece, sol = _piece(0.8 * P.static_deflection, 0.37 * P.natural_period, h)
    for tau in np.linspace(0.0, 1.0, 21):
        delta = sol.sol(0.37 * P.natural_period + tau * h)[0]
        exact = RATIO * P.m2 * P.stiffness_coefficient * delta ** (P.m2 - 1.0)
        fitted = law._quartic(piece, law.M_K, tau)[0]
        assert fitted == pytest.approx(exact, rel=1e-9)


def test_fundamental_series_at_constant_stiffness_is_the_oscillator():
    """At rest (k_t = λ K_n constant): (ẋ, e) rotate at ω, x = x0 + (ẋ0/ω) sin d +
    (e0/k_t)(cos d - 1), d = ω h τ; to 1e-13 of the state's scale."""
    h = 7.0 * DT  # θ ≈ 0.22: more series terms than the default step needs
    piece, _ = _piece(0.0, 0.0, h)
    x0, v0, e0 = 1e-9, 2e-4, -0.3
    for tau in (0.0, 0.25, 0.6, 1.0):
        d = OMEGA * h * tau
        x, v, e = law.stick_state(piece, x0, v0, e0, tau)
        assert v == pytest.approx(v0 * math.cos(d) - e0 / (P.mass * OMEGA) * math.sin(d),
                                  abs=1e-13 * abs(e0) / (P.mass * OMEGA))  # fmt: skip
        assert e == pytest.approx(e0 * math.cos(d) + P.mass * OMEGA * v0 * math.sin(d),
                                  abs=1e-13 * abs(e0))  # fmt: skip
        expected_x = x0 + v0 / OMEGA * math.sin(d) + e0 / K_T * (math.cos(d) - 1.0)
        assert x == pytest.approx(expected_x, abs=1e-13 * abs(e0) / K_T)


def test_fundamental_series_with_varying_stiffness_matches_scipy():
    """A piece of a large vibration, k_t varying by ~10 % over it: Φ(1) and ∫ẋ from the
    series against solve_ivp on the same quartic k(τ) (rtol 1e-13), and det Φ = 1."""
    h = 4.0 * P.natural_period / 200.0
    piece, _ = _piece(0.9 * P.static_deflection, 0.1 * P.natural_period, h)
    k = piece[law.M_K : law.M_K + 5]
    assert abs(k[1]) > 0.05 * abs(k[0])  # the stiffness does vary

    def rhs(tau, z):
        stiffness = np.polynomial.polynomial.polyval(tau, k)
        return [-h / P.mass * z[1], h * stiffness * z[0], h * z[0]]

    scale = math.sqrt(k[0] * P.mass)  # m ω: e against ẋ
    for column, start in ((0, [1.0, 0.0, 0.0]), (1, [0.0, 1.0, 0.0])):
        ref = solve_ivp(rhs, (0.0, 1.0), start, method="DOP853", rtol=1e-13, atol=1e-18).y[:, -1]
        v, e, x = (piece[law.M_PHI11 + column], piece[law.M_PHI21 + column],
                   piece[law.M_PSI1 + column])  # fmt: skip
        weight = 1.0 if column == 0 else scale
        assert v * weight == pytest.approx(ref[0] * weight, abs=1e-12)
        assert e * weight / scale == pytest.approx(ref[1] * weight / scale, abs=1e-12)
        assert x * weight == pytest.approx(ref[2] * weight, abs=1e-12 * h)
    det = piece[law.M_PHI11] * piece[law.M_PHI22] - piece[law.M_PHI12] * piece[law.M_PHI21]
    assert det == pytest.approx(1.0, abs=1e-13)


def test_a_stick_from_inside_the_piece_passes_through_its_start_state():
    """virtual_start then stick_state at the same τ_a gives back the lane's state."""
    piece, _ = _piece(0.9 * P.static_deflection, 0.1 * P.natural_period, 3.0 * DT)
    x_a, v_a, e_a = 3e-9, -1e-4, 0.2
    for tau_a in (0.2, 0.7):
        start = law.virtual_start(piece, tau_a, x_a, v_a, e_a)
        x, v, e = law.stick_state(piece, *start, tau_a)
        assert (x, v, e) == pytest.approx((x_a, v_a, e_a), rel=1e-13)


def test_bad_input_is_refused_in_one_line():
    normal0 = np.array([[P.static_deflection, 0.0]])
    with pytest.raises(ValueError, match=r"ratio must be > 0; got 0\.0"):
        run_mindlin_lanes(C[None], normal0, [0.0], [0], [0.5], 0.1, 0.1, 1e-3, DT)
    with pytest.raises(ValueError, match=r"dt = .* too coarse for the Mindlin"):
        run_mindlin_lanes(C[None], normal0, [RATIO], [0], [0.5], 0.1, 0.1, 1e-3, 100.0 * DT)


def test_a_release_between_two_sticking_piece_ends_is_found():
    """F = (1 + 1e-6) μ N/2: |f| = F(1 - cos ωt) passes μ N only for ~0.3 % of a period
    around its peak at π/ω, which the step puts in the middle of a piece; the margin is
    positive at both ends of that piece, so only the curvature bound of the vector pass
    can send it to the release search. Then the closed form of a release, slip and stop
    (μ_s = μ_k), and two switches."""
    mu = P.mu
    force = (1.0 + 1e-6) * 0.5 * mu * N
    dt = (math.pi / OMEGA) / 100.5  # the peak halfway through the 101st piece
    t1 = math.acos(1.0 - mu * N / force) / OMEGA
    v1 = force / K_T * OMEGA * math.sin(OMEGA * t1)
    deceleration = (mu * N - force) / P.mass
    t_stop = t1 + v1 / deceleration
    x_stop = mu * N / K_T + v1 * v1 / (2.0 * deceleration)
    amplitude = (mu * N - force) / K_T
    duration = t_stop + 0.4e-3
    x, switches = _run([force], [0.0], duration, dt=dt)
    assert switches[0] == 2
    expected = x_stop - amplitude * (1.0 - math.cos(OMEGA * (duration - t_stop)))
    assert x[0] == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("m2", [1.5, 2.5])
def test_an_exponent_rough_at_touchdown_hands_back_a_flight_only_without_windows(m2):
    """k_t ∝ δ^(m2-1) with 1 < m2 < 3, m2 != 2 is rough where δ = 0, and a lane that
    lands on its closed form would stall: without windows (``windowed=False``, what the
    GPU lanes do) a set-up that leaves contact is handed back (LaneStalledError naming
    it), with them it runs through its flights (tests/validation/
    test_mindlin_rough_flights_vs_event.py checks its values). One that stays in contact
    runs either way: at rest in the static deflection (N = m g, k_t = λ K_n with
    K_n = m2 m g/y0) a lane under F <= μ m g/2 sticks: x = F/k_t (1 - cos ωt)."""
    from microslip.integrators.shared_lanes import LaneStalledError

    params = ms.Parameters(m2=m2)
    c = normal_coefficients(ms.Model(params, tangential=ms.MindlinSpring(RATIO)).pack(0.0))
    y0 = params.static_deflection
    k_t = RATIO * params.contact_stiffness
    omega = math.sqrt(k_t / params.mass)
    dt = 2.0 * math.pi / omega / 200.0
    at_rest = [y0, 0.0]
    flight = list(initial_state_from_amplitude(params, 1.4 * y0)[:2])
    force, duration = 0.3, 1e-3
    args = (np.array([c, c]), np.array([at_rest, flight]), [RATIO, RATIO], [0, 1],
            [force, force], 0.1, 0.1, duration, dt)  # fmt: skip
    with pytest.raises(LaneStalledError, match="left contact") as info:
        run_mindlin_lanes(*args, windowed=False)
    assert list(info.value.setups) == [1]
    x, _v, _f, _mode, switches, _flagged = run_mindlin_lanes(*args)
    assert np.all(np.isfinite(x)) and switches[1] >= 1 and switches[0] == 0  # its landing
    alone = run_mindlin_lanes(c[None], np.array([at_rest]), [RATIO], [0], [force], 0.1, 0.1,
                              duration, dt)[0]  # fmt: skip
    expected = force / k_t * (1.0 - math.cos(omega * duration))
    assert alone[0] == pytest.approx(expected, rel=1e-9) and x[0] == alone[0]


def _repeated_set_up(amplitude, duration, dt=DT):
    """(coefficients, (y0, ẏ0), cycle, shape) of a free vibration of amplitude A [m]
    from rest at its top on a repeated tape (integrators/periodic_tape.py)."""
    from microslip.integrators import periodic_tape

    y0, ydot0 = initial_state_from_amplitude(P, amplitude)[:2]
    period = ms.free_period(P, amplitude)
    cycle, shape = periodic_tape.cycle_rows(C, y0, ydot0, period, duration, dt)
    assert shape[0] > 0 and shape[1] > 0 and shape[2] >= 3  # periods and a tail
    return y0, ydot0, cycle, shape


@pytest.mark.parametrize("amplitude", [0.5 * P.static_deflection, 2.5 * P.static_deflection])
def test_pieces_written_once_per_cycle_row_give_the_bits_of_writing_them_as_served(amplitude):
    """On a repeated tape the kernel writes each cycle row's piece once and reads it
    every period; writing it as each row is served (the rows shifted by k T, as
    periodic_tape.repeat_rows serves them) must give the same bits: the piece of a
    free vibration does not depend on the period it is in. With and without flights
    (A = 2.5 y0 leaves contact); a wrong row (the tail's, say) changes the bits."""
    from microslip.integrators import mindlin_lanes as ml
    from microslip.integrators import mindlin_windows as mw
    from microslip.integrators import periodic_tape
    from microslip.integrators.mindlin_spans import run_spans
    from microslip.integrators.rigid_pass import SPAN_ROWS
    from microslip.integrators.spring_pass import LANE_ROWS

    duration = 4.6 * P.natural_period
    y0, ydot0, cycle, shape = _repeated_set_up(amplitude, duration)
    forces = np.array([0.0, 0.2, 0.45, 0.55, 0.8, 1.2]) * P.mu * N

    def lanes():
        out = ml.pack_lanes(C[None], [RATIO], np.zeros(forces.size, dtype=np.int64), forces,
                            P.mu, 0.8 * P.mu, what="ratio")[0]  # fmt: skip
        return out, np.zeros(forces.size, dtype=np.int64), np.zeros(forces.size, dtype=np.int64)

    cached, switches, flagged = lanes()
    status = ml._run_group(C, y0, ydot0, RATIO, cycle, shape, duration, DT, cached, switches,
                           flagged, threads.stop_flag(), 0, True)  # fmt: skip
    assert status == 0 and switches.sum() > 10
    served, served_switches, served_flagged = lanes()
    flying = ml.start_lanes(C, y0, ydot0, served, forces.size)
    pieces = np.zeros((SPAN_ROWS, law.PIECE))  # each span's pieces, written as served
    for j in range(SPAN_ROWS):
        law.set_setup(pieces[j], P.mass, P.g, RATIO)
    n = forces.size
    scratch = (np.empty((LANE_ROWS, n)), np.empty(n, np.int64), np.empty((2, n), np.int64))
    carry, tape, _work = nt.tape_buffers(y0, ydot0)
    tape_status = 1
    while tape_status == 1:
        rows, tape_status = periodic_tape.repeat_rows(carry, tape, cycle, shape)
        window = mw.window_buffers(C, RATIO)
        status, flying = run_spans(served, tape, rows, (0, 0, 0, 0.0), pieces, -1, C, flying,
                                   served_switches, served_flagged, window, DT, True, scratch,
                                   threads.stop_flag(), 0)  # fmt: skip
        assert status == 0
    assert np.array_equal(cached, served)
    assert np.array_equal(switches, served_switches) and np.array_equal(flagged, served_flagged)


def test_a_step_too_coarse_on_a_repeated_tape_is_refused_in_one_line():
    amplitude = 0.5 * P.static_deflection
    normal0 = np.array([initial_state_from_amplitude(P, amplitude)[:2]])
    period = ms.free_period(P, amplitude)
    with pytest.raises(ValueError, match=r"dt = .* too coarse for the Mindlin"):
        run_mindlin_lanes(C[None], normal0, [RATIO], [0], [0.5], 0.1, 0.1, 5 * period,
                          60.0 * DT, periods=[period])  # fmt: skip


@pytest.mark.parametrize("degree", range(10))
def test_series_value_and_derivatives_against_numpy(degree):
    """_series (even and odd parts by Horner in τ²) gives Σ c_n τⁿ and its first two
    derivatives of every degree, odd and even, as numpy's polynomial does."""
    rng = np.random.default_rng(degree)
    coefficients = rng.normal(size=degree + 1)
    piece = np.full(degree + 8, np.nan)  # past the degree: never read
    piece[3 : 4 + degree] = coefficients
    p = np.polynomial.Polynomial(coefficients)
    scale = np.abs(coefficients).sum() * (1 + degree) ** 2
    for tau in (0.0, 0.3, 0.77, 1.0):
        value, rate, curvature = law._series(piece, 3, degree, tau)
        assert value == pytest.approx(p(tau), abs=1e-15 * scale)
        assert rate == pytest.approx(p.deriv()(tau), abs=1e-15 * scale)
        assert curvature == pytest.approx(p.deriv(2)(tau), abs=1e-15 * scale)
