"""A stuck spring lane over a span of tape rows at once (integrators/spring_pass.py,
``stuck_span``): the span's turn of the oscillator is its closed form, and the proof
that lets a lane take the span holds: wherever it does, the spring force stays within
the static limit μ_s N(t) at every instant of the span, N(t) read from the tape's own
quartics and f(t) from the oscillator, both sampled densely (an independent check of
the bound |f| <= max(|f0|, |f1|) + θ² sqrt(e0² + b²)/8 against the least N of the span).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import microslip as ms
from microslip.integrators import normal_tape as nt
from microslip.integrators.rigid_pass import SPAN_ROWS
from microslip.integrators.spring_lanes import run_spring_lanes
from microslip.integrators.spring_pass import span_constants, stuck_span
from microslip.simulation import initial_state_from_amplitude

P = ms.Parameters()
K_T = P.contact_stiffness
OMEGA = math.sqrt(K_T / P.mass)
DT = 2.0 * math.pi / OMEGA / 200.0
MU_S = 0.15


def _free_tape(amplitude: float, rows: int = 400) -> np.ndarray:
    """The first ``rows`` rows of the free vibration's tape from amplitude [m]."""
    model = ms.Model(P, tangential=ms.TangentialSpring(K_T))
    y0, ydot0 = initial_state_from_amplitude(P, amplitude)[:2]
    carry, tape, work = nt.tape_buffers(y0, ydot0)
    n_rows, _ = nt.fill_tape(
        carry, nt.normal_coefficients(model.pack(0.0)), rows * DT, DT, tape, work
    )
    return tape[:n_rows]


def _oscillator(x0, v0, f0, force, t):
    """(x [m], ẋ [m/s], f [N]) of a stuck lane t [s] later, the spring's closed form
    written out here: f - F = (f0 - F) cos ωt + (k_t ẋ0/ω) sin ωt."""
    e0, b = f0 - force, K_T * v0 / OMEGA
    c, s = np.cos(OMEGA * t), np.sin(OMEGA * t)
    return (
        x0 + e0 / K_T * (c - 1.0) + v0 / OMEGA * s,
        v0 * c - e0 / (P.mass * OMEGA) * s,
        force + e0 * c + b * s,
    )


def _least_margin(tape, b0, b1, x0, v0, f0, force):
    """min over the span of μ_s N(t) - |f(t)| [N], both sampled 200 times a row."""
    tau = np.linspace(0.0, 1.0, 200)
    least = math.inf
    for r in range(b0, b1):
        a = nt.coefficients(tape, r)
        normal = sum(a[j] * tau**j for j in range(5))
        t = tape[r, nt.T0] - tape[b0, nt.T0] + tau * tape[r, nt.H]
        spring = _oscillator(x0, v0, f0, force, t)[2]
        least = min(least, float(np.min(MU_S * normal - np.abs(spring))))
    return least


@pytest.mark.parametrize("amplitude", [0.0, 0.3e-7, 1.5e-7])
def test_a_lane_that_takes_a_span_sticks_throughout_it(amplitude):
    """Lanes pushed either way whose spring force peaks near μ_s times the span's
    least N, the peak inside the span or just outside it: each one that stuck_span lets
    through stays within the limit at every sampled instant, its end state is the closed
    form's, and the cases straddle the bound (some let through within 2% of it, some
    refused that do stay stuck). At A = 0 (N constant) a proof without its curvature
    term lets through lanes whose force peaks past the limit inside the span."""
    tape = _free_tape(amplitude)
    rng = np.random.default_rng(7)
    taken, refused_but_stuck, tight = 0, 0, 0
    for _ in range(600):
        b0 = SPAN_ROWS * int(rng.integers(0, tape.shape[0] // SPAN_ROWS))
        b1 = b0 + SPAN_ROWS
        length, _, _, p_min, _ = nt.span(tape, b0, b1)
        limit = MU_S * p_min
        reach = rng.uniform(0.02, 0.4) * limit  # the oscillation's amplitude [N]
        theta = OMEGA * length
        phase = rng.uniform(-theta - 0.1, 0.1)  # f - F = reach cos(ωt + phase)
        side = rng.choice([-1.0, 1.0])  # pushed either way
        force = side * (limit * (1.0 + rng.uniform(-0.02, 0.02)) - reach)
        f0 = force + side * reach * math.cos(phase)
        v0 = -side * reach * math.sin(phase) * OMEGA / K_T
        x0 = rng.uniform(-1e-8, 1e-8)
        k = span_constants(OMEGA, K_T, P.mass, length)
        stuck, x1, v1, f1 = stuck_span(k, p_min, 0.0, x0, v0, f0, force, MU_S)
        margin = _least_margin(tape, b0, b1, x0, v0, f0, force)
        if stuck:
            taken += 1
            assert margin >= -1e-12 * limit, (b0, margin / limit)
            tight += margin < 0.02 * limit
            expected = _oscillator(x0, v0, f0, force, length)
            scales = (abs(x0) + reach / K_T, reach * OMEGA / K_T, limit)
            for got, want, scale in zip((x1, v1, f1), expected, scales, strict=True):
                assert abs(got - want) <= 1e-12 * scale
        elif margin > 0.0:
            refused_but_stuck += 1
    assert taken > 50 and tight > 10 and refused_but_stuck > 10, (taken, tight, refused_but_stuck)


def test_only_a_stuck_lane_with_contact_throughout_takes_a_span():
    """A sliding or flying lane never takes a span, nor does any lane on a span whose
    least N is 0 (a flight or a touchdown in it)."""
    tape = _free_tape(0.3e-7)
    length, _, _, p_min, _ = nt.span(tape, 0, SPAN_ROWS)
    k = span_constants(OMEGA, K_T, P.mass, length)
    assert stuck_span(k, p_min, 0.0, 0.0, 0.0, 0.0, 0.0, MU_S)[0]
    for mode in (1.0, -1.0, 2.0):
        assert not stuck_span(k, p_min, mode, 0.0, 0.0, 0.0, 0.0, MU_S)[0]
    assert not stuck_span(k, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, MU_S)[0]


def test_lanes_stuck_throughout_a_run_follow_the_oscillator():
    """On a free vibration (N varies by ~30%), lanes at low forces stick throughout: the
    kernel takes them by spans, and where the run ends inside a span by its last rows
    alone; either way x is the oscillator's closed form (which does not depend on N) to
    1e-11, no lane is ever redone alone, and F = 0 stays exactly at rest."""
    forces = np.array([0.0, 0.05, 0.2]) * P.mu * P.mass * P.g
    model = ms.Model(P, tangential=ms.TangentialSpring(K_T))
    y0, ydot0 = initial_state_from_amplitude(P, 0.3e-7)[:2]
    coeffs = nt.normal_coefficients(model.pack(0.0))[None]
    for n_steps in (5 * SPAN_ROWS, 5 * SPAN_ROWS + 3):
        out = run_spring_lanes(coeffs, [[y0, ydot0]], [K_T], np.zeros(3, dtype=np.int64),
                               forces, P.mu, P.mu, n_steps * DT, DT)  # fmt: skip
        x, flagged = out[0], out[5]
        assert x[0] == 0.0 and out[2][0] == 0.0
        expected = _oscillator(0.0, 0.0, 0.0, forces[1:], n_steps * DT)[0]
        np.testing.assert_allclose(x[1:], expected, rtol=1e-11)
        assert not flagged[1:].any()
