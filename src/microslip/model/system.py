"""The composed system that the integrators advance (docs/design.md, "state layout").

This is the only module that knows what the state variables mean. The integrators see

* a state ``s``: a float64 array of :data:`N_STATE` values, here
  s = [y [m], ẏ [m/s], x [m], ẋ [m/s], u [m], f [N]]: the body's normal and tangential
  motion (y > 0 penetration, eq. 2.3; with a prescribed penetration y, ẏ carry δ, δ̇),
  the contact point u and the tangential spring force f of a compliant tangential
  contact (both constant with a rigid one: the friction then acts on the body);
* an opaque ``mode`` (a float): the slip direction of the interface, ±1, or 0 for stick.
  The interface is the body with a rigid tangential contact (sgn ẋ, eq. 2.2), the
  contact point with a compliant one (sgn u̇); a compliant contact point in flight has
  mode ±2 (its flight law, f = 0 and u̇ = ẋ, until the touchdown is applied: the law
  never changes inside a trial step). A rigid contact of a damped model carries its
  flight as the mode + 4 (3, 4, 5). In flight the normal force is 0 over the whole step
  (:func:`derivatives`), whatever the stage states: the contact is held, not read off
  each stage, so a force jump at touchdown (Kelvin–Voigt: c δ̇) never enters the stages
  of the step that locates it;
* the coefficient vector ``c`` (:mod:`microslip.model.coefficients`);

and call :func:`derivatives` within a mode, and the switching functions, which say when
the mode or the smoothness of the right-hand side changes (the state goes to them as a
tuple, :func:`state_tuple`, or as an array):

    CONTACT_GAP     δ                      > 0 in contact (touchdown / lift-off at δ = 0)
    SEPARATION      N_raw (sign-floored)   > 0 in contact; only with damping, which can
                                           make N_raw <= 0 while δ > 0
    STICK_MARGIN    μ_s N - |F| (rigid),   >= 0 while stick holds (eq. 2.2); stick only
                    μ_s N - |f| (compliant)
    SLIDING_SPEED   mode · ẋ (rigid),      > 0 while sliding in direction ``mode``
                    mode · u̇ (compliant)

The normal law is :mod:`microslip.model.normal` (contact law + damping + excitation),
the friction law :mod:`microslip.model.friction`, the drive :mod:`microslip.model.drive`,
the tangential contact :mod:`microslip.model.tangential`; the compliant contact point is
docs/theory/friction_reduction.md.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.coefficients import (
    DAMPING_KIND,
    DRIVE_KIND,
    EXCITATION_KIND,
    FRICTION_KIND,
    GRAVITY,
    MASS,
    STATIC_DEFLECTION,
    TANGENTIAL_KIND,
)
from microslip.model.contact import elastic_force, elastic_stiffness
from microslip.model.damping import can_separate_in_overlap, damped_force, damped_force_partials
from microslip.model.drive import drive_force, drive_force_rate, is_kinematic
from microslip.model.excitation import is_prescribed
from microslip.model.friction import friction_limit, friction_limit_rate, kinetic_coefficient
from microslip.model.normal import (
    acceleration_from_force,
    gap,
    normal_acceleration,
    normal_force,
    normal_force_rate,
    raw_normal_force,
)
from microslip.model.tangential import is_compliant, tangential_stiffness

__all__ = [
    "CONTACT_GAP",
    "EVENT_NAMES",
    "N_STATE",
    "N_SWITCHES",
    "SEPARATION",
    "SLIDING_SPEED",
    "STICK_MARGIN",
    "airborne",
    "apply_switch",
    "derivatives",
    "full_states",
    "holds_only_inside",
    "in_contact",
    "initial_mode",
    "inside",
    "interface_samples",
    "is_paper_model",
    "normal_acceleration_call",
    "normal_force_call",
    "normal_force_rate_call",
    "normal_samples",
    "separation_rate",
    "separation_value",
    "slip_directions",
    "state_array",
    "state_tuple",
    "switch_active",
    "switching_rate",
    "switching_value",
]

# State layout. Only this module (and the paper-model fast pass of the batched kernel,
# which imports these names) indexes the state by meaning.
N_STATE = 6
Y, YDOT, X, XDOT, U, FT = 0, 1, 2, 3, 4, 5

# Switching functions. NumPy integers, not Python ones: numba types a module-level int
# passed to a jitted function as a literal and compiles the callee once per value
# (docs/design.md, "The compiled form").
CONTACT_GAP = np.int64(0)
SEPARATION = np.int64(1)
STICK_MARGIN = np.int64(2)
SLIDING_SPEED = np.int64(3)
N_SWITCHES = 4

# Event kinds recorded in the output (codes kept stable: files and the CLI use them).
NO_EVENT = 0
CONTACT_LOST = 1
CONTACT_MADE = 2
SLIP_START = 3
STICK_START = 4
SLIP_REVERSAL = 5
EVENT_NAMES = ("none", "contact_lost", "contact_made", "slip_start", "stick_start", "reversal")

# Floor [N] of the elastic force in the separation function: out of overlap (δ <= 0)
# the function keeps the sign that N_raw has as δ -> 0+ (Kelvin–Voigt: sgn δ̇;
# Hunt–Crossley: sgn(1 + c δ̇/(m g))), so it is continuous at δ = 0 and flips only
# where the body can actually separate or re-touch inside the overlap.
_ELASTIC_FLOOR = 1e-200

FLIGHT = 2.0  # |mode| of a compliant contact point in flight (its law until touchdown)
# Added to the mode (0, ±1) of a rigid contact in flight when the model is damped. The
# undamped laws are continuous at touchdown (N = S c_n δ^m2 -> 0), so there the stage
# states decide, as in the paper's scheme and its vectorised pass.
_AIRBORNE = 4.0
_FLAGGED_ABOVE = 2.5  # modes above it carry the flag (3, 4, 5); every other one is < 2.5


@njit(cache=True, inline="always")
def _flight_flag(c):
    """What a rigid contact adds to its mode in flight: _AIRBORNE for a damped model, 0
    for an undamped one (the stage states decide there, see _AIRBORNE)."""
    return _AIRBORNE if can_separate_in_overlap(c) else 0.0


@njit(cache=True, inline="always")
def _tangential_mode(mode):
    """The interface part of ``mode``: 0 (stick), ±1 (slip), ±2 (compliant flight)."""
    return mode - _AIRBORNE if mode > _FLAGGED_ABOVE else mode


@njit(cache=True, inline="always")
def airborne(mode):
    """True when ``mode`` holds the body out of contact (N = 0 over the step)."""
    return mode > _FLAGGED_ABOVE or abs(mode) == FLIGHT


def slip_directions(modes: np.ndarray) -> np.ndarray:
    """The slip direction (-1, 0 = stick, +1) of recorded modes: a compliant contact
    point in flight (±2) gives ±1, a rigid contact in flight its tangential mode."""
    modes = np.asarray(modes, dtype=float)
    return np.sign(np.where(modes > _FLAGGED_ABOVE, modes - _AIRBORNE, modes))


@njit(cache=True, inline="always")
def sign(value):
    """-1, 0 or +1."""
    if value > 0.0:
        return 1.0
    if value < 0.0:
        return -1.0
    return 0.0


@njit(cache=True, inline="always")
def state_tuple(s):
    """The state array ``s`` as a tuple of its :data:`N_STATE` values.

    The laws below take the state as a tuple (or an array): a tuple goes by value
    through compiled calls, while an array argument is reference-counted (atomic
    operations) at every call, which costs more than the laws themselves.
    """
    return (s[Y], s[YDOT], s[X], s[XDOT], s[U], s[FT])


@njit(cache=True, inline="always")
def is_paper_model(c):
    """True for the paper's composition: no damping, free normal vibration, rigid
    tangential contact, Coulomb friction, constant force."""
    return (
        c[DAMPING_KIND] == 0.0
        and c[EXCITATION_KIND] == 0.0
        and c[TANGENTIAL_KIND] == 0.0
        and c[FRICTION_KIND] == 0.0
        and c[DRIVE_KIND] == 0.0
    )


# Compile boundaries. The switching functions evaluate the normal force a dozen times
# over; copying each evaluation (the contact, damping and excitation laws inside) into
# numba's IR made one compile of switching_rate take over a minute. They call these
# compiled functions instead, each of which inlines the laws once. The arguments are
# scalars and the coefficient tuple, so a call costs no reference counting, and the values
# are the same bits. The right-hand side (derivatives) keeps the laws inlined: it is the
# steps' hot loop (docs/design.md, "The compiled form").
@njit(cache=True, error_model="numpy")
def normal_force_call(t, y, ydot, c):
    """:func:`~microslip.model.normal.normal_force` [N] behind a compiled call."""
    return normal_force(t, y, ydot, c)


@njit(cache=True, error_model="numpy")
def normal_force_rate_call(t, y, ydot, c):
    """:func:`~microslip.model.normal.normal_force_rate` [N/s] behind a compiled call."""
    return normal_force_rate(t, y, ydot, c)


@njit(cache=True, error_model="numpy")
def normal_acceleration_call(t, y, ydot, c):
    """:func:`~microslip.model.normal.normal_acceleration` [m/s^2] behind a compiled call."""
    return normal_acceleration(t, y, ydot, c)


@njit(cache=True, inline="always")
def _body_slip_acceleration(normal, t, s, mode, c):
    """ẍ [m/s^2] of a body on a rigid contact sliding in ``mode`` = sgn ẋ (eqs. 2.2,
    2.5): m ẍ = F(t, x) - μ(|ẋ|) N sgn ẋ; 0 in stick (mode 0) and with the kinematic
    drive."""
    direction = _tangential_mode(mode)
    if direction == 0.0 or is_kinematic(c):
        return 0.0
    friction = kinetic_coefficient(s[XDOT], c) * normal
    return (drive_force(t, s[X], c) - direction * friction) / c[MASS]


@njit(cache=True, inline="always")
def _contact_point_rates(t, s, mode, normal, c):
    """(u̇ [m/s], ḟ [N/s]) of the compliant contact point.

    Flight (N = 0): the spring is relaxed and follows the body (u̇ = ẋ, ḟ = 0). Stick:
    u̇ = 0, ḟ = k_t ẋ (the incremental law, k_t = k_t(δ) for Mindlin). Slip in ``mode``:
    f = μ_k N mode stays on the limit, ḟ = μ_k Ṅ mode, and the spring's extension
    x - u follows it, u̇ = ẋ - ḟ / k_t.
    """
    xdot = s[XDOT]
    if normal <= 0.0 or abs(mode) == FLIGHT:
        return xdot, 0.0
    y = s[Y]
    ydot = s[YDOT]
    stiffness = tangential_stiffness(gap(t, y, ydot, c)[0], c)
    if mode == 0.0:
        return 0.0, stiffness * xdot
    force_rate = mode * kinetic_coefficient(0.0, c) * normal_force_rate_call(t, y, ydot, c)
    if stiffness <= 0.0:
        return xdot, force_rate
    return xdot - force_rate / stiffness, force_rate


@njit(cache=True, error_model="numpy")
def _contact_point_rates_call(t, s, mode, normal, c):
    """:func:`_contact_point_rates` behind a compiled call, for the switching functions
    (four copies of it, each with the tangential and friction laws inside, made
    switching_rate's compile seconds longer)."""
    return _contact_point_rates(t, s, mode, normal, c)


@njit(cache=True, inline="always")
def _body_acceleration(normal, t, s, mode, c):
    """ẍ [m/s^2] of the body in ``mode``."""
    if is_compliant(c):
        if is_kinematic(c):
            return 0.0
        return (drive_force(t, s[X], c) - s[FT]) / c[MASS]
    return _body_slip_acceleration(normal, t, s, mode, c)


# Inlined into the steps (one call site each): see integrators/steppers.py.
@njit(cache=True, inline="always")
def derivatives(t, s, mode, c):
    """ṡ = (ẏ, ÿ, ẋ, ẍ, u̇, ḟ) of eqs. (2.4)–(2.5) with the composed normal law, the
    drive and the tangential contact, a tuple in the state layout; ``s`` is a state
    tuple (:func:`state_tuple`) or array."""
    y = s[Y]
    yd = s[YDOT]
    normal = 0.0 if airborne(mode) else normal_force(t, y, yd, c)
    if is_compliant(c):
        udot, fdot = _contact_point_rates(t, s, mode, normal, c)
    else:
        udot, fdot = 0.0, 0.0
    return (
        yd,
        acceleration_from_force(t, normal, c),
        s[XDOT],
        _body_acceleration(normal, t, s, mode, c),
        udot,
        fdot,
    )


@njit(cache=True, error_model="numpy")
def _derivatives_call(t, s, mode, c):
    """:func:`derivatives` behind a compiled call (``s`` a state tuple)."""
    return derivatives(t, s, mode, c)


@njit(cache=True, inline="always")
def separation_value(delta, delta_rate, c):
    """SEPARATION's value [N]: N_raw at (δ [m], δ̇ [m/s]) with the elastic part floored
    (sign-floored, so that it is > 0 in contact)."""
    elastic = elastic_force(delta, c)
    if elastic < _ELASTIC_FLOOR:
        elastic = _ELASTIC_FLOOR
    return damped_force(elastic, delta_rate, c)


@njit(cache=True, inline="always")
def separation_rate(delta, delta_rate, delta_accel, c):
    """SEPARATION's rate [N/s] along the motion, given δ [m], δ̇ [m/s], δ̈ [m/s^2]."""
    elastic = elastic_force(delta, c)
    if elastic < _ELASTIC_FLOOR:
        elastic = _ELASTIC_FLOOR
    d_delta, d_rate = damped_force_partials(elastic, elastic_stiffness(delta, c), delta_rate, c)
    return d_delta * delta_rate + d_rate * delta_accel


@njit(cache=True, inline="always")
def switch_active(which, mode, c):
    """True when switching function ``which`` can change anything in ``mode``."""
    if which == CONTACT_GAP:
        return True
    if which == SEPARATION:
        return can_separate_in_overlap(c)
    direction = _tangential_mode(mode)
    if which == STICK_MARGIN:
        return direction == 0.0
    return direction == 1.0 or direction == -1.0


@njit(cache=True, inline="always")
def inside(which, value):
    """True on the "inside" side of switching function ``which`` (contact, stick holds,
    sliding on). The stick margin may be exactly 0 while stick holds (|F| <= μN, 2.2);
    δ = 0 and N_raw = 0 count as flight."""
    if which == STICK_MARGIN:
        return value >= 0.0
    return value > 0.0


@njit(cache=True, inline="always")
def holds_only_inside(which):
    """True when the mode that activates ``which`` exists only on its inside (stick
    margin, sliding speed): a value on the boundary at a step start is a mode entered
    right there (a release: the speed starts at exactly 0 and must first rise).
    False for the two-sided contact functions (flight and contact are both states)."""
    return which == STICK_MARGIN or which == SLIDING_SPEED


@njit(cache=True, inline="always")
def _held_force(t, s, c):
    """The force the interface holds in stick [N]: the drive F(t, x) on a rigid
    contact, the spring force f on a compliant one."""
    if is_compliant(c):
        return s[FT]
    return drive_force(t, s[X], c)


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
def _contact_point_acceleration(t, s, mode, c):
    """ü [m/s^2] of a sliding compliant contact point, by a central difference along
    the flow of :func:`derivatives` (see ``_RATE_STEP``)."""
    eps = _RATE_STEP * (c[STATIC_DEFLECTION] / c[GRAVITY]) ** 0.5
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
    direction = _tangential_mode(mode)
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
    direction = _tangential_mode(mode)
    return direction * _body_acceleration(normal, t, s, direction, c)


@njit(cache=True)
def in_contact(t, s, c):
    """True in contact: δ > 0 and N_raw > 0 (the separation function's sign)."""
    delta, delta_rate, _ = gap(t, s[Y], s[YDOT], c)
    return delta > 0.0 and separation_value(delta, delta_rate, c) > 0.0


@njit(cache=True, inline="always")
def _flight_mode(s):
    return -FLIGHT if s[XDOT] < 0.0 else FLIGHT


@njit(cache=True, inline="always")
def _lift_off(s):
    """(mode, event) of a compliant contact point leaving contact: the spring relaxes
    (f = 0, u = x, in place in ``s``) and the point flies with the body."""
    s[FT] = 0.0
    s[U] = s[X]
    return _flight_mode(s), CONTACT_LOST


@njit(cache=True, inline="always")
def _drop_to_kinetic_limit(t, s, direction, normal, c):
    """A compliant contact point starts to slip in ``direction``: its spring force drops
    to the kinetic limit μ_k N at once and the massless point jumps as the spring
    recovers (f = k_t (x - u) in the spring's own increments), in place in ``s``."""
    held = s[FT]
    s[FT] = direction * kinetic_coefficient(0.0, c) * normal
    stiffness = tangential_stiffness(gap(t, s[Y], s[YDOT], c)[0], c)
    if stiffness > 0.0:
        s[U] += (held - s[FT]) / stiffness


@njit(cache=True)
def initial_mode(t, s, c):
    """Friction mode at a state (eq. 2.2): stick iff the held force is within μ_s N.

    Rigid contact: sgn ẋ when the body moves; otherwise stick iff |F| <= μ_s N, else
    slip towards F, + 4 in flight for a damped model (module doc). Compliant: stick iff
    |f| <= μ_s N, else slip towards f, with f set to the kinetic limit μ_k N (in place in
    ``s``); in flight the label ±2 (sgn ẋ).
    """
    normal = normal_force_call(t, s[Y], s[YDOT], c)
    if is_compliant(c):
        if normal <= 0.0:
            return _flight_mode(s)
        if abs(s[FT]) <= friction_limit(normal, c):
            return 0.0
        direction = sign(s[FT])
        _drop_to_kinetic_limit(t, s, direction, normal, c)
        return direction
    offset = 0.0 if normal > 0.0 else _flight_flag(c)
    return _rigid_direction(t, s, normal, c) + offset


@njit(cache=True, inline="always")
def _rigid_direction(t, s, normal, c):
    """Slip direction of a body on a rigid contact at a state (eq. 2.2): sgn ẋ when it
    moves; at rest stick iff |F| <= μ_s N, else slip towards F."""
    if s[XDOT] != 0.0:
        return sign(s[XDOT])
    force = drive_force(t, s[X], c)
    if abs(force) <= friction_limit(normal, c):
        return 0.0
    return sign(force)


# Friction limit [in units of m g] below which a touchdown is taken as grazing (N = 0+):
# the spring, relaxed, then sticks only if the limit rises at least as fast as it loads.
GRAZING = 1e-12


@njit(cache=True)
def _touchdown_mode(t, s, c):
    """Mode of a compliant contact point at touchdown (relaxed spring, f = 0).

    With a force jump (Kelvin–Voigt) the point sticks: 0 = f < μ_s N. At a grazing
    touchdown (N = 0+) stick holds only if μ_s dN/dt >= k_t |ẋ|; otherwise the point
    slides with the body's direction on the limit f = μ_k N (= 0+).
    """
    normal = normal_force_call(t, s[Y], s[YDOT], c)
    if friction_limit(normal, c) > GRAZING * c[MASS] * c[GRAVITY] or s[XDOT] == 0.0:
        return 0.0
    limit_rate = friction_limit_rate(normal_force_rate_call(t, s[Y], s[YDOT], c), c)
    loading = tangential_stiffness(gap(t, s[Y], s[YDOT], c)[0], c) * abs(s[XDOT])
    if limit_rate >= loading:
        return 0.0
    direction = sign(s[XDOT])
    s[FT] = direction * kinetic_coefficient(0.0, c) * normal
    return direction


@njit(cache=True)
def _compliant_switch(which, t, s, mode, c):
    """(new mode, event) of a compliant contact point after a friction switch."""
    normal = normal_force_call(t, s[Y], s[YDOT], c)
    if normal <= 0.0:
        # The friction functions are active only in contact (mode 0, ±1), so the contact
        # ended at this very instant: N -> 0 makes the friction limit and, in slip, the
        # rate u̇ = ẋ - ḟ/k_t jump, and their flip can be located an ulp before the
        # contact function's. It is the loss of contact (else the spring would keep its
        # extension through the flight and the loss would never be recorded).
        return _lift_off(s)
    if which == STICK_MARGIN:
        # Slip starts towards the spring force, which drops to the kinetic limit
        # (instantly: the contact point is massless). Where μ_s > μ_k and N falls the
        # drop may leave nothing to slide for: the point sticks again at once.
        direction = sign(s[FT])
        _drop_to_kinetic_limit(t, s, direction, normal, c)
        if direction * _contact_point_rates(t, s, direction, normal, c)[0] <= 0.0:
            return 0.0, SLIP_START
        return direction, SLIP_START
    # The contact point comes to rest on the limit f = μ_k N sgn: it sticks (f can
    # only fall back inside the static limit, never reverse at once).
    s[FT] = mode * kinetic_coefficient(0.0, c) * normal
    return 0.0, STICK_START


@njit(cache=True)
def apply_switch(which, t, s, mode, c):
    """(new mode, event kind) after switching function ``which`` flipped at (t, s).

    ``s`` is the state just past the flip; it is modified in place where the switch
    sets a variable (ẋ = 0 exactly when the slider comes to rest; the spring force of a
    compliant contact put on its kinetic limit at a slip start or a stick, relaxed at a
    loss of contact). A contact function that flips without changing contact (the
    separation function while δ <= 0, the gap after a separation inside the overlap)
    gives ``NO_EVENT``. At touchdown a compliant contact point lands with a relaxed
    spring (f = 0) and sticks, unless the touchdown grazes (N = 0+) and the spring
    loads faster than the limit rises (:func:`_touchdown_mode`).
    """
    if which == CONTACT_GAP or which == SEPARATION:
        delta, delta_rate, _ = gap(t, s[Y], s[YDOT], c)
        gap_in = delta > 0.0
        sep_in = separation_value(delta, delta_rate, c) > 0.0
        after = gap_in and sep_in
        if which == CONTACT_GAP:
            before = (not gap_in) and sep_in
        else:
            before = gap_in and not sep_in
        if after and not before:
            if is_compliant(c):
                s[FT] = 0.0
                s[U] = s[X]
                return _touchdown_mode(t, s, c), CONTACT_MADE
            return _tangential_mode(mode), CONTACT_MADE
        if before and not after:
            if is_compliant(c):
                return _lift_off(s)
            return mode + _flight_flag(c), CONTACT_LOST
        return mode, NO_EVENT
    if is_compliant(c):
        return _compliant_switch(which, t, s, mode, c)
    # A rigid contact keeps its flight flag (the contact switches set it).
    offset = _AIRBORNE if airborne(mode) else 0.0
    if which == STICK_MARGIN:
        return sign(drive_force(t, s[X], c)) + offset, SLIP_START
    # The slider has come to rest: ẋ = 0 exactly, then stick or slide on (2.2).
    s[XDOT] = 0.0
    normal = 0.0 if offset else normal_force_call(t, s[Y], s[YDOT], c)
    direction = _rigid_direction(t, s, normal, c)
    if direction == 0.0:
        return offset, STICK_START
    if direction == _tangential_mode(mode):
        return direction + offset, SLIP_START
    return direction + offset, SLIP_REVERSAL


def state_array(
    y: float,
    ydot: float,
    x: float = 0.0,
    xdot: float = 0.0,
    u: float | None = None,
    spring_force: float = 0.0,
) -> np.ndarray:
    """A state vector [y [m], ẏ [m/s], x [m], ẋ [m/s], u [m], f [N]] in the layout above
    (u defaults to x: a relaxed tangential spring when f = 0)."""
    out = np.zeros(N_STATE)
    out[Y], out[YDOT], out[X], out[XDOT] = y, ydot, x, xdot
    out[U] = x if u is None else u
    out[FT] = spring_force
    return out


def full_states(states: np.ndarray) -> np.ndarray:
    """``states`` (shape (..., N_STATE) or (..., 4)) in the full layout: rows holding only
    the body's (y, ẏ, x, ẋ) get a relaxed contact point, u = x and f = 0."""
    states = np.asarray(states, dtype=np.float64)
    if states.shape[-1] != 4:
        return states
    out = np.zeros((*states.shape[:-1], N_STATE))
    out[..., :4] = states
    out[..., U] = states[..., X]
    return out


@njit(cache=True)
def normal_samples(t, y, ydot, c):
    """(N [N], N_raw [N], δ [m]) at the samples (t[k], y[k], ẏ[k]), from the composed
    normal law: in contact iff δ > 0 and N_raw > 0."""
    n = t.shape[0]
    force = np.empty(n)
    raw = np.empty(n)
    delta = np.empty(n)
    for k in range(n):
        force[k] = normal_force(t[k], y[k], ydot[k], c)
        raw[k] = raw_normal_force(t[k], y[k], ydot[k], c)
        delta[k] = gap(t[k], y[k], ydot[k], c)[0]
    return force, raw, delta


@njit(cache=True)
def interface_samples(t, states, modes, c):
    """(F [N], F_t [N], μ_s N [N]) at the samples: the drive force on the body, the
    friction force on the body signed as in (2.5) (m ẍ = F + F_t) and the static limit.

    Rigid: sliding F_t = -μ(|ẋ|) N sgn ẋ, stick F_t = -F. Compliant: F_t = -f (the
    spring force). Kinematic drive: F = -F_t, the force that keeps ẋ = v.
    """
    n = t.shape[0]
    drive = np.empty(n)
    friction = np.empty(n)
    limit = np.empty(n)
    for k in range(n):
        s = states[k]
        normal = normal_force(t[k], s[Y], s[YDOT], c)
        limit[k] = friction_limit(normal, c)
        direction = _tangential_mode(modes[k])
        if is_compliant(c):
            friction[k] = -s[FT]
        elif direction != 0.0:
            friction[k] = -direction * kinetic_coefficient(s[XDOT], c) * normal
        else:
            friction[k] = -drive_force(t[k], s[X], c)
        drive[k] = -friction[k] if is_kinematic(c) else drive_force(t[k], s[X], c)
    return drive, friction, limit
