"""Effective friction under normal vibration: μ_eff = <F_t>/<N> of a kinematically driven
body (docs/theory/friction_reduction.md).

The body moves at a prescribed velocity v (``drive=PrescribedVelocity(v)``); the contact
transmits the friction force F_t (on the body -F_t along the drive, the force the drive
must supply). With a rigid tangential contact the body never sticks and μ_eff = μ(|v|)
exactly for every normal motion (identity 6). With a compliant contact the contact point
sticks where the friction limit rises faster than the spring can load it (μ_k dN/dt >
k_t v) and μ_eff falls below μ_k, by β D(ṽ) for the flat punch (:func:`flat_punch_reduction`).

Exact path: the normal motion is periodic (prescribed penetration, a stable period-1
forced orbit, the undamped free vibration); the full system is integrated period by
period with the event method until the tangential state at the period start repeats (a
slip erases the memory, so this takes a few periods), then the last period is integrated
again with output at Gauss–Legendre nodes between its switching instants, where f and N
are smooth: the averages carry the integration tolerance (~1e-10 relative), not a
sampling error. A forced response that is not period-1 falls back to a time average
with an error estimate (``method="time_average"``, with a warning).
"""

from __future__ import annotations

import itertools
import math
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from microslip import validation as check
from microslip.model.capabilities import require
from microslip.model.coefficients import MU_STATIC
from microslip.model.composition import Model
from microslip.model.contact import elastic_stiffness
from microslip.model.drive import PrescribedVelocity
from microslip.model.excitation import PrescribedPenetration
from microslip.model.friction import StaticKinetic, Stribeck, kinetic_coefficient
from microslip.model.normal import normal_force, normal_force_rate
from microslip.model.tangential import MindlinSpring, TangentialSpring

__all__ = [
    "EffectiveFriction",
    "effective_friction",
    "effective_friction_curve",
    "effective_friction_map",
    "flat_punch_reduction",
]

_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(8)
_PIECES_PER_PERIOD = 64  # a smooth piece longer than T/64 is split for the quadrature
_MAX_PERIODS = 200
_RATE_SAMPLES = 4096  # uniform samples of dN/dt per period for max|dN/dt|
_FALLBACK_PERIODS = 64


@dataclass(frozen=True)
class EffectiveFriction:
    """The effective friction of a kinematically driven body in the steady state.

    Attributes
    ----------
    mu_eff : float
        <F_t>/<N> [-], F_t the friction force the contact transmits along the drive.
    mu_kinetic : float
        The reference coefficient μ_k(|v|) [-] (Coulomb: μ).
    ratio : float
        μ_eff / μ_k [-].
    v_tilde : float
        Dimensionless drive speed ṽ = k_t |v| / (μ_k max|dN/dt|) [-]; nan with a rigid
        contact or a constant N. Mindlin: k_t at the static (or mean) penetration;
        max|dN/dt| sampled at the quadrature nodes (>= 512 per period, ~1e-5 relative).
    mean_friction_force, mean_normal_force : float
        <F_t> [N] and <N> [N] over a period.
    stick_fraction : float
        Fraction of the period [-] the contact point sticks (in contact).
    period : float
        Period [s] of the normal motion (nan if constant).
    method : str
        "exact" (periodic steady state), "closed_form" (rigid or constant N) or
        "time_average".
    error : float
        Estimated relative error [-] of mu_eff: the event tolerance for "exact" and
        "closed_form" round-off, the spread of block averages for "time_average".
    """

    mu_eff: float
    mu_kinetic: float
    ratio: float
    v_tilde: float
    mean_friction_force: float
    mean_normal_force: float
    stick_fraction: float
    period: float
    method: str
    error: float


def flat_punch_reduction(v_tilde: Any) -> np.ndarray:
    """D(ṽ) [-] of the flat punch: μ_eff/μ = 1 - β D(ṽ) for N = N0 (1 + β cos ωt), β <= 1
    (m2 = 1, prescribed penetration, constant k_t, Coulomb, kinematic drive).

    θ = ωt; the contact point sticks from θ1 = π + arcsin ṽ (where μ dN/dt reaches k_t v)
    to the first θ2 > θ1 with cos θ1 + ṽ (θ2 - θ1) = cos θ2 (the spring force catches up
    with μN); D = [sin θ2 - sin θ1 - (θ2 - θ1) cos θ1 - ṽ (θ2 - θ1)²/2] / (2π). D(0) = 1,
    D = 0 for ṽ >= 1 (docs/theory/friction_reduction.md).
    """
    from scipy.optimize import brentq

    values = np.asarray(v_tilde, dtype=float)
    if np.any(~np.isfinite(values)) or np.any(values < 0.0):
        raise ValueError("v_tilde must be finite and >= 0")
    out = np.zeros(values.shape)
    for index, vt in np.ndenumerate(values):
        if vt >= 1.0:
            continue
        theta1 = math.pi + math.asin(vt)
        c1 = math.cos(theta1)

        def gap(theta: float, c1: float = c1, theta1: float = theta1, vt: float = vt) -> float:
            return c1 + vt * (theta - theta1) - math.cos(theta)

        # g is tangent at θ1 and negative just after it (its curvature is cos θ1 < 0):
        # bracket from the first minimum (sin θ = -ṽ again, θ = 2π - arcsin ṽ).
        start = 2.0 * math.pi - math.asin(vt)
        theta2 = brentq(gap, start, theta1 + 2.0 * math.pi, xtol=1e-15, rtol=1e-15)
        span = theta2 - theta1
        out[index] = (math.sin(theta2) - math.sin(theta1) - span * c1 - 0.5 * vt * span * span) / (
            2.0 * math.pi
        )
    return out


def _kinetic(model: Model) -> float:
    c = model.pack()
    return float(kinetic_coefficient(abs(model.drive.velocity), c))


def _normal_cycle(model: Model, amplitude: float | None, cache: dict | None = None):
    """(period [s] or None for a constant N, initial state (y, ẏ) at t = 0); ``cache``
    (a dict) shares the normal motion between models that differ only tangentially."""
    if cache is not None:
        key = (model.replace(tangential=None, friction=None, drive=None), amplitude)
        if key not in cache:
            cache[key] = _normal_cycle(model, amplitude)
        return cache[key]
    from microslip.analysis.free_vibration import free_period
    from microslip.analysis.periodic import periodic_orbit

    params = model.params
    excitation = model.excitation
    if isinstance(excitation, PrescribedPenetration):
        if amplitude is not None:
            raise ValueError("amplitude does not apply with PrescribedPenetration")
        return excitation.period, None
    if excitation is not None:
        if amplitude is not None:
            raise ValueError("amplitude does not apply to a forced normal motion")
        # The normal motion does not depend on the tangential parts: the orbit of the
        # normal model (NotPeriodOneError: the caller falls back to a time average).
        orbit = periodic_orbit(model.replace(tangential=None, friction=None, drive=None))
        return orbit.period, (float(orbit.y0_state[0]), float(orbit.y0_state[1]))
    if amplitude is None:
        raise ValueError("give amplitude=A [m] for the free normal vibration")
    amplitude = check.amplitude(params, amplitude)
    if model.damping is not None or amplitude == 0.0:
        return None, None  # decays to (or stays at) rest: N = m g
    return free_period(params, amplitude), (params.static_deflection - amplitude, 0.0)


def _tangential_stiffness(model: Model) -> float:
    """k_t [N/m]; Mindlin's at the static (or mean prescribed) penetration."""
    if isinstance(model.tangential, TangentialSpring):
        return model.tangential.stiffness
    delta = model.params.static_deflection
    if isinstance(model.excitation, PrescribedPenetration):
        delta = model.excitation.mean
    return model.tangential.ratio * float(elastic_stiffness(delta, model.pack()))


def _start(normal, velocity: float) -> tuple[float, ...]:
    """Body state at a period start (a prescribed penetration sets y, ẏ in :func:`_run`)."""
    y, ydot = (0.0, 0.0) if normal is None else normal
    return (y, ydot, 0.0, velocity, 0.0, 0.0)


def _run(model: Model, state, period: float, rtol: float, t_eval=None):
    from microslip.simulation import simulate

    if isinstance(model.excitation, PrescribedPenetration):
        state = (model.excitation.mean + model.excitation.amplitude, 0.0, *state[2:])
    return simulate(
        model, duration=period, initial_state=state, method="event", rtol=rtol, t_eval=t_eval
    )


def _steady_period(model: Model, period: float, normal, rtol: float):
    """The state at the start of a steady period, found by iterating the period map."""
    velocity = model.drive.velocity
    c = model.pack()
    scale = max(model.params.mass * model.params.g * c[MU_STATIC], 1e-300)
    # Start on the kinetic limit, f = μ_k N(0) sgn v, as if slipping: the first slip
    # then erases the start, even at drive speeds that would need many periods to load
    # a relaxed spring.
    if normal is None:  # prescribed penetration
        y, ydot = model.excitation.mean + model.excitation.amplitude, 0.0
    else:
        y, ydot = normal
    limit = float(kinetic_coefficient(0.0, c) * normal_force(0.0, y, ydot, c))
    spring = math.copysign(limit, velocity) if velocity != 0.0 else 0.0
    stiffness = _tangential_stiffness(model)
    shift = -spring / stiffness if stiffness > 0 else 0.0
    state = (*_start(normal, velocity)[:4], shift, spring)
    for _ in range(_MAX_PERIODS):
        run = _run(model, state, period, rtol)
        end = (
            float(run.y[-1]),
            float(run.ydot[-1]),
            0.0,
            velocity,
            float(run.u[-1] - run.x[-1]),
            float(run.spring_force[-1]),
        )
        if abs(end[5] - state[5]) <= 1e-9 * scale:
            return end
        state = end
    raise RuntimeError(f"no periodic tangential steady state within {_MAX_PERIODS} periods")


def _quadrature_nodes(period: float, switches: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights [s] on [0, T], split at the switching instants."""
    bounds = np.unique(
        np.concatenate([[0.0], switches[(switches > 0) & (switches < period)], [period]])
    )
    nodes, weights = [], []
    for a, b in itertools.pairwise(bounds):
        parts = max(1, math.ceil((b - a) * _PIECES_PER_PERIOD / period))
        edges = np.linspace(a, b, parts + 1)
        for lo, hi in itertools.pairwise(edges):
            half = 0.5 * (hi - lo)
            nodes.append(lo + half * (_GAUSS_NODES + 1.0))
            weights.append(half * _GAUSS_WEIGHTS)
    return np.concatenate(nodes), np.concatenate(weights)


def _max_normal_rate(model: Model, t, y, ydot) -> float:
    """max|dN/dt| [N/s] from uniform samples, refined by the parabola through the
    largest sample and its neighbours."""
    c = model.pack()
    rate = np.abs(
        [float(normal_force_rate(a, b, d, c)) for a, b, d in zip(t, y, ydot, strict=True)]
    )
    k = int(np.argmax(rate))
    if 0 < k < rate.size - 1:
        left, mid, right = rate[k - 1], rate[k], rate[k + 1]
        curvature = left - 2.0 * mid + right
        if curvature < 0.0:
            return float(mid - 0.125 * (right - left) ** 2 / curvature)
    return float(rate[k])


def _mean_normal_force(model: Model) -> float:
    """<N> [N]: m g for any bounded motion of the body (identity 1); the period average
    of the law for a prescribed penetration (Gauss–Legendre, 64 x 8 nodes)."""
    from microslip.simulation import simulate

    if not isinstance(model.excitation, PrescribedPenetration):
        return model.params.mass * model.params.g
    period = model.excitation.period
    nodes, weights = _quadrature_nodes(period, np.empty(0))
    normal_model = model.replace(drive=None, tangential=None, friction=None)
    run = simulate(normal_model, force=0.0, duration=period, t_eval=nodes)
    return float(weights @ run.N) / period


def effective_friction(
    model: Model, *, amplitude: float | None = None, rtol: float = 1e-11, _cycles=None
) -> EffectiveFriction:
    """μ_eff = <F_t>/<N> [-] of a body driven at ``model.drive.velocity`` in the steady state.

    Parameters
    ----------
    model : Model
        With ``drive=PrescribedVelocity(v)``; any normal part; a rigid or compliant
        tangential contact; Coulomb or StaticKinetic friction (Stribeck: rigid only).
    amplitude : float, optional
        Free normal vibration only: A = y0 - y_min [m] of the undamped free orbit.
    rtol : float
        Relative tolerance of the event method (default 1e-11).

    Returns
    -------
    EffectiveFriction
    """
    if not isinstance(model, Model):
        raise ValueError(f"model must be a microslip.Model, got {type(model).__name__}")
    require(
        model,
        "effective_friction",
        allowed={
            "tangential": (None, TangentialSpring, MindlinSpring),
            "friction": (None, StaticKinetic, Stribeck),
            "drive": (PrescribedVelocity,),
        },
        instead="drive the body with ms.PrescribedVelocity(v) (or use ms.simulate)",
    )
    rtol = check.tolerance("rtol", rtol, check.RTOL_RANGE)
    mu_k = _kinetic(model)
    weight = model.params.mass * model.params.g
    from microslip.analysis.periodic import NotPeriodOneError

    if not model.is_compliant:  # identity 6: the body never sticks, F_t = μ_k(|v|) N
        mean_n = _mean_normal_force(model)
        return EffectiveFriction(
            mu_k, mu_k, 1.0, math.nan, mu_k * mean_n, mean_n, 0.0, math.nan, "closed_form", 0.0
        )
    try:
        period, normal = _normal_cycle(model, amplitude, _cycles)
    except NotPeriodOneError as error:
        return _time_average(model, mu_k, rtol, str(error))
    if period is None:  # constant N = m g: steady slip at the kinetic limit
        return EffectiveFriction(
            mu_k, mu_k, 1.0, math.nan, mu_k * weight, weight, 0.0, math.nan, "closed_form", 0.0
        )
    start = _steady_period(model, period, normal, rtol)
    first = _run(model, start, period, rtol)
    nodes, weights = _quadrature_nodes(period, first.event_t)
    samples = np.linspace(0.0, period, _RATE_SAMPLES + 1)
    run = _run(model, start, period, rtol, t_eval=np.sort(np.concatenate([nodes, samples])))
    is_node = np.isin(run.t, nodes)
    mean_n = float(weights @ run.N[is_node]) / period
    sign = math.copysign(1.0, model.drive.velocity) if model.drive.velocity != 0 else 1.0
    mean_f = float(weights @ (-sign * run.Ft[is_node])) / period
    stuck = (run.direction == 0) & (run.N > 0)
    stick = float(weights @ stuck[is_node]) / period
    uniform = ~is_node
    rate = _max_normal_rate(model, run.t[uniform], run.y[uniform], run.ydot[uniform])
    v_tilde = (
        _tangential_stiffness(model) * abs(model.drive.velocity) / (mu_k * rate)
        if rate > 0 and mu_k > 0
        else math.nan
    )
    mu_eff = mean_f / mean_n if mean_n > 0 else math.nan
    return EffectiveFriction(
        mu_eff,
        mu_k,
        mu_eff / mu_k if mu_k > 0 else math.nan,
        v_tilde,
        mean_f,
        mean_n,
        stick,
        period,
        "exact",
        10.0 * rtol,
    )


def _time_average(model: Model, mu_k: float, rtol: float, reason: str) -> EffectiveFriction:
    """μ_eff from a long run when the forced normal motion is not period-1."""
    from microslip.simulation import simulate

    period = model.excitation.period
    warnings.warn(f"{reason}; effective friction from a time average", RuntimeWarning, stacklevel=3)
    start, blocks = _FALLBACK_PERIODS * period, 8
    t = np.linspace(start, start + _FALLBACK_PERIODS * period, 64 * _FALLBACK_PERIODS + 1)
    run = simulate(model, duration=float(t[-1]), method="event", rtol=rtol, t_eval=t)
    sign = math.copysign(1.0, model.drive.velocity) if model.drive.velocity != 0 else 1.0
    f, n = -sign * run.Ft, run.N
    per_block = np.array_split(np.arange(t.size - 1), blocks)
    ratios = [
        np.trapezoid(f[b[0] : b[-1] + 2], t[b[0] : b[-1] + 2])
        / np.trapezoid(n[b[0] : b[-1] + 2], t[b[0] : b[-1] + 2])
        for b in per_block
    ]
    mu_eff = float(np.trapezoid(f, t) / np.trapezoid(n, t))
    error = float(np.std(ratios) / math.sqrt(blocks) / abs(mu_eff)) if mu_eff else math.nan
    return EffectiveFriction(
        mu_eff,
        mu_k,
        mu_eff / mu_k,
        math.nan,
        float(np.mean(f)),
        float(np.mean(n)),
        math.nan,
        period,
        "time_average",
        error,
    )


_VARIABLES = {
    "mu_eff": ("1", "effective friction coefficient <F_t>/<N>"),
    "ratio": ("1", "mu_eff / mu_kinetic"),
    "v_tilde": ("1", "dimensionless drive speed k_t v / (mu max|dN/dt|)"),
    "stick_fraction": ("1", "fraction of the period the contact point sticks"),
}


def effective_friction_curve(
    model: Model, velocities: Any, *, amplitude: float | None = None
) -> xr.Dataset:
    """μ_eff over drive speeds v [m/s] (dim "velocity"); ``model`` needs a
    PrescribedVelocity drive, whose velocity each point replaces."""
    velocities = check.real_array("velocities", velocities)
    if velocities.ndim != 1 or velocities.size == 0:
        raise ValueError("velocities must be a non-empty 1-D array [m/s]")
    if not isinstance(model.drive, PrescribedVelocity):
        raise ValueError("effective_friction_curve needs drive=ms.PrescribedVelocity(v)")
    cycles: dict = {}  # one normal motion shared by every speed
    points = [
        effective_friction(
            model.replace(**{"drive.velocity": float(v)}), amplitude=amplitude, _cycles=cycles
        )
        for v in velocities
    ]
    data = {
        name: (
            "velocity",
            np.array([getattr(p, name) for p in points]),
            {"units": unit, "long_name": text},
        )
        for name, (unit, text) in _VARIABLES.items()
    }
    ds = xr.Dataset(
        data,
        coords={
            "velocity": (
                "velocity",
                velocities,
                {"units": "m s-1", "long_name": "drive velocity v"},
            )
        },
        attrs={
            **model.to_attrs(),
            "mu_kinetic": points[0].mu_kinetic,
            "method": ",".join(sorted({p.method for p in points})),
        },
    )
    return ds


def effective_friction_map(
    model: Model, velocities: Any, name: str, values: Any, *, amplitude: float | None = None
) -> xr.Dataset:
    """μ_eff over (``name``, "velocity"): ``name`` a dotted model field (e.g.
    "excitation.amplitude", "tangential.stiffness") or "amplitude" (the free vibration's
    A [m]), ``values`` in its SI unit."""
    values = check.real_array(name, values)
    if values.ndim != 1 or values.size == 0:
        raise ValueError(f"{name} values must be a non-empty 1-D array")
    curves = []
    for value in values:
        if name == "amplitude":
            curves.append(effective_friction_curve(model, velocities, amplitude=float(value)))
        else:
            point = model.replace(**{name: float(value)})
            curves.append(effective_friction_curve(point, velocities, amplitude=amplitude))
    unit = "m" if name == "amplitude" else model.unit(name)
    ds = xr.concat(curves, dim=name, combine_attrs="override")
    ds = ds.assign_coords({name: (name, values, {"units": unit})})
    ds.attrs.update(model.to_attrs())
    return ds
