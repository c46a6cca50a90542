"""Located switching: stick ↔ slip and contact ↔ flight instants inside a step.

The friction mode (sliding direction, or stick) is held fixed over a step. After each
trial step the switching functions are checked; when one changes sign its root is found
by re-stepping the same method from the step start over a fraction θ of the step
(Illinois false position), so the switching instant carries the method's own accuracy
and a fixed-step method keeps its order (docs/model-facts.md, "Numerical pitfalls").

A switching function can cross zero twice inside one step and show no sign change at
the step ends. For the laws here the relevant extrema are known: the contact gap y and
the stick margin μ|R(y)| - |F| are extremal where ẏ = 0, and the sliding speed s·ẋ is
extremal where s·ẍ = 0. Those interior points are located and checked as well.
"""

from __future__ import annotations

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.integrators.methods import advance
from microslip.model.coefficients import MASS
from microslip.model.contact import normal_acceleration
from microslip.model.friction import (
    drive_force,
    drive_force_rate,
    friction_limit,
    friction_limit_rate,
    slip_acceleration,
)

# Switching functions.
CONTACT_GAP = 0  # y: > 0 in contact
STICK_MARGIN = 1  # μ|R| - |F|: >= 0 while stick can hold
SLIDING_SPEED = 2  # s·ẋ: > 0 while sliding in direction s
TURNING = 3  # ẏ
NET_FORCE = 4  # s·ẍ

# Event kinds recorded in the output.
NO_EVENT = 0
CONTACT_LOST = 1
CONTACT_MADE = 2
SLIP_START = 3
STICK_START = 4
SLIP_REVERSAL = 5
EVENT_NAMES = ("none", "contact_lost", "contact_made", "slip_start", "stick_start", "reversal")

_EPS = 2.220446049250313e-16


@njit(cache=True, inline="always")
def switching_value(which, s, t, direction, c):
    y, yd, _x, xd = s
    if which == CONTACT_GAP:
        return y
    if which == STICK_MARGIN:
        return friction_limit(y, yd, t, c) - abs(drive_force(t, c))
    if which == SLIDING_SPEED:
        return direction * xd
    if which == TURNING:
        return yd
    return direction * slip_acceleration(y, yd, t, direction, c)


@njit(cache=True, inline="always")
def switching_rate(which, s, t, direction, c):
    """Time derivative of :func:`switching_value` along the motion (for Newton steps)."""
    y, yd, _x, _xd = s
    if which == CONTACT_GAP:
        return yd
    if which == TURNING:
        return normal_acceleration(y, yd, c)
    if which == SLIDING_SPEED:
        return direction * slip_acceleration(y, yd, t, direction, c)
    force = drive_force(t, c)
    force_rate = drive_force_rate(t, c)
    if which == STICK_MARGIN:
        sign_f = 1.0 if force > 0.0 else (-1.0 if force < 0.0 else 0.0)
        return friction_limit_rate(y, yd, t, c) - sign_f * force_rate
    return (direction * force_rate - friction_limit_rate(y, yd, t, c)) / c[MASS]


@njit(cache=True, inline="always")
def _inside(which, value):
    # The stick margin may be exactly zero while stick holds (|F| <= μ|R|, eq. 2.2).
    if which == STICK_MARGIN:
        return value >= 0.0
    return value > 0.0


@njit(cache=True)
def locate(which, method, s0, t, h, direction, c, rtol, atol, lo, hi, f_lo, f_hi):
    """Fraction θ in (lo, hi] of the step where switching function ``which`` flips.

    Each trial state is a step of length θh from ``s0``. Newton steps use the switching
    function's rate along the motion; the bracket [lo, hi] is kept, and a trial outside
    it falls back to Illinois false position. Returns the first θ known to lie past the
    flip, to within a few ulps of t.
    """
    side_lo = _inside(which, f_lo)
    tolerance = 4.0 * _EPS * (abs(t) + abs(h)) / abs(h)
    retained = 0
    theta = hi - f_hi * (hi - lo) / (f_hi - f_lo) if f_hi != f_lo else 0.5 * (lo + hi)
    for _ in range(200):
        if hi - lo <= tolerance:
            break
        if not (lo < theta < hi):
            theta = 0.5 * (lo + hi)
        s_mid, _err = advance(method, s0, t, theta * h, direction, c, rtol, atol)
        t_mid = t + theta * h
        f_mid = switching_value(which, s_mid, t_mid, direction, c)
        if _inside(which, f_mid) == side_lo:
            lo, f_lo = theta, f_mid
            if retained == -1:
                f_hi *= 0.5
            retained = -1
        else:
            hi, f_hi = theta, f_mid
            if retained == 1:
                f_lo *= 0.5
            retained = 1
        slope = switching_rate(which, s_mid, t_mid, direction, c) * h
        step = f_mid / slope if slope != 0.0 else 0.0
        if slope != 0.0 and abs(step) <= 0.25 * tolerance:
            # Converged: probe just past the root to close the bracket from the far side.
            theta = theta - step + (0.5 * tolerance if retained == -1 else -0.5 * tolerance)
            continue
        newton = theta - step
        if slope != 0.0 and lo < newton < hi:
            theta = newton
        elif f_hi != f_lo:
            theta = hi - f_hi * (hi - lo) / (f_hi - f_lo)
        else:
            theta = 0.5 * (lo + hi)
    return hi


@njit(cache=True)
def _interior_extremum(extremum_fn, method, s0, s1, t, h, direction, c, rtol, atol):
    """θ where ``extremum_fn`` changes sign inside the step, or -1 if it does not."""
    f0 = switching_value(extremum_fn, s0, t, direction, c)
    f1 = switching_value(extremum_fn, s1, t + h, direction, c)
    if f0 == 0.0 or (f0 > 0.0) == (f1 > 0.0):
        return -1.0  # no interior extremum (one at the step start is not interior)
    return locate(extremum_fn, method, s0, t, h, direction, c, rtol, atol, 0.0, 1.0, f0, f1)


@njit(cache=True, inline="always")
def _lowest_height(s0, s1, h, c):
    """A lower bound [m] of y over a step that contains the top of the normal motion.

    Near the top ÿ > 0, so ẏ is monotone and y dips below its lower end value by at most
    h·max|ẏ|; the bound doubles that allowance and adds an h²|ÿ| term for safety.
    """
    a0 = normal_acceleration(s0[0], s0[1], c)
    a1 = normal_acceleration(s1[0], s1[1], c)
    band = h * (abs(s0[1]) + abs(s1[1])) + h * h * (abs(a0) + abs(a1))
    return min(s0[0], s1[0]) - band


@njit(cache=True)
def _first_flip(which, method, s0, s1, t, h, direction, c, rtol, atol):
    """θ of the first flip of the gap y or the stick margin in the step (or 2.0 if none).

    Both are monotone in y, so they can flip twice inside one step only around a turning
    point of y (ẏ = 0): the top (a minimum of both) or, in flight, a bottom. Such a
    turning point is located and checked only when the cheap bound of
    :func:`_lowest_height` does not already exclude a double crossing.
    """
    f0 = switching_value(which, s0, t, direction, c)
    f1 = switching_value(which, s1, t + h, direction, c)
    inside0 = _inside(which, f0)
    if _inside(which, f1) != inside0:  # one turning point at most: a single crossing
        return locate(which, method, s0, t, h, direction, c, rtol, atol, 0.0, 1.0, f0, f1)
    top = s0[1] < 0.0 <= s1[1]
    bottom = s0[1] > 0.0 >= s1[1]
    if top:
        low = (_lowest_height(s0, s1, h, c), 0.0, s0[2], s0[3])
        if _inside(which, switching_value(which, low, t, direction, c)) == inside0:
            return 2.0
    elif not (bottom and which == CONTACT_GAP and not inside0):
        return 2.0  # a bottom is a maximum: it matters only for contact seen from flight
    theta_x = _interior_extremum(TURNING, method, s0, s1, t, h, direction, c, rtol, atol)
    if not (0.0 < theta_x < 1.0):
        return 2.0
    sx, _err = advance(method, s0, t, theta_x * h, direction, c, rtol, atol)
    fx = switching_value(which, sx, t + theta_x * h, direction, c)
    if _inside(which, fx) != inside0:
        return locate(which, method, s0, t, h, direction, c, rtol, atol, 0.0, theta_x, f0, fx)
    return 2.0


@njit(cache=True)
def _first_stop(method, s0, s1, t, h, direction, c, rtol, atol):
    """θ where the sliding speed s·ẋ first returns to zero in the step (or 2.0).

    s·ẍ = (s F - μ|R(y)|)/m is monotone in y, so the speed has at most one interior
    extremum per step. Right after a release (s·ẋ = 0, net force >= 0) the speed first
    rises: it can stop only after its maximum. While sliding, a minimum inside the step
    can touch zero; it is located only when the bound h(|ẍ0| + |ẍ1|) on the dip allows.
    """
    v0 = switching_value(SLIDING_SPEED, s0, t, direction, c)
    v1 = switching_value(SLIDING_SPEED, s1, t + h, direction, c)
    a0 = switching_value(NET_FORCE, s0, t, direction, c)
    a1 = switching_value(NET_FORCE, s1, t + h, direction, c)
    if v0 > 0.0:
        if v1 <= 0.0:
            return locate(
                SLIDING_SPEED, method, s0, t, h, direction, c, rtol, atol, 0.0, 1.0, v0, v1
            )
        if not (a0 < 0.0 < a1) or min(v0, v1) > h * (abs(a0) + abs(a1)):
            return 2.0
    elif a1 > 0.0:
        return 2.0  # just released and still accelerating at the step end
    # The interior extremum: after a release the maximum (its net force at θ = 0 is
    # zero up to rounding, so it is taken as positive), else the minimum.
    a_start = abs(a0) if v0 <= 0.0 else a0
    if a_start == 0.0:
        a_start = 1e-300
    theta_x = locate(NET_FORCE, method, s0, t, h, direction, c, rtol, atol, 0.0, 1.0, a_start, a1)
    if not (0.0 < theta_x < 1.0):
        return 2.0
    sx, _err = advance(method, s0, t, theta_x * h, direction, c, rtol, atol)
    vx = switching_value(SLIDING_SPEED, sx, t + theta_x * h, direction, c)
    if v0 > 0.0 and vx <= 0.0:
        return locate(
            SLIDING_SPEED, method, s0, t, h, direction, c, rtol, atol, 0.0, theta_x, v0, vx
        )
    if v0 <= 0.0 and vx > 0.0 and v1 <= 0.0:
        return locate(
            SLIDING_SPEED, method, s0, t, h, direction, c, rtol, atol, theta_x, 1.0, vx, v1
        )
    return 2.0


@njit(cache=True)
def first_switch(method, s0, s1, t, h, direction, c, rtol, atol):
    """Earliest switching inside a trial step from (t, s0) to (t + h, s1).

    Returns (θ, which) with θ in (0, 1], or (2.0, -1) when the step holds no switch.
    """
    # y = 0 counts as flight, so the contact state is always (y > 0) at the step start.
    best = _first_flip(CONTACT_GAP, method, s0, s1, t, h, direction, c, rtol, atol)
    which = CONTACT_GAP if best <= 1.0 else -1
    if direction == 0.0:
        theta = _first_flip(STICK_MARGIN, method, s0, s1, t, h, direction, c, rtol, atol)
        if theta < best:
            best, which = theta, STICK_MARGIN
    else:
        theta = _first_stop(method, s0, s1, t, h, direction, c, rtol, atol)
        if theta < best:
            best, which = theta, SLIDING_SPEED
    return best, which


@njit(cache=True, inline="always")
def sign(value):
    if value > 0.0:
        return 1.0
    if value < 0.0:
        return -1.0
    return 0.0


@njit(cache=True)
def initial_direction(s, t, c):
    """Friction mode at a given state: sgn ẋ when sliding; stick iff |F| <= μ|R| (2.2)."""
    if s[3] != 0.0:
        return sign(s[3])
    force = drive_force(t, c)
    if abs(force) <= friction_limit(s[0], s[1], t, c):
        return 0.0
    return sign(force)


@njit(cache=True)
def apply_switch(which, s, t, direction, c):
    """New (state, direction, event kind) after switching function ``which`` flipped."""
    if which == CONTACT_GAP:
        return s, direction, CONTACT_MADE if s[0] > 0.0 else CONTACT_LOST
    if which == STICK_MARGIN:
        return s, sign(drive_force(t, c)), SLIP_START
    # The slider has come to rest: ẋ = 0 exactly, then stick or slide on (2.2).
    rest = (s[0], s[1], s[2], 0.0)
    new_direction = initial_direction(rest, t, c)
    if new_direction == 0.0:
        return rest, 0.0, STICK_START
    if new_direction == direction:
        return rest, new_direction, SLIP_START
    return rest, new_direction, SLIP_REVERSAL
