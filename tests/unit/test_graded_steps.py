"""Graded fixed steps next to a Mindlin touchdown or loss of contact on a rough law.

A Mindlin stiffness ∝ δ^(m2-1) has a corner at δ = 0 for a non-integer m2 < 4
(docs/theory/numerics.md, "Order at a touchdown"). ``rk4`` and the batched kernel reach
such a flip on sub-steps that halve towards it (``steppers.rk4_graded_step``) and leave
it on steps that double from it (``kernel.graded_target``).
"""

import numpy as np
import pytest

import microslip as ms
from microslip.integrators.kernel import graded_target
from microslip.integrators.methods import RK4, RK4_GRADED, WORK_ROWS
from microslip.integrators.steppers import GRADED_FINEST, rk4_graded_step, rk4_step
from microslip.integrators.switching import method_for
from microslip.model.coefficients import as_tuple
from microslip.model.switches import initial_mode
from microslip.model.switching_functions import graded_after, graded_switch
from microslip.model.system import (
    CONTACT_GAP,
    CONTACT_LOST,
    CONTACT_MADE,
    FLIGHT,
    N_STATE,
    N_SWITCHES,
    YDOT,
    Y,
)

HERTZ = ms.Parameters(m2=1.5)


def _coefficients(model):
    return as_tuple(model.pack(0.3))


@pytest.mark.parametrize(
    "tangential, m2, graded",
    [
        ("mindlin", 1.5, True),
        ("mindlin", 2.5, True),
        ("mindlin", 3.7, True),
        ("mindlin", 1.0, False),
        ("mindlin", 2.0, False),
        ("mindlin", 3.0, False),
        ("mindlin", 4.5, False),
        ("spring", 1.5, False),  # the contact law's own corner is left to full steps
        ("rigid", 1.5, False),
    ],
)
def test_only_the_contact_gap_of_a_rough_mindlin_contact_is_graded(tangential, m2, graded):
    params = ms.Parameters(m2=m2)
    part = {
        "mindlin": ms.MindlinSpring(0.8235),
        "spring": ms.TangentialSpring(params.contact_stiffness),
        "rigid": None,
    }[tangential]
    c = _coefficients(ms.Model(params, tangential=part))
    assert graded_switch(CONTACT_GAP, c) == graded
    assert method_for(RK4, CONTACT_GAP, c) == (RK4_GRADED if graded else RK4)
    for which in range(N_SWITCHES):
        if which != CONTACT_GAP:
            assert not graded_switch(which, c)
            assert method_for(RK4, which, c) == RK4


def _departure(t, target, start, dt, grading=None):
    """The ends of the steps that graded_target gives from t towards the grid point
    ``target`` after a switch at ``start``, as the kernels take them (no switches);
    ``grading`` (a list), where given, gets whether grading goes on past each end."""
    ends = []
    while True:
        end, on_grid, still = graded_target(t, target, start, dt)
        ends.append(end)
        if grading is not None:
            grading.append(still)
        t = end
        if on_grid:
            return ends


def test_steps_double_from_the_switch_until_the_grid():
    dt = 1e-6
    grading = []
    ends = _departure(0.0, dt, 0.0, dt, grading)  # a switch on a grid point: dt to the next
    assert grading == [True] * 8 + [False]  # grading ends with the step to the grid
    lengths = np.diff([0.0, *ends])
    assert lengths[0] == pytest.approx(GRADED_FINEST * dt, rel=1e-12)
    assert lengths[1] == pytest.approx(GRADED_FINEST * dt, rel=1e-12)
    # each step is as long as the time since the switch, so the ends double
    ratios = np.array(ends[2:-1]) / np.array(ends[1:-2])
    assert np.allclose(ratios, 2.0, rtol=1e-12), ratios
    assert ends[-1] == dt  # the grid point itself, exactly
    assert len(ends) == 9  # 2^-8, 2^-7, ..., 2^-1, then 1: log2(1/GRADED_FINEST) + 1
    # no step longer than 1.5 times the time since the switch
    assert np.all(lengths[1:] <= 1.5 * np.array(ends[:-1]) * (1 + 1e-12))


def test_a_switch_just_before_a_grid_point_is_graded_past_it():
    """The touchdown 0.084 dt before a grid point: grading stopped at that grid point
    left the next full step with the corner 0.084 dt before its start (the error this
    was found by). The kernels keep grading until a grid point dt/2 past the switch."""
    dt = 1.0
    start = -0.084
    grading = []
    first = _departure(start, 0.0, start, dt, grading)
    assert first[-1] == 0.0
    # grading goes on: that grid point is less than dt/2 from the switch
    assert 0.0 - start < 0.5 * dt and grading[-1]
    grading = []
    second = _departure(0.0, 1.0, start, dt, grading)
    assert grading[-1] is False and all(grading[:-1])  # it ends at the next grid point
    lengths = np.diff([0.0, *second])
    assert lengths[0] == pytest.approx(0.084, rel=1e-12)  # as long as the time since
    assert second[-1] == 1.0
    assert np.all(lengths <= 1.5 * (np.array([0.0, *second[:-1]]) - start) + 1e-15)


def _flight_state(y, ydot):
    s = np.zeros(N_STATE)
    s[Y], s[YDOT] = y, ydot
    return s


def test_graded_step_ends_exactly_at_the_step_end_with_the_free_fall():
    """In flight the motion is a parabola, which RK4 integrates exactly on any steps:
    the graded step must give it to rounding. Sub-steps that do not add up to h (or a
    last one that overshoots) would show here."""
    model = ms.Model(HERTZ, tangential=ms.MindlinSpring(0.8235))
    c = _coefficients(model)
    y0, v0, t, h = -2e-7, 3e-3, 1.0e-3, 7.3e-7
    s = _flight_state(y0, v0)
    out = np.empty(N_STATE)
    work = np.empty((WORK_ROWS, N_STATE))
    mode = initial_mode(t, s, c)  # in flight: the motion is the free fall
    rk4_graded_step(s, t, h, mode, c, out, work)
    g = HERTZ.g
    assert out[Y] == pytest.approx(y0 + v0 * h + 0.5 * g * h * h, rel=0, abs=1e-20)
    assert out[YDOT] == pytest.approx(v0 + g * h, rel=1e-14)
    single = np.empty(N_STATE)
    rk4_step(s, t, h, mode, c, single, work)
    assert out[YDOT] == pytest.approx(single[YDOT], rel=1e-14)


def test_a_run_split_into_many_calls_keeps_its_grading():
    """integrate_chunk returns whenever its output buffer is full and resumes from its
    carry: a call that ends while leaving a graded switch must resume grading (the
    carry holds it), or the run's bits depend on the buffer size."""
    model = ms.Model(HERTZ, tangential=ms.MindlinSpring(0.8235), drive=ms.ConstantForce(0.5))
    y0 = HERTZ.static_deflection
    state0 = np.array([y0 - 1.3 * y0, 0.0, 0.0, 0.0])  # y_min = y0 - A, A = 1.3 y0: flights
    dt = HERTZ.natural_period / 200
    t_end = 4 * HERTZ.natural_period
    c = model.pack(0.5)
    runs = [
        ms.integrators.integrate("rk4", c, state0, 0.0, t_end, dt=dt, buffer_size=size)
        for size in (64, 1 << 16)
    ]
    assert runs[0].t.size == runs[1].t.size > 64 * 4
    assert np.array_equal(runs[0].t, runs[1].t)
    assert np.array_equal(runs[0].states, runs[1].states)


def test_a_touchdown_is_left_by_graded_steps_a_lift_off_by_one_step_to_the_grid():
    """Past a touchdown the Mindlin stiffness has its corner: the steps double from the
    flip (dt/256, dt/128, ...). Past a lift-off the point flies on a smooth right-hand
    side (model.switching_functions.graded_after): the next step ends on the grid."""
    model = ms.Model(HERTZ, tangential=ms.MindlinSpring(0.8235), drive=ms.ConstantForce(0.5))
    y0 = HERTZ.static_deflection
    state0 = np.array([y0 - 1.3 * y0, 0.0, 0.0, 0.0])  # A = 1.3 y0: a flight a period
    dt = HERTZ.natural_period / 200
    run = ms.integrators.integrate(
        "rk4", model.pack(0.5), state0, 0.0, 4 * HERTZ.natural_period, dt=dt
    )
    kinds = list(run.event_kind)
    assert kinds.count(CONTACT_MADE) >= 3 and kinds.count(CONTACT_LOST) >= 3
    for t_event, kind in zip(run.event_t, run.event_kind, strict=True):
        after = run.t[np.searchsorted(run.t, t_event, side="right")]
        if kind == CONTACT_MADE:
            assert after - t_event == pytest.approx(GRADED_FINEST * dt, rel=1e-9)
        elif kind == CONTACT_LOST:
            assert after == pytest.approx(np.ceil(t_event / dt) * dt, rel=1e-14)


@pytest.mark.parametrize("mode, graded", [(0.0, True), (1.0, True), (-1.0, True),
                                          (FLIGHT, False), (-FLIGHT, False)])  # fmt: skip
def test_graded_after_a_contact_flip_only_into_contact(mode, graded):
    rough = _coefficients(ms.Model(HERTZ, tangential=ms.MindlinSpring(0.8235)))
    smooth = _coefficients(ms.Model(ms.Parameters(), tangential=ms.MindlinSpring(0.8235)))
    assert graded_after(CONTACT_GAP, mode, rough) == graded
    assert not graded_after(CONTACT_GAP, mode, smooth)
    for which in range(N_SWITCHES):
        if which != CONTACT_GAP:
            assert not graded_after(which, mode, rough)
