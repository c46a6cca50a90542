"""Windows around the contact switches of a Mindlin set-up on a rough contact law: the
lanes of :mod:`microslip.integrators.mindlin_lanes` through a flight at a contact
exponent outside :func:`~microslip.integrators.mindlin_lanes.supports_exponent` (a
Hertz contact, m2 = 1.5).

There k_t = λ dN/dδ ∝ δ^(m2-1) is not smooth where δ = 0: the quartic of k_t on a piece
that touches δ = 0 misses its infinite slope, and a lane's closed form chatters there
(docs/theory/numerics.md, "Lanes on a Mindlin spring"). Away from δ = 0 the closed form
holds. So each lane crosses a lift-off and a touchdown on the core fixed-step kernel
instead, one lane at a time, with the model's own laws and switches
(:func:`~microslip.integrators.batched.scalar_step`, the scalar step of the batched RK4
kernel and of ``simulate(method="rk4")``: RK4 on the grid k·dt, every switch located,
the steps graded next to a touchdown or lift-off, docs/theory/numerics.md, "Order at a
touchdown"), over a *window* of the tape:

* a lift-off at t_l: the window starts at the last grid point at least MARGIN·dt before
  it (:func:`lift_off_ahead` looks for one in the next rows at every grid point of
  contact), and the scalar step finds its own lift-off;
* a touchdown at t_c (the tape's located instant, δ just positive): each lane lands by
  the model's rule (``switches.apply_switch``: a relaxed spring, stick unless it grazes)
  and the window starts there, its steps graded from t_c;
* a window ends at the first grid point of the tape where the lanes can take over: a
  row in flight (they fly on), or a contact row at least MARGIN·dt past the last
  touchdown (the grading's end, ``kernel.graded_target``, is dt/2).

Inside a window each lane integrates its own normal motion from the tape's state at the
window's start (the scalar step carries the whole state), which differs from the tape's
by the RK4 error of the graded steps. The lanes' bits still depend only on their own
parameters and their set-up. A window that does not end within the rows in sight (its
tape block and PEEK_ROWS after it, or one period of a repeated tape), or a lift-off
not seen coming, hands the set-up back, as before (``LEFT_ROUGH_CONTACT``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators import normal_tape as nt
from microslip.integrators.batched import scalar_step
from microslip.integrators.kernel import as_tuple, next_grid_point
from microslip.integrators.methods import WORK_ROWS
from microslip.integrators.spring_lanes import FORCE as LANE_FORCE
from microslip.integrators.spring_lanes import FS, MODE, MU_K, MU_S, V, X, lift_off
from microslip.integrators.tape_row import flight_piece
from microslip.model.coefficients import (
    DRIVE_KIND,
    FORCE,
    FRICTION_KIND,
    MU,
    MU_STATIC,
    TANGENTIAL_KIND,
    TANGENTIAL_STIFFNESS,
)
from microslip.model.drive import CONSTANT
from microslip.model.friction import COULOMB, STATIC_KINETIC
from microslip.model.switches import apply_switch
from microslip.model.system import CONTACT_GAP, FT, N_STATE, XDOT, YDOT, U, Y
from microslip.model.system import FLIGHT as FLIGHT_MODE
from microslip.model.system import X as STATE_X
from microslip.model.tangential import MINDLIN

# Grid steps kept between a window's ends and the contact switch it crosses: a lane's
# closed form is used only on pieces at least this far from δ = 0. (Measured on Hertz
# maps with flights: 0.5, the grading's own end, was 5x closer to the event method than
# 1.5, which runs more of each period on the scalar step.)
MARGIN = 0.5
PEEK_ROWS = 16  # tape rows integrated past a block, where a window may end
_SCRATCH_ROWS = 6 + WORK_ROWS  # state, trial, piece, extremum, end state, atol, work


@njit(cache=True)
def window_buffers(normal_c, ratio):
    """(resume, scratch, c_full) of a set-up: the time [s] before which its rows were
    integrated by a window (-inf: none yet), the scalar step's scratch and the
    coefficient vector of its lanes as one model (the normal law of ``normal_c``, a
    MindlinSpring of ratio λ [-], a constant force; each lane's force and friction go in
    by :func:`_lane_coefficients`)."""
    c = normal_c.copy()
    c[TANGENTIAL_KIND] = MINDLIN
    c[TANGENTIAL_STIFFNESS] = ratio
    c[DRIVE_KIND] = CONSTANT
    return np.full(1, -math.inf), np.zeros((_SCRATCH_ROWS, N_STATE)), c


@njit(cache=True, inline="always")
def integrated_ahead(window, t):
    """True for a row starting at ``t`` [s] that a window has already integrated."""
    return t < window[0][0]


@njit(cache=True)
def reset_windows(window):
    """Nothing integrated ahead (a repeated tape's next period, whose times are the first
    one's again)."""
    window[0][0] = -math.inf


@njit(cache=True, inline="always")
def on_grid(t, dt):
    """True when ``t`` [s] is a point k·dt of the fixed-step grid (kernel.next_grid_point)."""
    return t == round(t / dt) * dt


@njit(cache=True)
def lift_off_ahead(rows, r, n_rows, dt):
    """The row of a lift-off that a window must start at row ``r`` (a contact row at a
    grid point t) to cross: the first flight row after it if it starts before
    t + (1 + MARGIN) dt (the next grid point would be closer to it than MARGIN·dt),
    else -1; -2 if rows [0, ``n_rows``) end before that can be told."""
    horizon = rows[r, nt.T0] + (1.0 + MARGIN) * dt
    for j in range(r + 1, n_rows):
        if rows[j, nt.T0] >= horizon:
            return -1
        if flight_piece(nt.coefficients(rows, j)):
            return j
    return -2


@njit(cache=True)
def window_end(rows, r0, n_rows, last_touchdown, dt, final):
    """The first row after row ``r0`` where the lanes take over from a window (module
    doc): its index, ``n_rows`` if the window runs to the end of the run (``final``: the
    rows end at it), -1 if it is not in rows [0, ``n_rows``). ``last_touchdown`` [s]: the
    window's touchdown, -inf for a lift-off."""
    for r in range(r0 + 1, n_rows):
        t = rows[r, nt.T0]
        flight = flight_piece(nt.coefficients(rows, r))
        if not flight and flight_piece(nt.coefficients(rows, r - 1)):
            last_touchdown = t
        if on_grid(t, dt) and (flight or t - last_touchdown >= MARGIN * dt):
            return r
    return n_rows if final else -1


@njit(cache=True)
def _lane_coefficients(c_full, lanes, i):
    """The coefficient tuple of lane ``i``'s own model: its set-up's ``c_full``
    (:func:`window_buffers`) with its force and friction coefficients, written into
    ``c_full`` (the set-up's own scratch: no copy per lane and window)."""
    c_full[FORCE] = lanes[LANE_FORCE, i]
    c_full[MU_STATIC] = lanes[MU_S, i]
    c_full[MU] = lanes[MU_K, i]
    c_full[FRICTION_KIND] = COULOMB if lanes[MU_S, i] == lanes[MU_K, i] else STATIC_KINETIC
    return as_tuple(c_full)


@njit(cache=True)
def _window_lane(lanes, switches, flagged, i, c_full, t_a, y_a, ydot_a, landing, t_b, dt,
                 scratch):  # fmt: skip
    """Lane ``i`` from t_a to t_b [s] on the scalar step, in place: from the normal state
    (y_a [m], ẏ_a [m/s]) and the lane's own, landing first where ``landing`` (a touchdown
    at t_a, steps graded from it). Returns False if it stalled (more than
    MAX_SWITCHES_PER_STEP switches in a step), its state then left as it was."""
    s, trial, piece = scratch[0], scratch[1], scratch[2]
    extremum, s1, atol = scratch[3], scratch[4], scratch[5]
    work = scratch[6:]  # atol: unused by RK4 (zeros, as window_buffers made it)
    c = _lane_coefficients(c_full, lanes, i)
    s[Y], s[YDOT], s[STATE_X], s[XDOT] = y_a, ydot_a, lanes[X, i], lanes[V, i]
    s[U], s[FT] = lanes[X, i], lanes[FS, i]
    mode = lanes[MODE, i]
    if abs(mode) == FLIGHT_MODE:
        mode = -FLIGHT_MODE if s[XDOT] < 0.0 else FLIGHT_MODE
    graded_from = math.nan
    count = 0
    if landing:
        mode = apply_switch(CONTACT_GAP, t_a, s, mode, c)[0]
        graded_from = t_a
        count = 1
    t = t_a
    k = np.int64(math.floor(t_a / dt))
    while t < t_b:
        target, k = next_grid_point(t, 0.0, k, dt, t_b)
        mode, t, switched, stalled, graded_from = scalar_step(
            s, mode, t, target, dt, graded_from, c, s1, False, piece, trial, extremum, work,
            atol,
        )  # fmt: skip
        if stalled:
            return False
        count += switched
    switches[i] += count
    flagged[i] += 1
    lanes[X, i], lanes[V, i], lanes[FS, i] = s[STATE_X], s[XDOT], s[FT]
    lanes[MODE, i] = abs(mode) if abs(mode) == FLIGHT_MODE else mode
    return True


@njit(cache=True)
def step_lane(window, lanes, switches, flagged, i, rows, r, dt):
    """Lane ``i`` through tape row ``r`` of ``rows`` on the scalar step, in place, where
    its closed form stalled (an exact tie of stick and slip); ``window`` as for
    :func:`cross`. A lane still in flight lands at the row's start (a contact row after
    a flight starts at the touchdown). Returns False if it stalls there too."""
    t0 = rows[r, nt.T0]
    landing = abs(lanes[MODE, i]) == FLIGHT_MODE
    return _window_lane(
        lanes, switches, flagged, i, window[2], t0, rows[r, nt.Y_START],
        rows[r, nt.YDOT_START], landing, t0 + rows[r, nt.H], dt, window[1],
    )  # fmt: skip


@njit(cache=True)
def run_window(lanes, switches, flagged, c_full, t_a, y_a, ydot_a, landing, t_b, dt,
               scratch):  # fmt: skip
    """Every lane through a window from t_a to t_b [s] (:func:`_window_lane`); a lane that
    stalls is handed back alone (NaN from here on, as
    :mod:`~microslip.integrators.mindlin_lanes` does)."""
    for i in range(lanes.shape[1]):
        if lanes[X, i] != lanes[X, i]:
            continue  # handed back already
        if not _window_lane(lanes, switches, flagged, i, c_full, t_a, y_a, ydot_a, landing,
                            t_b, dt, scratch):  # fmt: skip
            lanes[X, i], lanes[V, i], lanes[FS, i] = math.nan, math.nan, math.nan


@njit(cache=True)
def cross(window, lanes, switches, flagged, rows, r, r_switch, n_rows, final, dt):
    """The lanes from the start of row ``r`` of ``rows`` through the contact switch at
    the start of row ``r_switch`` (a lift-off where that row is in flight, else a
    touchdown: then ``r_switch`` = ``r``) by a window (module doc), in place; ``window``
    from :func:`window_buffers`. Returns (done, flying): done False when the window does
    not end within rows [0, ``n_rows``) (the caller hands the set-up back); flying where
    the lanes fly on from its end (a lane that the scalar step kept in contact a
    rounding longer lifts off there, as the lanes' flight does: f = 0)."""
    resume, scratch, c_full = window
    landing = r_switch == r and not flight_piece(nt.coefficients(rows, r))
    last_touchdown = rows[r, nt.T0] if landing else -math.inf
    r_b = window_end(rows, r_switch, n_rows, last_touchdown, dt, final)
    if r_b < 0:
        return False, False
    if r_b < n_rows:
        t_b = rows[r_b, nt.T0]
    else:
        t_b = rows[n_rows - 1, nt.T0] + rows[n_rows - 1, nt.H]
    run_window(lanes, switches, flagged, c_full, rows[r, nt.T0], rows[r, nt.Y_START],
               rows[r, nt.YDOT_START], landing, t_b, dt, scratch)  # fmt: skip
    resume[0] = t_b
    flying = r_b < n_rows and flight_piece(nt.coefficients(rows, r_b))
    if flying:
        lift_off(lanes, lanes.shape[1])
    return True, flying
