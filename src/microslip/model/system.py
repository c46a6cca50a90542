"""The composed system that the integrators advance (docs/design.md, "state layout").

This is the only module that knows what the state variables mean. The integrators see

* a state ``s``: a float64 array of :data:`N_STATE` values, here
  s = [y [m], ẏ [m/s], x [m], ẋ [m/s]] (y > 0 penetration, eq. 2.3; with a prescribed
  penetration y, ẏ carry δ, δ̇);
* an opaque ``mode`` (a float): today the sliding direction sgn ẋ = ±1, or 0 for stick;
* the coefficient vector ``c`` (:mod:`microslip.model.coefficients`);

and call :func:`derivatives` within a mode, and the switching functions, which say when
the mode or the smoothness of the right-hand side changes (the state goes to them as a
tuple, :func:`state_tuple`, or as an array):

    CONTACT_GAP     δ                      > 0 in contact (touchdown / lift-off at δ = 0)
    SEPARATION      N_raw (sign-floored)   > 0 in contact; only with damping, which can
                                           make N_raw <= 0 while δ > 0
    STICK_MARGIN    μN - |F|               >= 0 while stick holds (eq. 2.2); stick only
    SLIDING_SPEED   mode · ẋ               > 0 while sliding in direction ``mode``

The normal law is :mod:`microslip.model.normal` (contact law + damping + excitation),
the friction limit μN and the drive F come from :mod:`microslip.model.friction`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.contact import elastic_force, elastic_stiffness
from microslip.model.damping import can_separate_in_overlap, damped_force, damped_force_partials
from microslip.model.excitation import is_prescribed
from microslip.model.friction import (
    drive_force,
    drive_force_rate,
    friction_limit,
    friction_limit_rate,
    slip_acceleration,
)
from microslip.model.normal import (
    gap,
    normal_acceleration,
    normal_force,
    normal_force_rate,
    raw_normal_force,
)

__all__ = [
    "CONTACT_GAP",
    "EVENT_NAMES",
    "N_STATE",
    "N_SWITCHES",
    "SEPARATION",
    "SLIDING_SPEED",
    "STICK_MARGIN",
    "apply_switch",
    "derivatives",
    "holds_only_inside",
    "in_contact",
    "initial_mode",
    "inside",
    "normal_samples",
    "state_array",
    "state_tuple",
    "switch_active",
    "switching_rate",
    "switching_value",
]

# State layout. Only this module (and the paper-model fast pass of the batched kernel,
# which imports these names) indexes the state by meaning.
N_STATE = 4
Y, YDOT, X, XDOT = 0, 1, 2, 3

# Switching functions.
CONTACT_GAP = 0
SEPARATION = 1
STICK_MARGIN = 2
SLIDING_SPEED = 3
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
    return (s[Y], s[YDOT], s[X], s[XDOT])


# Inlined into the steps (one call site each): see integrators/steppers.py.
@njit(cache=True, inline="always")
def derivatives(t, s, mode, c):
    """ṡ = (ẏ, ÿ, ẋ, ẍ) of eqs. (2.4)–(2.5) with the composed normal law, a tuple in
    the state layout; ``s`` is a state tuple (:func:`state_tuple`) or array."""
    y = s[Y]
    yd = s[YDOT]
    return (
        yd,
        normal_acceleration(t, y, yd, c),
        s[XDOT],
        slip_acceleration(normal_force(t, y, yd, c), t, mode, c),
    )


@njit(cache=True, inline="always")
def _separation_value(delta, delta_rate, c):
    elastic = elastic_force(delta, c)
    if elastic < _ELASTIC_FLOOR:
        elastic = _ELASTIC_FLOOR
    return damped_force(elastic, delta_rate, c)


@njit(cache=True, inline="always")
def switch_active(which, mode, c):
    """True when switching function ``which`` can change anything in ``mode``."""
    if which == CONTACT_GAP:
        return True
    if which == SEPARATION:
        return can_separate_in_overlap(c)
    if which == STICK_MARGIN:
        return mode == 0.0
    return mode != 0.0


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
        return _separation_value(delta, delta_rate, c)
    if which == STICK_MARGIN:
        return friction_limit(normal_force(t, y, yd, c), c) - abs(drive_force(t, c))
    return mode * s[XDOT]


@njit(cache=True, error_model="numpy")
def switching_rate(which, t, s, mode, c):
    """Time derivative of :func:`switching_value` along the motion in ``mode``."""
    y = s[Y]
    yd = s[YDOT]
    if which == CONTACT_GAP:
        return gap(t, y, yd, c)[1]
    if which == SEPARATION:
        delta, delta_rate, third = gap(t, y, yd, c)
        elastic = elastic_force(delta, c)
        if elastic < _ELASTIC_FLOOR:
            elastic = _ELASTIC_FLOOR
        d_delta, d_rate = damped_force_partials(elastic, elastic_stiffness(delta, c), delta_rate, c)
        delta_accel = third if is_prescribed(c) else normal_acceleration(t, y, yd, c) - third
        return d_delta * delta_rate + d_rate * delta_accel
    if which == STICK_MARGIN:
        force = drive_force(t, c)
        rate = friction_limit_rate(normal_force_rate(t, y, yd, c), c)
        return rate - sign(force) * drive_force_rate(t, c)
    return mode * slip_acceleration(normal_force(t, y, yd, c), t, mode, c)


@njit(cache=True)
def in_contact(t, s, c):
    """True in contact: δ > 0 and N_raw > 0 (the separation function's sign)."""
    delta, delta_rate, _ = gap(t, s[Y], s[YDOT], c)
    return delta > 0.0 and _separation_value(delta, delta_rate, c) > 0.0


@njit(cache=True)
def initial_mode(t, s, c):
    """Friction mode at a state: sgn ẋ when sliding; stick iff |F| <= μN (2.2)."""
    if s[XDOT] != 0.0:
        return sign(s[XDOT])
    force = drive_force(t, c)
    if abs(force) <= friction_limit(normal_force(t, s[Y], s[YDOT], c), c):
        return 0.0
    return sign(force)


@njit(cache=True)
def apply_switch(which, t, s, mode, c):
    """(new mode, event kind) after switching function ``which`` flipped at (t, s).

    ``s`` is the state just past the flip; it is modified in place where the switch
    sets a variable (ẋ = 0 exactly when the slider comes to rest). A contact function
    that flips without changing contact (the separation function while δ <= 0, the
    gap after a separation inside the overlap) gives ``NO_EVENT``.
    """
    if which == CONTACT_GAP or which == SEPARATION:
        delta, delta_rate, _ = gap(t, s[Y], s[YDOT], c)
        gap_in = delta > 0.0
        sep_in = _separation_value(delta, delta_rate, c) > 0.0
        after = gap_in and sep_in
        if which == CONTACT_GAP:
            before = (not gap_in) and sep_in
        else:
            before = gap_in and not sep_in
        if after and not before:
            return mode, CONTACT_MADE
        if before and not after:
            return mode, CONTACT_LOST
        return mode, NO_EVENT
    if which == STICK_MARGIN:
        return sign(drive_force(t, c)), SLIP_START
    # The slider has come to rest: ẋ = 0 exactly, then stick or slide on (2.2).
    s[XDOT] = 0.0
    new_mode = initial_mode(t, s, c)
    if new_mode == 0.0:
        return 0.0, STICK_START
    if new_mode == mode:
        return new_mode, SLIP_START
    return new_mode, SLIP_REVERSAL


def state_array(y: float, ydot: float, x: float = 0.0, xdot: float = 0.0) -> np.ndarray:
    """A state vector [y [m], ẏ [m/s], x [m], ẋ [m/s]] in the layout above."""
    out = np.zeros(N_STATE)
    out[Y], out[YDOT], out[X], out[XDOT] = y, ydot, x, xdot
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
