"""The composed normal motion: contact law + damping + excitation (docs/design.md).

    m ÿ = m g + P(t) - N,    N = max(0, N_raw(δ, δ̇)) while δ > 0, else 0,

with δ = y - z(t) the penetration, N_raw the elastic law (2.3) with the damping of
:mod:`microslip.model.damping`, P(t) and z(t) from :mod:`microslip.model.excitation`.
With a prescribed penetration the normal degree of freedom is removed: δ(t) is
given, and y, ẏ carry δ, δ̇ (z = 0).

Every path (event and rk4 integration, the batched kernel, the steady state, shooting
and continuation) evaluates the normal force through these functions. They depend on
the normal state (t, y, ẏ) only: the normal motion never depends on the tangential one.

They are compiled functions, taking the coefficients as a tuple; LLVM inlines them into
the right-hand sides of the steps, which compute N once and pass it on
(:func:`acceleration_from_force`). The switching functions, which evaluate them a dozen
times over, call them through compiled boundaries (:mod:`microslip.model.system`;
docs/design.md, "Compile time").
"""

from __future__ import annotations

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.coefficients import EXCITATION_KIND, GRAVITY, MASS
from microslip.model.contact import elastic_force, elastic_stiffness
from microslip.model.damping import damped_force, damped_force_partials
from microslip.model.excitation import (
    NONE,
    applied_force,
    is_prescribed,
    prescribed_gap,
    surface_motion,
)

__all__ = [
    "acceleration_from_force",
    "acceleration_from_forcing",
    "forcing",
    "gap",
    "gap_from",
    "normal_acceleration",
    "normal_force",
    "normal_force_from",
    "normal_force_partials",
    "normal_force_rate",
    "raw_normal_force",
    "surface",
]


@njit(cache=True, error_model="numpy")
def surface(t, c):
    """What the penetration reads of time at t: (z [m], ż [m/s], z̈ [m/s^2]) of the
    slideway surface, or for a prescribed penetration (δ [m], δ̇ [m/s], δ̈ [m/s^2]);
    zeros, without a sine, for the other excitations. A step whose stages share a time
    evaluates it once for them all (:mod:`microslip.integrators.normal_step`)."""
    if c[EXCITATION_KIND] == NONE:
        return 0.0, 0.0, 0.0
    if is_prescribed(c):
        return prescribed_gap(t, c)
    return surface_motion(t, c)


@njit(cache=True, error_model="numpy")
def gap_from(surface_terms, y, ydot, c):
    """:func:`gap` (δ [m], δ̇ [m/s], z̈ or δ̈ [m/s^2]) at the state (y [m], ẏ [m/s]),
    given ``surface_terms`` = :func:`surface` at its time."""
    if c[EXCITATION_KIND] == NONE:
        return y, ydot, 0.0
    if is_prescribed(c):
        return surface_terms
    z, zdot, zddot = surface_terms
    return y - z, ydot - zdot, zddot


@njit(cache=True, error_model="numpy")
def gap(t, y, ydot, c):
    """(δ [m], δ̇ [m/s], z̈ [m/s^2]): penetration, its rate, and the surface acceleration.

    With a prescribed penetration, δ and δ̇ are the prescribed ones and the third value
    is δ̈ (the body's ÿ then follows δ̈).
    """
    return gap_from(surface(t, c), y, ydot, c)


@njit(cache=True, error_model="numpy")
def raw_normal_force(t, y, ydot, c):
    """N_raw [N], the unclipped contact law at (t, y, ẏ); meaningful while δ > 0.

    In contact iff δ > 0 and N_raw > 0. For δ <= 0 the elastic part is 0 and N_raw is
    the damping term alone.
    """
    delta, delta_rate, _ = gap(t, y, ydot, c)
    return damped_force(elastic_force(delta, c), delta_rate, c)


@njit(cache=True, error_model="numpy")
def normal_force(t, y, ydot, c):
    """Compressive normal force N >= 0 [N] (the paper's |R|, eq. 2.3, with damping)."""
    return normal_force_from(surface(t, c), y, ydot, c)


@njit(cache=True, error_model="numpy")
def normal_force_from(surface_terms, y, ydot, c):
    """:func:`normal_force` N >= 0 [N] at the state (y [m], ẏ [m/s]), given
    ``surface_terms`` = :func:`surface` at its time."""
    delta, delta_rate, _ = gap_from(surface_terms, y, ydot, c)
    if delta <= 0.0:
        return 0.0
    n = damped_force(elastic_force(delta, c), delta_rate, c)
    return n if n > 0.0 else 0.0


@njit(cache=True, error_model="numpy")
def forcing(t, c):
    """The term of the normal acceleration that depends on time alone, at t: P(t) [N]
    of a harmonic force, δ̈(t) [m/s^2] of a prescribed penetration, else 0. One sine
    (or cosine) of the excitation: a step whose stages share a time evaluates it once
    for them all (:mod:`microslip.integrators.normal_step`)."""
    if c[EXCITATION_KIND] == NONE:
        return 0.0
    if is_prescribed(c):
        return prescribed_gap(t, c)[2]
    return applied_force(t, c)


@njit(cache=True, error_model="numpy")
def acceleration_from_forcing(forcing_value, normal, c):
    """ÿ [m/s^2] given :func:`forcing` and the normal force N [N] at one time:
    g + P/m - N/m (eq. 2.4 with excitation); δ̈ if prescribed (N is then not used)."""
    if c[EXCITATION_KIND] == NONE:
        return c[GRAVITY] - normal / c[MASS]
    if is_prescribed(c):
        return forcing_value
    return c[GRAVITY] + (forcing_value - normal) / c[MASS]


@njit(cache=True, error_model="numpy")
def acceleration_from_force(t, normal, c):
    """ÿ [m/s^2] given the normal force N [N] at t: g + P(t)/m - N/m (eq. 2.4 with
    excitation); δ̈(t) if prescribed (N is then not used)."""
    return acceleration_from_forcing(forcing(t, c), normal, c)


@njit(cache=True, error_model="numpy")
def normal_acceleration(t, y, ydot, c):
    """ÿ [m/s^2]: g + P(t)/m - N/m (eq. 2.4 with excitation); δ̈(t) if prescribed."""
    return acceleration_from_force(t, normal_force(t, y, ydot, c), c)


@njit(cache=True, error_model="numpy")
def normal_force_partials(t, y, ydot, c):
    """(∂N/∂y [N/m], ∂N/∂ẏ [N s/m]); 0 out of contact and where N is clipped.

    With a prescribed penetration N does not depend on the state: (0, 0).
    """
    if is_prescribed(c):
        return 0.0, 0.0
    delta, delta_rate, _ = gap(t, y, ydot, c)
    if delta <= 0.0:
        return 0.0, 0.0
    elastic = elastic_force(delta, c)
    if damped_force(elastic, delta_rate, c) <= 0.0:
        return 0.0, 0.0
    return damped_force_partials(elastic, elastic_stiffness(delta, c), delta_rate, c)


@njit(cache=True, error_model="numpy")
def normal_force_rate(t, y, ydot, c):
    """dN/dt [N/s] along the motion (0 out of contact or while clipped)."""
    return _force_rate(t, y, ydot, normal_force(t, y, ydot, c), c, True)


@njit(cache=True, error_model="numpy")
def raw_normal_force_rate(t, y, ydot, normal, c):
    """dN_raw/dt [N/s] of the unclipped law while δ > 0 (0 for δ <= 0): dN/dt in
    contact, continued smoothly past a separation inside the overlap (N_raw <= 0 with
    δ > 0, a damped law), where N itself is clipped to 0. ``normal`` is
    :func:`normal_force` [N] at (t, y, ẏ), which its callers hold already (δ̈ needs it:
    computing it again was a fifth of a slipping Mindlin step on a Hertz contact)."""
    return _force_rate(t, y, ydot, normal, c, False)


@njit(cache=True, error_model="numpy", inline="always")
def _force_rate(t, y, ydot, normal, c, clipped):
    """dN/dt [N/s], 0 for δ <= 0 and, where ``clipped``, while N_raw <= 0; ``normal``
    the clipped N [N] at (t, y, ẏ), for δ̈."""
    delta, delta_rate, third = gap(t, y, ydot, c)
    if delta <= 0.0:
        return 0.0
    elastic = elastic_force(delta, c)
    if clipped and damped_force(elastic, delta_rate, c) <= 0.0:
        return 0.0
    d_delta, d_rate = damped_force_partials(elastic, elastic_stiffness(delta, c), delta_rate, c)
    if is_prescribed(c):
        delta_accel = third
    else:
        delta_accel = acceleration_from_force(t, normal, c) - third
    return d_delta * delta_rate + d_rate * delta_accel
