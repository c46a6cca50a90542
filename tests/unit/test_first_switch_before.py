"""first_switch screens and locates the functions after a found flip only up to it.

The step here holds a lift-off of a MindlinSpring on a Hertz contact (m2 = 1.5). A
contact point sliding forward (s = +1) while the body moves back has s u̇ > 0 in contact
(the spring unloads with N), and u̇ = ẋ < 0 in flight: over the whole step the sliding
speed's ends differ in sign, a jump at the lift-off, not a stop. first_switch must
return the lift-off, located as on its own, and must still find a tangential flip that
comes before it (a release of a stuck point as N falls). The state it hands back for the
step to the flip is that step's.
"""

import math

import numpy as np
import pytest

import microslip as ms
from microslip.analysis.free_vibration import free_period
from microslip.integrators import normal_tape as nt
from microslip.integrators import periodic_tape, switching
from microslip.integrators.kernel import as_tuple
from microslip.integrators.methods import DOP853, RK4, RK4_GRADED, WORK_ROWS, advance
from microslip.integrators.mindlin_windows import on_grid
from microslip.integrators.steppers import rk4_step
from microslip.model.normal import normal_force
from microslip.model.system import (
    CONTACT_GAP,
    FT,
    N_STATE,
    SLIDING_SPEED,
    STICK_MARGIN,
    XDOT,
    YDOT,
    Y,
    state_tuple,
)

PARAMS = ms.Parameters(m2=1.5)
MODEL = ms.Model(PARAMS, tangential=ms.MindlinSpring(0.8235))


@pytest.fixture(scope="module")
def lift_off_step():
    """(t [s], h [s], y [m], ẏ [m/s], N [N], c): the grid step of a repeated Hertz tape
    (A = 1.2 y0) that holds its lift-off, from the tape's state at its start."""
    c = MODEL.pack(0.4)
    amplitude = 1.2 * PARAMS.static_deflection
    period = free_period(PARAMS, amplitude)
    dt = ms.budget.shortest_period(MODEL) / 200
    rows, shape = periodic_tape.cycle_rows(
        nt.normal_coefficients(c), PARAMS.static_deflection - amplitude, 0.0, period, 0.05, dt
    )
    step = period / math.ceil(period / dt)
    flight = [nt.flight_piece(nt.coefficients(rows, j)) for j in range(shape[0])]
    lift = next(j for j in range(1, shape[0]) if flight[j] and not flight[j - 1])
    start = next(j for j in range(lift - 1, -1, -1) if on_grid(rows[j, nt.T0], step))
    t0 = rows[start, nt.T0]
    assert t0 < rows[lift, nt.T0] < t0 + step  # the lift-off is inside the step
    y, ydot = rows[start, nt.Y_START], rows[start, nt.YDOT_START]
    laws = as_tuple(c)
    return t0, step, y, ydot, normal_force(t0, y, ydot, laws), laws


def _first(state, mode, t0, h, laws):
    s1 = np.zeros(N_STATE)
    work = np.zeros((WORK_ROWS, N_STATE))
    rk4_step(state, t0, h, mode, laws, s1, work)
    scratch = np.zeros(N_STATE), np.zeros(N_STATE), np.zeros(N_STATE)
    found = switching.first_switch(RK4, state, s1, t0, h, mode, laws, 1.0, scratch[0],
                                   scratch[1], scratch[2], work)  # fmt: skip
    return found, s1


def _alone(which, method, state, s1, mode, t0, h, laws):
    """θ of function ``which`` located over the whole step, as if no other flipped."""
    work = np.zeros((WORK_ROWS, N_STATE))
    verdict, g0, g1, r0, r1 = switching._screen(which, t0, h, mode, laws, state_tuple(state),
                                                state_tuple(s1))  # fmt: skip
    assert verdict != switching._CLEAR
    if verdict == switching._CROSSING:  # the ends' rates, as first_switch passes them
        r0 = r1 = math.nan
        if method == RK4_GRADED:
            r0 = switching.switching_rate(which, t0, state_tuple(state), mode, laws) * h
            r1 = switching.switching_rate(which, t0 + h, state_tuple(s1), mode, laws) * h
    scratch = np.zeros(N_STATE), np.zeros(N_STATE), np.zeros(N_STATE)
    return switching._resolve(verdict, which, method, state, t0, h, mode, laws, 1.0,
                              scratch[0], g0, g1, r0, r1, scratch[1], scratch[2],
                              work)[0]  # fmt: skip


def test_the_sliding_speeds_jump_at_a_lift_off_is_not_taken_for_a_stop(lift_off_step):
    t0, h, y, ydot, normal, laws = lift_off_step
    state = np.zeros(N_STATE)
    state[Y], state[YDOT], state[XDOT] = y, ydot, -5e-6
    state[FT] = PARAMS.mu * normal  # on the kinetic limit, sliding forward
    (theta, which, _held), s1 = _first(state, 1.0, t0, h, laws)
    # Over the whole step the sliding speed changes sign (the jump at the lift-off) ...
    verdict = switching._screen(SLIDING_SPEED, t0, h, 1.0, laws, state_tuple(state),
                                state_tuple(s1))[0]  # fmt: skip
    assert verdict == switching._CROSSING
    # ... but the step's switch is the lift-off, with the bits of its own search.
    assert which == CONTACT_GAP
    assert theta == _alone(CONTACT_GAP, RK4_GRADED, state, s1, 1.0, t0, h, laws)


def test_a_release_before_the_lift_off_is_still_found(lift_off_step):
    t0, h, y, ydot, normal, laws = lift_off_step
    state = np.zeros(N_STATE)
    state[Y], state[YDOT] = y, ydot
    state[FT] = 0.5 * PARAMS.mu * normal  # stuck, released once μ N falls to |f|
    (theta, which, _held), s1 = _first(state, 0.0, t0, h, laws)
    lift = _alone(CONTACT_GAP, RK4_GRADED, state, s1, 0.0, t0, h, laws)
    release = _alone(STICK_MARGIN, RK4, state, s1, 0.0, t0, h, laws)
    assert release < lift
    assert which == STICK_MARGIN
    # Located on the sub-step before the lift-off: the same instant to its tolerance.
    tolerance = 4.0 * np.finfo(float).eps * (t0 + h) / h
    assert abs(theta - release) <= 2.0 * tolerance


def test_the_state_handed_back_is_the_very_step_to_the_switch(lift_off_step):
    """first_switch hands back, where it says ``held``, the locating's last trial past
    the flip, which piece_end takes instead of stepping there again: it must be that
    step's bits (a trial from the bracket's near side, or a sub-step's trial, would be
    near it but not equal). Lift-offs (graded RK4), releases (RK4) and DOP853's own."""
    t0, h, y, ydot, normal, laws = lift_off_step
    dop_atol = np.full(N_STATE, 1e-12)
    held_count = located = 0
    for method in (RK4, DOP853):
        for mode, ft_share, xdot in [
            (1.0, 1.0, 5e-6), (1.0, 1.0, -5e-6), (-1.0, -1.0, -5e-6), (0.0, 0.0, 0.0),
            (0.0, 0.5, 0.0), (0.0, -0.8, 1e-7), (0.0, 0.95, -1e-7), (1.0, 1.0, 0.0),
        ]:  # fmt: skip
            state = np.zeros(N_STATE)
            state[Y], state[YDOT], state[XDOT] = y, ydot, xdot
            state[FT] = ft_share * PARAMS.mu * normal
            work = np.zeros((WORK_ROWS, N_STATE))
            s1 = np.zeros(N_STATE)
            advance(method, state, t0, h, mode, laws, 1e-10, dop_atol, s1, work)
            trial, extremum = np.zeros(N_STATE), np.zeros(N_STATE)
            theta, which, held = switching.first_switch(
                method, state, s1, t0, h, mode, laws, 1e-10, dop_atol, trial, extremum, work
            )
            assert which >= 0 and theta < 1.0
            located += 1
            if held:
                held_count += 1
                again = np.zeros(N_STATE)
                by = switching.method_for(method, which, laws)
                advance(by, state, t0, theta * h, mode, laws, 1e-10, dop_atol, again, work)
                assert np.array_equal(extremum, again), (method, mode, ft_share, xdot)
    # The saving is real: most located switches hand their step back.
    assert held_count >= located // 2, (held_count, located)
