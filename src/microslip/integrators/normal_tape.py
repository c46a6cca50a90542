"""The normal motion once, as a tape of polynomial pieces shared by many tangential lanes.

The normal motion never depends on the tangential one (docs/design.md): at a given
normal set-up (contact law, damping, excitation, initial normal state) it is the same
for every force, friction coefficient and drive. :func:`fill_tape` integrates it with the
core RK4 kernel (:func:`~microslip.integrators.kernel.integrate_chunk`, fixed steps on
the grid k·dt, every contact switch located) on a copy of the model whose tangential
side cannot switch (a kinematic drive on a rigid contact: only the contact functions are
active), so the normal states on the grid are those of ``simulate(method="rk4")`` up to
the first tangential switch of a trajectory.

Each piece between two boundaries (grid points and contact switches) becomes a row of
the tape (its columns and the quartic's functions: :mod:`microslip.integrators.tape_row`):
its start t0 [s], length h [s], and the normal force over it as a quartic in
τ = (t - t0)/h ∈ [0, 1],

    P(τ) = a0 + a1 τ + a2 τ² + a3 τ³ + a4 τ⁴   [N],

interpolating N and h·dN/dt at both ends and N at the middle (the middle state from the
quintic Hermite interpolant of y through y, ẏ, ÿ at both ends). N is smooth inside a
piece (contact switches are piece ends), so P is O(h⁵) accurate there; a piece in
flight has P = 0. The row also holds the exact integrals I(1) = ∫₀¹ P and
K(1) = ∫₀¹ (1 - τ) P, the exact extremes of P on [0, 1], and its critical points (the
roots of P', at most three), which split the piece into segments where P is monotone:
the lanes' located switching (:mod:`microslip.integrators.shared_lanes`) brackets every
root on those segments, so no double crossing can hide inside a piece. The row ends with
the normal state (y, ẏ, ÿ) at both ends, for a law that depends on more than N (the
Mindlin stiffness k_t(δ): :func:`~microslip.integrators.mindlin_piece.hermite_state`).

Nothing here knows about the lanes: the tape is the normal force N(t) [N] of one
normal set-up.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators.kernel import (
    MAX_SWITCHES_PER_STEP,
    STALLED,
    as_tuple,
    next_grid_point,
)
from microslip.integrators.methods import RK4, WORK_ROWS, advance
from microslip.integrators.switching import first_switch, method_for, two_sided_may_flip

# A row's columns and the quartic of its piece are tape_row's; all its names are
# re-exported here (callers read nt.ROW, nt.H, nt.poly, nt.integral, ...).
from microslip.integrators.tape_row import (  # noqa: F401  (re-exported)
    _BISECTIONS,
    A0,
    A1,
    A2,
    A3,
    A4,
    CRIT1,
    CRIT2,
    CRIT3,
    INT1,
    KINT1,
    NCRIT,
    PMAX,
    PMIN,
    ROW,
    T0,
    Y_END,
    Y_START,
    YDDOT_END,
    YDDOT_START,
    YDOT_END,
    YDOT_START,
    H,
    _extremes,
    _quartic,
    _root_of_rate,
    coefficients,
    critical_points,
    double_integral,
    flight_piece,
    has_flight,
    integral,
    poly,
    poly_rate,
)
from microslip.model.coefficients import (
    DRIVE_AMPLITUDE,
    DRIVE_KIND,
    DRIVE_OMEGA,
    DRIVE_VELOCITY,
    FORCE,
    FRICTION_KIND,
    MU,
    MU_STATIC,
    STRIBECK_EXPONENT,
    STRIBECK_VELOCITY,
    TANGENTIAL_KIND,
    TANGENTIAL_STIFFNESS,
)
from microslip.model.damping import can_separate_in_overlap
from microslip.model.drive import KINEMATIC
from microslip.model.excitation import is_prescribed
from microslip.model.friction import COULOMB
from microslip.model.normal import (
    acceleration_from_force,
    gap,
    normal_acceleration,
    raw_normal_force,
)
from microslip.model.switches import apply_switch, initial_mode
from microslip.model.switching_functions import (
    contact_side_rate,
    separation_rate,
    separation_value,
)
from microslip.model.system import N_STATE, airborne
from microslip.model.tangential import RIGID

TAPE_ROWS = 2048  # pieces a lane kernel takes per call of fill_tape (bounded memory)


def normal_coefficients(c: np.ndarray) -> np.ndarray:
    """A copy of coefficient vector ``c`` whose tangential side cannot switch: a rigid
    contact, Coulomb friction and a kinematic drive at 1 m/s. Its normal motion is the
    model's (no normal law reads the tangential slots)."""
    out = np.array(c, dtype=np.float64, copy=True)
    out[TANGENTIAL_KIND] = RIGID
    out[FRICTION_KIND] = COULOMB
    out[DRIVE_KIND] = KINEMATIC
    out[DRIVE_VELOCITY] = 1.0
    return out


# The tangential slots of a coefficient vector (force, friction, spring, drive): no
# normal law reads them, so two set-ups that differ only there have the same tape.
TANGENTIAL_SLOTS = (
    FORCE, MU, MU_STATIC, TANGENTIAL_STIFFNESS, STRIBECK_VELOCITY, STRIBECK_EXPONENT,
    DRIVE_AMPLITUDE, DRIVE_OMEGA,
)  # fmt: skip


def normal_key(c: np.ndarray) -> bytes:
    """The normal set-up of coefficient vector ``c`` as bytes: equal for vectors whose
    normal motion is the same (:func:`normal_coefficients`, the tangential slots zeroed)."""
    out = normal_coefficients(c)
    out[list(TANGENTIAL_SLOTS)] = 0.0
    return out.tobytes()


# fill_tape's per-step helpers are inlined into it (inline="always"), and it takes their
# error model: each compiled call passed the coefficient tuple (SIZE floats) by value, a
# third of a step's cost (docs/design.md, "Compile time").
@njit(cache=True, error_model="numpy", inline="always")
def _end_values(t, y, ydot, c):
    """(ÿ [m/s^2], N_raw [N], dN_raw/dt [N/s], δ [m], δ̇ [m/s], dN/dt in contact [N/s])
    at a piece end: the normal acceleration, the SEPARATION function and its rate (the
    raw law: continuous through a separation inside the overlap, where the clipped N has
    a kink), the CONTACT_GAP function and its rate, and the rate seen from inside the
    contact (:func:`~microslip.model.switching_functions.contact_side_rate`: at a loss
    of contact at δ = 0 the piece before it ends with the law's slope, S c_n δ̇ for
    m2 = 1, where SEPARATION's rate, past δ = 0, is 0). Computed once per boundary: the
    quartics on either side, the screening of the step and the next step's first RK4
    stage share them."""
    delta, delta_rate, third = gap(t, y, ydot, c)
    acceleration = normal_acceleration(t, y, ydot, c)
    delta_accel = third if is_prescribed(c) else acceleration - third
    return (
        acceleration,
        separation_value(delta, delta_rate, c),
        separation_rate(delta, delta_rate, delta_accel, c),
        delta,
        delta_rate,
        contact_side_rate(delta, delta_rate, delta_accel, c),
    )


@njit(cache=True, inline="always")
def piece_coefficients(t0, y0, v0, ends0, t1, y1, v1, ends1, c):
    """The quartic (a0, ..., a4) [N] of the normal force over the piece from
    (t0, y0, ẏ0) to (t1, y1, ẏ1) of a normal motion in coefficients ``c``; zeros in
    flight. ``ends0``, ``ends1`` are :func:`_end_values` there (computed once per
    boundary, shared by the pieces on either side)."""
    h = t1 - t0
    acc0, n0, rate0 = ends0[0], ends0[1], ends0[5]
    acc1, n1, rate1 = ends1[0], ends1[1], ends1[5]
    # The middle of the piece from the quintic Hermite interpolant of y.
    y_mid = 0.5 * (y0 + y1) + h * (v0 - v1) * (5.0 / 32.0) + h * h * (acc0 + acc1) / 64.0
    v_mid = 15.0 * (y1 - y0) / (8.0 * h) - 7.0 * (v0 + v1) / 16.0 + h * (acc1 - acc0) / 32.0
    t_mid = t0 + 0.5 * h
    n_mid = 0.0
    if gap(t_mid, y_mid, v_mid, c)[0] > 0.0:
        n_mid = raw_normal_force(t_mid, y_mid, v_mid, c)
    if n_mid <= 0.0:  # in flight
        return 0.0, 0.0, 0.0, 0.0, 0.0
    return _quartic(n0, h * rate0, n_mid, n1, h * rate1)


WORK_SCRATCH = WORK_ROWS + 6  # rows of the ``work`` scratch of :func:`fill_tape`

# Slots of the carry vector of a tape integration.
C_T, C_Y, C_YDOT, C_K, C_MODE = range(5)
CARRY = 5


@njit(cache=True)
def start_tape(y0, ydot0):
    """Carry vector of the normal integration from (y0 [m], ẏ0 [m/s]) at t = 0."""
    carry = np.zeros(CARRY)
    carry[C_Y] = y0
    carry[C_YDOT] = ydot0
    carry[C_MODE] = math.nan  # set by the first fill_tape (it has the coefficients)
    return carry


@njit(cache=True)
def tape_buffers(y0, ydot0):
    """(carry, tape, work) of a tape integration from (y0 [m], ẏ0 [m/s]) at t = 0: the
    carry vector (:func:`start_tape`), a tape of TAPE_ROWS rows and the scratch of
    :func:`fill_tape`."""
    tape = np.empty((TAPE_ROWS, ROW))
    work = np.zeros((WORK_SCRATCH, N_STATE))
    return start_tape(y0, ydot0), tape, work


@njit(cache=True, inline="always")
def _held_acceleration(t, y, v, c, flight):
    """ÿ [m/s^2] at a stage: N = 0 in flight, else the law at the stage state."""
    if flight:
        return acceleration_from_force(t, 0.0, c)
    return normal_acceleration(t, y, v, c)


@njit(cache=True, error_model="numpy", inline="always")
def _rk4(t, h, t1, y, v, a1, c, flight):
    """One RK4 step of the normal motion alone: the arithmetic of
    :func:`~microslip.integrators.steppers.rk4_step` on the (y, ẏ) components; ``a1`` is
    ÿ at the step start (from :func:`_end_values`). In ``flight`` N = 0 at every stage
    (the mode holds the contact: :func:`~microslip.model.system.derivatives`). The last
    stage is at ``t1``, the step's end (its grid point), which is t + h to the bit
    wherever t >= t1/2 (then h = t1 - t is exact, by Sterbenz's lemma): every step but
    one that starts at a switch inside the first grid interval. Written so, the
    excitation's value at t1 is shared with the step's end values (:func:`_end_values`),
    one sin a step fewer for a harmonic excitation."""
    hh = 0.5 * h
    y2, v2 = y + hh * v, v + hh * a1
    a2 = _held_acceleration(t + hh, y2, v2, c, flight)
    y3, v3 = y + hh * v2, v + hh * a2
    a3 = _held_acceleration(t + hh, y3, v3, c, flight)
    y4, v4 = y + h * v3, v + h * a3
    a4 = _held_acceleration(t1, y4, v4, c, flight)
    w = h / 6.0
    return y + w * (v + 2.0 * v2 + 2.0 * v3 + v4), v + w * (a1 + 2.0 * a2 + 2.0 * a3 + a4)


@njit(cache=True, inline="always")
def _may_switch(h, ends0, ends1, c):
    """False when neither contact function can flip inside the step (the screening of
    :mod:`~microslip.integrators.switching`, on the end values)."""
    if two_sided_may_flip(ends0[3], ends1[3], ends0[4], ends1[4], h):
        return True
    if can_separate_in_overlap(c):
        return two_sided_may_flip(ends0[1], ends1[1], ends0[2], ends1[2], h)
    return False


@njit(cache=True, error_model="numpy")
def fill_tape(carry, c_array, t_end, dt, tape, work):
    """Integrate the normal motion on from ``carry`` and write its pieces into ``tape``.

    Fixed RK4 steps on the grid k·dt (the last one clipped to ``t_end``); a step in
    which a contact function may flip goes to the core located switching
    (:func:`~microslip.integrators.switching.first_switch`), and the piece ends at the
    switch, as in :func:`~microslip.integrators.kernel.integrate_chunk`. ``work`` is
    scratch of WORK_SCRATCH rows of N_STATE values. Returns (rows written, status):
    0 when ``t_end`` was reached, 1 when the tape is full (call again), STALLED when a
    step holds too many switches.
    """
    c = as_tuple(c_array)
    t, y, v = carry[C_T], carry[C_Y], carry[C_YDOT]
    k = int(carry[C_K])
    mode = carry[C_MODE]
    if mode != mode:  # the start: the kinematic drive's direction (+1, it never switches)
        start = work[WORK_ROWS]
        start[:] = 0.0
        start[0], start[1], start[3] = y, v, 1.0
        mode = initial_mode(t, start, c)
    ends0 = _end_values(t, y, v, c)
    rows = 0
    status = 0
    switches_in_step = 0
    while t < t_end:
        if rows >= tape.shape[0]:
            status = 1
            break
        target, k = next_grid_point(t, 0.0, k, dt, t_end)
        h = target - t
        t1 = target
        y1, v1 = _rk4(t, h, t1, y, v, ends0[0], c, airborne(mode))
        ends1 = _end_values(t1, y1, v1, c)
        if _may_switch(h, ends0, ends1, c):
            s0, s1, piece = work[WORK_ROWS], work[WORK_ROWS + 1], work[WORK_ROWS + 2]
            trial, extremum, atol = work[WORK_ROWS + 3], work[WORK_ROWS + 4], work[WORK_ROWS + 5]
            s0[:] = 0.0
            atol[:] = 0.0
            s0[0], s0[1], s0[3] = y, v, 1.0
            for j in range(N_STATE):  # a loop: a slice copy compiles its error message
                s1[j] = s0[j]
            s1[0], s1[1] = y1, v1
            theta, which = first_switch(
                RK4, s0, s1, t, h, mode, c, 0.0, atol, trial, extremum, work
            )
            if which >= 0 and theta < 1.0:
                advance(method_for(RK4, which, c), s0, t, theta * h, mode, c, 0.0, atol, piece,
                        work)  # fmt: skip
                t1 = t + theta * h
                mode, _ = apply_switch(which, t1, piece, mode, c)
                y1, v1 = piece[0], piece[1]
                ends1 = _end_values(t1, y1, v1, c)
                switches_in_step += 1
                if switches_in_step > MAX_SWITCHES_PER_STEP:
                    status = STALLED
                    break
        if t1 == target:
            k += 1
            switches_in_step = 0
        # The row, written here: a compiled call taking ``tape`` would count it.
        a = piece_coefficients(t, y, v, ends0, t1, y1, v1, ends1, c)
        p_min, p_max, n_crit, tau1, tau2, tau3 = _extremes(a)
        tape[rows, T0] = t
        tape[rows, H] = t1 - t
        for j in range(5):
            tape[rows, A0 + j] = a[j]
        tape[rows, INT1] = integral(a, 1.0)
        tape[rows, KINT1] = double_integral(a, 1.0)
        tape[rows, PMIN] = p_min
        tape[rows, PMAX] = p_max
        tape[rows, NCRIT] = n_crit
        tape[rows, CRIT1] = tau1
        tape[rows, CRIT2] = tau2
        tape[rows, CRIT3] = tau3
        tape[rows, Y_START], tape[rows, YDOT_START], tape[rows, YDDOT_START] = y, v, ends0[0]
        tape[rows, Y_END], tape[rows, YDOT_END], tape[rows, YDDOT_END] = y1, v1, ends1[0]
        rows += 1
        t, y, v, ends0 = t1, y1, v1, ends1
    carry[C_T], carry[C_Y], carry[C_YDOT], carry[C_K], carry[C_MODE] = t, y, v, k, mode
    return rows, status


@njit(cache=True)
def leaves_contact(c, y0, ydot0, t_end, dt):
    """True when the normal motion in coefficients ``c`` (:func:`normal_coefficients`)
    from (y0 [m], ẏ0 [m/s]) at t = 0 has a tape row in flight before ``t_end`` [s], at
    the RK4 step ``dt`` [s]: the test by which the Mindlin lanes hand back a set-up of a
    rough exponent (:mod:`~microslip.integrators.mindlin_lanes`), without its lanes. A
    normal integration that fails counts as leaving (the run reports it)."""
    carry, tape, work = tape_buffers(y0, ydot0)
    while True:
        rows, status = fill_tape(carry, c, t_end, dt, tape, work)
        if status > 1 or has_flight(tape, rows):
            return True
        if status == 0:
            return False
