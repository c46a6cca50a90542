"""What a switch does to the composed system's mode and state (docs/design.md, "state
layout").

:mod:`microslip.model.system` says *when* the mode or the smoothness of the right-hand
side changes (with :mod:`microslip.model.switching_functions`); this module says *what
follows*: the friction
mode at a state (:func:`initial_mode`, eq. 2.2) and the new mode, the event recorded and
the state set after a switching function flipped (:func:`apply_switch`). A slider comes
to rest and sticks or slides on (eq. 2.2); a compliant contact point starts to slip (its
spring force drops to the kinetic limit), sticks, lifts off (the spring relaxes) or
lands (relaxed, and stuck unless the touchdown grazes, :func:`_touchdown_mode`). The
rigid contact's part of both, and what a contact function's flip means
(:func:`rigid_initial_mode`, :func:`contact_event`, :func:`rigid_contact_mode`), are
functions of their own: the normal tape, whose copy of the model has a rigid contact,
calls them without compiling the rest (:mod:`microslip.integrators.normal_step`).
"""

from __future__ import annotations

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.coefficients import GRAVITY, MASS
from microslip.model.drive import drive_force
from microslip.model.friction import (
    friction_limit,
    friction_limit_rate,
    kinetic_coefficient_at_rest,
)
from microslip.model.normal import gap
from microslip.model.switching_functions import separation_value
from microslip.model.system import (
    AIRBORNE,
    CONTACT_GAP,
    CONTACT_LOST,
    CONTACT_MADE,
    FLIGHT,
    FT,
    NO_EVENT,
    SEPARATION,
    SLIP_REVERSAL,
    SLIP_START,
    STICK_MARGIN,
    STICK_START,
    XDOT,
    YDOT,
    U,
    X,
    Y,
    airborne,
    contact_point_rates,
    flight_flag,
    normal_force_call,
    normal_force_rate_call,
    sign,
    tangential_mode,
)
from microslip.model.tangential import is_compliant, tangential_stiffness

__all__ = [
    "GRAZING",
    "apply_switch",
    "contact_event",
    "initial_mode",
    "rigid_contact_mode",
    "rigid_initial_mode",
]


@njit(cache=True)
def _flight_mode(s):
    return -FLIGHT if s[XDOT] < 0.0 else FLIGHT


@njit(cache=True)
def _lift_off(s):
    """(mode, event) of a compliant contact point leaving contact: the spring relaxes
    (f = 0, u = x, in place in ``s``) and the point flies with the body."""
    s[FT] = 0.0
    s[U] = s[X]
    return _flight_mode(s), CONTACT_LOST


@njit(cache=True)
def _drop_to_kinetic_limit(t, s, direction, normal, c):
    """A compliant contact point starts to slip in ``direction``: its spring force drops
    to the kinetic limit μ_k N at once and the massless point jumps as the spring
    recovers (f = k_t (x - u) in the spring's own increments), in place in ``s``."""
    held = s[FT]
    s[FT] = direction * kinetic_coefficient_at_rest(c) * normal
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
    return rigid_initial_mode(t, s, normal, c)


@njit(cache=True)
def rigid_initial_mode(t, s, normal, c):
    """:func:`initial_mode` of a rigid contact under the normal force ``normal`` [N]:
    the slip direction (:func:`_rigid_direction`), + the flight flag out of contact."""
    offset = 0.0 if normal > 0.0 else flight_flag(c)
    return _rigid_direction(t, s, normal, c) + offset


@njit(cache=True)
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
    s[FT] = direction * kinetic_coefficient_at_rest(c) * normal
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
        if direction * contact_point_rates(t, s, direction, normal, c)[0] <= 0.0:
            return 0.0, SLIP_START
        return direction, SLIP_START
    # The contact point comes to rest on the limit f = μ_k N sgn: it sticks (f can
    # only fall back inside the static limit, never reverse at once).
    s[FT] = mode * kinetic_coefficient_at_rest(c) * normal
    return 0.0, STICK_START


@njit(cache=True)
def contact_event(which, t, y, ydot, c):
    """What contact function ``which`` (CONTACT_GAP or SEPARATION) flipping at
    (t [s], y [m], ẏ [m/s]) does: CONTACT_MADE, CONTACT_LOST, or NO_EVENT where contact
    does not change (the separation function while δ <= 0, the gap after a separation
    inside the overlap). In contact means δ > 0 and N_raw > 0; the other function is
    read at the same state to tell which side the flip came from."""
    delta, delta_rate, _ = gap(t, y, ydot, c)
    gap_in = delta > 0.0
    sep_in = separation_value(delta, delta_rate, c) > 0.0
    after = gap_in and sep_in
    if which == CONTACT_GAP:
        before = (not gap_in) and sep_in
    else:
        before = gap_in and not sep_in
    if after and not before:
        return CONTACT_MADE
    if before and not after:
        return CONTACT_LOST
    return NO_EVENT


@njit(cache=True)
def rigid_contact_mode(event, mode, c):
    """Mode of a rigid contact after a :func:`contact_event`: a touchdown drops the flight
    flag, a lift-off adds it (:func:`~microslip.model.system.flight_flag`)."""
    if event == CONTACT_MADE:
        return tangential_mode(mode)
    if event == CONTACT_LOST:
        return mode + flight_flag(c)
    return mode


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
        event = contact_event(which, t, s[Y], s[YDOT], c)
        if event == CONTACT_MADE and is_compliant(c):
            s[FT] = 0.0
            s[U] = s[X]
            return _touchdown_mode(t, s, c), CONTACT_MADE
        if event == CONTACT_LOST and is_compliant(c):
            return _lift_off(s)
        return rigid_contact_mode(event, mode, c), event
    if is_compliant(c):
        return _compliant_switch(which, t, s, mode, c)
    # A rigid contact keeps its flight flag (the contact switches set it).
    offset = AIRBORNE if airborne(mode) else 0.0
    if which == STICK_MARGIN:
        return sign(drive_force(t, s[X], c)) + offset, SLIP_START
    # The slider has come to rest: ẋ = 0 exactly, then stick or slide on (2.2).
    s[XDOT] = 0.0
    normal = 0.0 if offset else normal_force_call(t, s[Y], s[YDOT], c)
    direction = _rigid_direction(t, s, normal, c)
    if direction == 0.0:
        return offset, STICK_START
    if direction == tangential_mode(mode):
        return direction + offset, SLIP_START
    return direction + offset, SLIP_REVERSAL
