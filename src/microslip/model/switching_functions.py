"""The switching functions of the composed system: when its mode, or the smoothness of
its right-hand side, changes (docs/design.md, "state layout").

:mod:`microslip.model.system` holds the state, the mode and the right-hand side;
:mod:`microslip.model.switches` what follows a switch. The integrators' located
switching (:mod:`microslip.integrators.switching`) evaluates these, for the switching
function ``which`` of :mod:`~microslip.model.system` (CONTACT_GAP, SEPARATION,
STICK_MARGIN, SLIDING_SPEED):

* :func:`switching_value` and :func:`switching_rate`: its value (units of its law) and
  its time derivative along the motion in a mode;
* :func:`switch_active`: whether it can change anything in a mode; :func:`inside` and
  :func:`holds_only_inside`: which side of it the mode lives on;
* :func:`separation_value`, :func:`separation_rate`: N_raw [N] with the elastic part
  floored, and its rate, which the normal tape shares; :func:`contact_side_rate`, the
  rate seen from inside the contact at a loss of contact; :func:`in_contact`.
"""

from __future__ import annotations

import math

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.coefficients import GRAVITY, STATIC_DEFLECTION
from microslip.model.contact import contact_side_stiffness, elastic_force, elastic_stiffness
from microslip.model.damping import can_separate_in_overlap, damped_force, damped_force_partials
from microslip.model.drive import drive_force, drive_force_rate
from microslip.model.excitation import is_prescribed
from microslip.model.friction import friction_limit, friction_limit_rate
from microslip.model.normal import gap
from microslip.model.system import (
    CONTACT_GAP,
    FLIGHT,
    FT,
    SEPARATION,
    SLIDING_SPEED,
    STICK_MARGIN,
    XDOT,
    YDOT,
    U,
    X,
    Y,
    airborne,
    body_acceleration,
    contact_point_rates,
    derivatives,
    normal_acceleration_call,
    normal_force_call,
    normal_force_rate_call,
    sign,
    tangential_mode,
)
from microslip.model.tangential import is_compliant, stiffness_rough_at_touch

__all__ = [
    "contact_side_rate",
    "graded_after",
    "graded_switch",
    "holds_only_inside",
    "in_contact",
    "inside",
    "separation_rate",
    "separation_value",
    "switch_active",
    "switching_rate",
    "switching_value",
]


# Floor [N] of the elastic force in the separation function: out of overlap (δ <= 0)
# the function keeps the sign that N_raw has as δ -> 0+ (Kelvin–Voigt: sgn δ̇;
# Hunt–Crossley: sgn(1 + c δ̇/(m g))), so it is continuous at δ = 0 and flips only
# where the body can actually separate or re-touch inside the overlap.
_ELASTIC_FLOOR = 1e-200


@njit(cache=True, error_model="numpy")
def _contact_point_rates_call(t, s, mode, normal, c):
    """:func:`~microslip.model.system.contact_point_rates` behind a compiled call (four
    copies of it, each with the tangential and friction laws inside, made
    switching_rate's compile seconds longer)."""
    return contact_point_rates(t, s, mode, normal, c)


@njit(cache=True, error_model="numpy")
def _derivatives_call(t, s, mode, c):
    """:func:`~microslip.model.system.derivatives` behind a compiled call (``s`` a state
    tuple)."""
    return derivatives(t, s, mode, c)


@njit(cache=True)
def separation_value(delta, delta_rate, c):
    """SEPARATION's value [N]: N_raw at (δ [m], δ̇ [m/s]) with the elastic part floored
    (sign-floored, so that it is > 0 in contact)."""
    elastic = elastic_force(delta, c)
    if elastic < _ELASTIC_FLOOR:
        elastic = _ELASTIC_FLOOR
    return damped_force(elastic, delta_rate, c)


@njit(cache=True)
def _rate_with_stiffness(delta, stiffness, delta_rate, delta_accel, c):
    """dN_raw/dt [N/s] along the motion, the elastic part floored, given δ [m], the
    elastic stiffness [N/m], δ̇ [m/s] and δ̈ [m/s^2]."""
    elastic = elastic_force(delta, c)
    if elastic < _ELASTIC_FLOOR:
        elastic = _ELASTIC_FLOOR
    d_delta, d_rate = damped_force_partials(elastic, stiffness, delta_rate, c)
    return d_delta * delta_rate + d_rate * delta_accel


@njit(cache=True)
def separation_rate(delta, delta_rate, delta_accel, c):
    """SEPARATION's rate [N/s] along the motion, given δ [m], δ̇ [m/s], δ̈ [m/s^2]."""
    return _rate_with_stiffness(delta, elastic_stiffness(delta, c), delta_rate, delta_accel, c)


@njit(cache=True)
def contact_side_rate(delta, delta_rate, delta_accel, c):
    """dN_raw/dt [N/s] seen from inside the contact: :func:`separation_rate`, with the
    stiffness's limit as δ -> 0+ where δ <= 0
    (:func:`~microslip.model.contact.contact_side_stiffness`): at the end of a piece of
    contact that a loss of contact closes (m2 = 1: N leaves with slope S c_n δ̇)."""
    return _rate_with_stiffness(delta, contact_side_stiffness(delta, c), delta_rate, delta_accel, c)


@njit(cache=True)
def switch_active(which, mode, c):
    """True when switching function ``which`` can change anything in ``mode``."""
    if which == CONTACT_GAP:
        return True
    if which == SEPARATION:
        return can_separate_in_overlap(c)
    direction = tangential_mode(mode)
    if which == STICK_MARGIN:
        return direction == 0.0
    return direction == 1.0 or direction == -1.0


@njit(cache=True)
def graded_switch(which, c):
    """True when a fixed step of full length is too coarse next to a flip of switching
    function ``which``: the contact gap of a Mindlin contact whose stiffness has a
    corner there (:func:`~microslip.model.tangential.stiffness_rough_at_touch`). A
    fixed-step integrator then reaches and leaves the flip by graded steps
    (docs/theory/numerics.md, "Order at a touchdown"). The contact law's own corner
    (N ∝ δ^m2) is left to the full steps: graded steps next to it did not lower the
    error of y, which the full steps just past them set."""
    return which == CONTACT_GAP and stiffness_rough_at_touch(c)


@njit(cache=True)
def graded_after(which, mode, c):
    """True when a fixed-step integrator leaves a flip of switching function ``which``
    by graded steps (docs/theory/numerics.md, "Order at a touchdown"), ``mode`` the mode
    the flip entered: a :func:`graded_switch` flip into contact, a touchdown. Past a
    lift-off the point flies (|mode| = FLIGHT) on a smooth right-hand side (no contact
    law acts in flight): graded steps there bought nothing, and cost ~8 steps a lift-off
    on a Hertz Mindlin contact."""
    return graded_switch(which, c) and abs(mode) != FLIGHT


@njit(cache=True)
def inside(which, value):
    """True on the "inside" side of switching function ``which`` (contact, stick holds,
    sliding on). The stick margin may be exactly 0 while stick holds (|F| <= μN, 2.2);
    δ = 0 and N_raw = 0 count as flight."""
    if which == STICK_MARGIN:
        return value >= 0.0
    return value > 0.0


@njit(cache=True)
def holds_only_inside(which):
    """True when the mode that activates ``which`` exists only on its inside (stick
    margin, sliding speed): a value on the boundary at a step start is a mode entered
    right there (a release: the speed starts at exactly 0 and must first rise).
    False for the two-sided contact functions (flight and contact are both states)."""
    return which == STICK_MARGIN or which == SLIDING_SPEED


@njit(cache=True)
def _held_force(t, s, c):
    """The force the interface holds in stick [N]: the drive F(t, x) on a rigid
    contact, the spring force f on a compliant one."""
    if is_compliant(c):
        return s[FT]
    return drive_force(t, s[X], c)


@njit(cache=True)
def _interface_velocity(t, s, mode, c):
    """Velocity [m/s] of the interface in ``mode``: ẋ (rigid) or u̇ (compliant)."""
    if is_compliant(c):
        normal = normal_force_call(t, s[Y], s[YDOT], c)
        return _contact_point_rates_call(t, s, mode, normal, c)[0]
    return s[XDOT]


# Step [in units of sqrt(y0/g), a time scale of the normal motion] of the central
# difference of the contact point's velocity along the motion: its exact rate needs
# d²N/dt², which no law provides. The difference is used only for Newton steps and the
# extremum screening of the switching logic, which a relative error ~1e-9 does not upset.
_RATE_STEP = 1e-7


@njit(cache=True)
def _contact_point_acceleration(t, s, mode, c):
    """ü [m/s^2] of a sliding compliant contact point, by a central difference along
    the flow of :func:`derivatives` (see ``_RATE_STEP``)."""
    eps = _RATE_STEP * math.sqrt(c[STATIC_DEFLECTION] / c[GRAVITY])
    d = _derivatives_call(t, s, mode, c)
    plus = (
        s[Y] + eps * d[0], s[YDOT] + eps * d[1], s[X] + eps * d[2],
        s[XDOT] + eps * d[3], s[U] + eps * d[4], s[FT] + eps * d[5],
    )  # fmt: skip
    minus = (
        s[Y] - eps * d[0], s[YDOT] - eps * d[1], s[X] - eps * d[2],
        s[XDOT] - eps * d[3], s[U] - eps * d[4], s[FT] - eps * d[5],
    )  # fmt: skip
    ahead = _contact_point_rates_call(
        t + eps, plus, mode, normal_force_call(t + eps, plus[0], plus[1], c), c
    )
    behind = _contact_point_rates_call(
        t - eps, minus, mode, normal_force_call(t - eps, minus[0], minus[1], c), c
    )
    return (ahead[0] - behind[0]) / (2.0 * eps)


# error_model="numpy": no ZeroDivisionError branch (the only division is by the mass),
# which would keep numba from dropping the reference counts of its callers' arrays.
@njit(cache=True, error_model="numpy")
def switching_value(which, t, s, mode, c):
    """Value of switching function ``which`` at (t, s) in ``mode`` (units of its law);
    ``s`` a state tuple or array."""
    y = s[Y]
    yd = s[YDOT]
    if which == CONTACT_GAP:
        return gap(t, y, yd, c)[0]
    if which == SEPARATION:
        delta, delta_rate, _ = gap(t, y, yd, c)
        return separation_value(delta, delta_rate, c)
    if which == STICK_MARGIN:
        return friction_limit(normal_force_call(t, y, yd, c), c) - abs(_held_force(t, s, c))
    direction = tangential_mode(mode)
    return direction * _interface_velocity(t, s, direction, c)


@njit(cache=True, error_model="numpy")
def switching_rate(which, t, s, mode, c):
    """Time derivative of :func:`switching_value` along the motion in ``mode``."""
    y = s[Y]
    yd = s[YDOT]
    if which == CONTACT_GAP:
        return gap(t, y, yd, c)[1]
    if which == SEPARATION:
        delta, delta_rate, third = gap(t, y, yd, c)
        delta_accel = third if is_prescribed(c) else normal_acceleration_call(t, y, yd, c) - third
        return separation_rate(delta, delta_rate, delta_accel, c)
    if which == STICK_MARGIN:
        rate = friction_limit_rate(normal_force_rate_call(t, y, yd, c), c)
        if is_compliant(c):
            normal = normal_force_call(t, y, yd, c)
            held_rate = _contact_point_rates_call(t, s, 0.0, normal, c)[1]
        else:
            held_rate = drive_force_rate(t, s[X], s[XDOT], c)
        return rate - sign(_held_force(t, s, c)) * held_rate
    if is_compliant(c) and normal_force_call(t, y, yd, c) > 0.0:
        return mode * _contact_point_acceleration(t, s, mode, c)
    normal = 0.0 if airborne(mode) else normal_force_call(t, y, yd, c)
    direction = tangential_mode(mode)
    return direction * body_acceleration(normal, t, s, direction, c)


@njit(cache=True)
def in_contact(t, s, c):
    """True in contact: δ > 0 and N_raw > 0 (the separation function's sign)."""
    delta, delta_rate, _ = gap(t, s[Y], s[YDOT], c)
    return delta > 0.0 and separation_value(delta, delta_rate, c) > 0.0
