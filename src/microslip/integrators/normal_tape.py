"""The normal motion once, as a tape of polynomial pieces shared by many tangential lanes.

The normal motion never depends on the tangential one (docs/design.md): at a given
normal set-up (contact law, damping, excitation, initial normal state) it is the same
for every force, friction coefficient and drive. :func:`fill_tape` integrates it as the
core RK4 kernel does (:func:`~microslip.integrators.kernel.integrate_chunk`: fixed steps
on the grid k·dt, every contact switch located; the step and the search on (y, ẏ)
alone: :mod:`~microslip.integrators.normal_step`) on a copy of the model whose tangential
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
from microslip.integrators.normal_step import (
    contact_switch,
    end_values,
    may_switch,
    rk4,
    time_terms,
)

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
    EMPTY_SPAN,
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
    extend_span,
    flight_piece,
    has_flight,
    integral,
    poly,
    poly_rate,
    span,
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
from microslip.model.drive import KINEMATIC
from microslip.model.friction import COULOMB
from microslip.model.normal import gap, normal_force, raw_normal_force
from microslip.model.switches import contact_event, rigid_contact_mode, rigid_initial_mode
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


@njit(cache=True, inline="always")
def piece_coefficients(t0, y0, v0, ends0, t1, y1, v1, ends1, c):
    """The quartic (a0, ..., a4) [N] of the normal force over the piece from
    (t0, y0, ẏ0) to (t1, y1, ẏ1) of a normal motion in coefficients ``c``; zeros in
    flight. ``ends0``, ``ends1`` are :func:`~microslip.integrators.normal_step.end_values`
    there (computed once per boundary, shared by the pieces on either side)."""
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


WORK_SCRATCH = 1  # rows of the ``work`` scratch of :func:`fill_tape`: the start state

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


@njit(cache=True, error_model="numpy")
def fill_tape(carry, c_array, t_end, dt, tape, work):
    """Integrate the normal motion on from ``carry`` and write its pieces into ``tape``.

    Fixed RK4 steps on the grid k·dt (the last one clipped to ``t_end``); a step in
    which a contact function may flip has it located
    (:func:`~microslip.integrators.normal_step.contact_switch`), and the piece ends at
    the switch, as in :func:`~microslip.integrators.kernel.integrate_chunk`. ``work`` is
    scratch of WORK_SCRATCH rows of N_STATE values. Returns (rows written, status):
    0 when ``t_end`` was reached, 1 when the tape is full (call again), STALLED when a
    step holds too many switches.
    """
    c = as_tuple(c_array)
    t, y, v = carry[C_T], carry[C_Y], carry[C_YDOT]
    k = int(carry[C_K])
    mode = carry[C_MODE]
    if mode != mode:  # the start: the kinematic drive's direction (+1, it never switches)
        start = work[0]
        start[:] = 0.0
        start[0], start[1], start[3] = y, v, 1.0
        mode = rigid_initial_mode(t, start, normal_force(t, y, v, c), c)
    ends0 = end_values(t, y, v, time_terms(t, c), c)
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
        terms1 = time_terms(t1, c)  # shared by the step's last stage and its end values
        y1, v1 = rk4(t, h, t1, y, v, ends0[0], terms1, c, airborne(mode))
        ends1 = end_values(t1, y1, v1, terms1, c)
        if may_switch(h, ends0, ends1, c):
            theta, which = contact_switch(t, h, y, v, ends0, ends1, c, airborne(mode))
            if which >= 0 and theta < 1.0:
                t1 = t + theta * h
                terms1 = time_terms(t1, c)
                y1, v1 = rk4(t, theta * h, t1, y, v, ends0[0], terms1, c, airborne(mode))
                # The copy's contact is rigid: apply_switch's law for it.
                mode = rigid_contact_mode(contact_event(which, t1, y1, v1, c), mode, c)
                ends1 = end_values(t1, y1, v1, terms1, c)
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
