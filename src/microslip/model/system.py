"""The composed system that the integrators advance (docs/design.md, "state layout").

This module and its three companions are the only ones that know what the state
variables mean: here the state, the mode and the right-hand side,
:mod:`microslip.model.switching_functions` the switching functions (when a switch
happens), :mod:`microslip.model.switches` what a switch does, and
:mod:`microslip.model.samples` the states and forces of a trajectory's output. The
integrators see

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

and call :func:`derivatives` within a mode, and the switching functions
(:mod:`~microslip.model.switching_functions`), indexed by the codes below, which say when
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
    MASS,
    TANGENTIAL_KIND,
)
from microslip.model.damping import can_separate_in_overlap
from microslip.model.drive import drive_force, is_kinematic
from microslip.model.friction import kinetic_coefficient, kinetic_coefficient_at_rest
from microslip.model.normal import (
    acceleration_from_force,
    gap,
    normal_acceleration,
    normal_force,
    normal_force_rate,
    raw_normal_force_rate,
)
from microslip.model.tangential import is_compliant, tangential_stiffness

__all__ = [
    "AIRBORNE",
    "CONTACT_GAP",
    "EVENT_NAMES",
    "N_STATE",
    "N_SWITCHES",
    "SEPARATION",
    "SLIDING_SPEED",
    "STICK_MARGIN",
    "airborne",
    "body_acceleration",
    "contact_point_rates",
    "derivatives",
    "flight_flag",
    "is_paper_model",
    "normal_acceleration_call",
    "normal_force_call",
    "normal_force_rate_call",
    "raw_normal_force_rate_call",
    "slip_directions",
    "state_tuple",
    "tangential_mode",
]

# State layout. Only the model's system modules (this one, switching_functions.py,
# switches.py, samples.py) and
# the paper-model fast pass of the batched kernel, which import these names, index the
# state by meaning.
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

FLIGHT = 2.0  # |mode| of a compliant contact point in flight (its law until touchdown)
# Added to the mode (0, ±1) of a rigid contact in flight when the model is damped. The
# undamped laws are continuous at touchdown (N = S c_n δ^m2 -> 0), so there the stage
# states decide, as in the paper's scheme and its vectorised pass.
AIRBORNE = 4.0
_FLAGGED_ABOVE = 2.5  # modes above it carry the flag (3, 4, 5); every other one is < 2.5


@njit(cache=True, inline="always")
def flight_flag(c):
    """What a rigid contact adds to its mode in flight: AIRBORNE for a damped model, 0
    for an undamped one (the stage states decide there, see AIRBORNE)."""
    return AIRBORNE if can_separate_in_overlap(c) else 0.0


@njit(cache=True, inline="always")
def tangential_mode(mode):
    """The interface part of ``mode``: 0 (stick), ±1 (slip), ±2 (compliant flight)."""
    return mode - AIRBORNE if mode > _FLAGGED_ABOVE else mode


@njit(cache=True, inline="always")
def airborne(mode):
    """True when ``mode`` holds the body out of contact (N = 0 over the step)."""
    return mode > _FLAGGED_ABOVE or abs(mode) == FLIGHT


def slip_directions(modes: np.ndarray) -> np.ndarray:
    """The slip direction (-1, 0 = stick, +1) of recorded modes: a compliant contact
    point in flight (±2) gives ±1, a rigid contact in flight its tangential mode."""
    modes = np.asarray(modes, dtype=float)
    return np.sign(np.where(modes > _FLAGGED_ABOVE, modes - AIRBORNE, modes))


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
# compiled functions instead. The arguments are scalars and the coefficient tuple, so a
# call costs no reference counting, and the values are the same bits. The right-hand
# side (derivatives) is inlined into the steps: it is their hot loop (docs/design.md,
# "The compiled form").
@njit(cache=True, error_model="numpy")
def normal_force_call(t, y, ydot, c):
    """:func:`~microslip.model.normal.normal_force` [N] behind a compiled call."""
    return normal_force(t, y, ydot, c)


@njit(cache=True, error_model="numpy")
def normal_force_rate_call(t, y, ydot, c):
    """:func:`~microslip.model.normal.normal_force_rate` [N/s] behind a compiled call."""
    return normal_force_rate(t, y, ydot, c)


@njit(cache=True, error_model="numpy")
def raw_normal_force_rate_call(t, y, ydot, normal, c):
    """:func:`~microslip.model.normal.raw_normal_force_rate` [N/s] behind a compiled
    call."""
    return raw_normal_force_rate(t, y, ydot, normal, c)


@njit(cache=True, error_model="numpy")
def normal_acceleration_call(t, y, ydot, c):
    """:func:`~microslip.model.normal.normal_acceleration` [m/s^2] behind a compiled call."""
    return normal_acceleration(t, y, ydot, c)


@njit(cache=True, inline="always")
def _body_slip_acceleration(normal, t, s, mode, c):
    """ẍ [m/s^2] of a body on a rigid contact sliding in ``mode`` = sgn ẋ (eqs. 2.2,
    2.5): m ẍ = F(t, x) - μ(|ẋ|) N sgn ẋ; 0 in stick (mode 0) and with the kinematic
    drive."""
    direction = tangential_mode(mode)
    if direction == 0.0 or is_kinematic(c):
        return 0.0
    friction = kinetic_coefficient(s[XDOT], c) * normal
    return (drive_force(t, s[X], c) - direction * friction) / c[MASS]


@njit(cache=True, inline="always")
def contact_point_rates(t, s, mode, normal, c):
    """(u̇ [m/s], ḟ [N/s]) of the compliant contact point.

    Flight (N = 0): the spring is relaxed and follows the body (u̇ = ẋ, ḟ = 0). Stick:
    u̇ = 0, ḟ = k_t ẋ (the incremental law, k_t = k_t(δ) for Mindlin). Slip in ``mode``:
    f = μ_k N mode stays on the limit, ḟ = μ_k Ṅ mode, and the spring's extension
    x - u follows it, u̇ = ẋ - ḟ / k_t.

    Past a separation inside the overlap (δ > 0, a damped N_raw <= 0, N clipped to 0)
    a contact mode keeps its law, with Ṅ the raw law's
    (:func:`~microslip.model.normal.raw_normal_force_rate`): the rates stay smooth
    through the SEPARATION root within a trial step, whose switch then ends the contact
    (the flight rates there made slip's u̇ and ḟ jump by ~Ṅ, which an adaptive step's
    error estimate cannot pass: a step size underflow at the root).
    """
    xdot = s[XDOT]
    if abs(mode) == FLIGHT:
        return xdot, 0.0
    y = s[Y]
    ydot = s[YDOT]
    delta = gap(t, y, ydot, c)[0]
    if normal <= 0.0 and delta <= 0.0:
        return xdot, 0.0
    stiffness = tangential_stiffness(delta, c)
    if mode == 0.0:
        return 0.0, stiffness * xdot
    force_rate = (
        mode * kinetic_coefficient_at_rest(c) * raw_normal_force_rate_call(t, y, ydot, normal, c)
    )
    if stiffness <= 0.0:
        return xdot, force_rate
    return xdot - force_rate / stiffness, force_rate


@njit(cache=True, inline="always")
def body_acceleration(normal, t, s, mode, c):
    """ẍ [m/s^2] of the body in ``mode``."""
    if is_compliant(c):
        if is_kinematic(c):
            return 0.0
        if mode == 1.0 or mode == -1.0:
            # In slip the spring force is on its limit, f = mode μ_k N: the limit itself,
            # not the integrated f, whose rate μ_k Ṅ is singular at a touchdown
            # (Ṅ ∝ δ^(m2-1) δ̇) and costs RK4 its order there.
            friction = mode * kinetic_coefficient_at_rest(c) * normal
            return (drive_force(t, s[X], c) - friction) / c[MASS]
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
        udot, fdot = contact_point_rates(t, s, mode, normal, c)
    else:
        udot, fdot = 0.0, 0.0
    return (
        yd,
        acceleration_from_force(t, normal, c),
        s[XDOT],
        body_acceleration(normal, t, s, mode, c),
        udot,
        fdot,
    )
