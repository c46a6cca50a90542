"""States in the layout of :mod:`microslip.model.system`, and the forces along recorded
samples of a trajectory (for its output: :mod:`microslip.results`)."""

from __future__ import annotations

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.coefficients import as_tuple
from microslip.model.drive import drive_force, is_kinematic
from microslip.model.friction import friction_limit, kinetic_coefficient
from microslip.model.normal import gap, normal_force, raw_normal_force
from microslip.model.system import FT, N_STATE, XDOT, YDOT, U, X, Y, tangential_mode
from microslip.model.tangential import is_compliant

__all__ = ["full_states", "interface_samples", "normal_samples", "state_array"]


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
def normal_samples(t, y, ydot, coefficients):
    """(N [N], N_raw [N], δ [m]) at the samples (t[k], y[k], ẏ[k]), from the composed
    normal law: in contact iff δ > 0 and N_raw > 0."""
    c = as_tuple(coefficients)  # the laws' one compiled form (docs/design.md)
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
def interface_samples(t, states, modes, coefficients):
    """(F [N], F_t [N], μ_s N [N]) at the samples: the drive force on the body, the
    friction force on the body signed as in (2.5) (m ẍ = F + F_t) and the static limit.

    Rigid: sliding F_t = -μ(|ẋ|) N sgn ẋ, stick F_t = -F. Compliant: F_t = -f (the
    spring force). Kinematic drive: F = -F_t, the force that keeps ẋ = v.
    """
    c = as_tuple(coefficients)  # the laws' one compiled form (docs/design.md)
    n = t.shape[0]
    drive = np.empty(n)
    friction = np.empty(n)
    limit = np.empty(n)
    for k in range(n):
        s = states[k]
        normal = normal_force(t[k], s[Y], s[YDOT], c)
        limit[k] = friction_limit(normal, c)
        direction = tangential_mode(modes[k])
        if is_compliant(c):
            friction[k] = -s[FT]
        elif direction != 0.0:
            friction[k] = -direction * kinetic_coefficient(s[XDOT], c) * normal
        else:
            friction[k] = -drive_force(t[k], s[X], c)
        drive[k] = -friction[k] if is_kinematic(c) else drive_force(t[k], s[X], c)
    return drive, friction, limit
