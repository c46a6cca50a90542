"""Effective friction under normal vibration: μ_eff = <F_t>/<N> in the steady state
(docs/theory/friction_reduction.md).

F_t is the friction force the contact transmits, taken positive along the drive: with
the simulation's sign (eq. 2.5, ``SimulationResult.Ft`` is the force on the body) it is
-Ft sgn(drive), the force the drive must supply against friction. μ_eff < μ_k is a
friction reduction.

Exact path (``method="exact"``, picked by ``"auto"`` where it applies): a kinematic drive
(:class:`~microslip.model.drive.PrescribedVelocity`) and a periodic or constant normal
motion: a prescribed penetration (N(t) in closed form), a forced excitation (its stable
period-1 orbit, :func:`microslip.analysis.periodic.periodic_orbit`, read back on its
quintic Hermite nodes as the steady sliding of
:mod:`microslip.analysis.sliding_tables` does), the undamped free vibration of amplitude
A (the table of :mod:`microslip.analysis.orbit`), or a damped free vibration (it decays
to N = m g). The normal motion does not depend on the tangential one: it is computed
once and shared by every drive speed (and by every tangential stiffness or friction
coefficient of a map).

- Rigid tangential contact: the body slides at v all the time, F_t = μ(|v|) N, so
  μ_eff = μ(|v|) exactly for every normal motion (identity 6), also a forced response
  that is not period-1 (its <N> is then m g, identity 1).
- Compliant contact (TangentialSpring, MindlinSpring; Coulomb or StaticKinetic): the
  contact point's stick/slip/flight under the known N(t) is a 1-D problem solved exactly
  over one period (:mod:`microslip.analysis.contact_point`): switching instants by root
  finding to round-off, Gauss–Legendre quadrature between them, the period map iterated
  until the tangential state at the period start repeats.

Time average (``method="time_average"``, picked by ``"auto"`` for the rest: force
drives, a forced response that is not period-1;
:mod:`microslip.analysis.friction_time_average`): ``simulate(method="event")`` after a
transient, μ_eff = ∫F_t dt / ∫N dt over a window, each integral a Gauss–Legendre sum on
the pieces between the recorded switching instants (exact to the integration tolerance
where the response is smooth); the error estimate is the standard error of the ratio
ΣF_b/ΣN_b over ``blocks`` equal sub-windows b (the spread of F_b - μ_eff N_b).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from microslip import validation as check
from microslip.analysis import contact_point as cp
from microslip.analysis import normal_period
from microslip.analysis.friction_time_average import time_average
from microslip.analysis.normal_period import NormalCycle
from microslip.analysis.normal_pieces import CLOSED_FORM, TABLE
from microslip.model.capabilities import require
from microslip.model.coefficients import MU, MU_STATIC, TANGENTIAL_STIFFNESS
from microslip.model.composition import Model
from microslip.model.drive import ConstantForce, HarmonicDrive, PrescribedVelocity, SpringDrive
from microslip.model.friction import StaticKinetic, Stribeck, kinetic_coefficients
from microslip.model.tangential import MindlinSpring, TangentialSpring

__all__ = [
    "EffectiveFriction",
    "effective_friction",
    "effective_friction_curve",
    "effective_friction_map",
]

METHODS = ("auto", "exact", "time_average")
MAX_PERIODS = 1000  # normal periods the period map may take to reach its cycle
# Tolerance of the exact path (root finding to round-off, 8-point Gauss–Legendre on
# pieces of at most T/32 and graded towards contact switches): relative, closed-form N;
# a tabulated orbit adds the error of its interpolation (free: ~1e-13, forced: ~1e-11).
EXACT_ERROR = {CLOSED_FORM: 1e-12, TABLE: 1e-10}


@dataclass(frozen=True)
class EffectiveFriction:
    """The effective friction coefficient of a driven body in the steady state.

    Attributes
    ----------
    mu_eff : float
        <F_t>/<N> [-], F_t the friction force the contact transmits, positive along the
        drive (-Ft sgn(drive) with ``SimulationResult.Ft``, eq. 2.5).
    mu_kinetic : float
        Reference coefficient μ_k [-]: μ_k (Coulomb: μ; StaticKinetic: mu_kinetic), or
        Stribeck's μ(|v|) at the drive speed.
    ratio : float
        μ_eff / μ_k [-]; 1 - ratio is the friction reduction.
    v_tilde : float
        Dimensionless drive speed ṽ = |v| / v_c [-], v_c = max over the contact of
        μ_k Ṅ / k_t, the speed above which a slip never ends (no reduction for ṽ >= 1
        without a jump of N). Constant k_t: ṽ = k_t |v| / (μ_k max dN/dt) (max|dN/dt| for a
        time-symmetric N: prescribed penetration, free vibration). Mindlin, elastic:
        ṽ = λ |v| / (μ_k max dδ/dt). nan for a rigid contact, a constant N, or a time
        average.
    mean_friction_force : float
        <F_t> [N] over the steady cycle (window).
    mean_normal_force : float
        <N> [N] over the steady cycle (window).
    stick_fraction : float
        Fraction of the time [-] the contact point sticks in contact (0 rigid).
    period : float
        Period [s] of the normal motion (nan for a constant N); time average: the
        reference period of the window.
    method : str
        "exact" or "time_average".
    error : float
        Estimated relative error of mu_eff [-]. exact: the tolerance of the root finding
        and quadrature (``EXACT_ERROR``; 0 for a rigid contact or a constant N, where
        μ_eff = μ_k holds exactly), plus the drift of the period map if it found no
        cycle within ``MAX_PERIODS`` periods. time_average: the standard error of the
        ratio of the block sums (module docstring); 0-ish for a periodic response
        averaged over whole periods, large for a transient or chaotic one.
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


# -- points ----------------------------------------------------------------------------------
_FIELDS = (
    "mu_eff", "mu_kinetic", "ratio", "v_tilde", "mean_friction_force", "mean_normal_force",
    "stick_fraction", "error",
)  # fmt: skip


def _check(model: Model, method: str) -> None:
    if not isinstance(model, Model):
        raise ValueError(f"model must be a microslip.Model, got {type(model).__name__}")
    require(
        model, "effective_friction",
        allowed={
            "tangential": (None, TangentialSpring, MindlinSpring),
            "friction": (None, StaticKinetic, Stribeck),
            "drive": (PrescribedVelocity, ConstantForce, HarmonicDrive, SpringDrive),
        },
        instead="give the model a drive, e.g. drive=ms.PrescribedVelocity(v)",
    )  # fmt: skip
    check.one_of("method", method, METHODS)
    if method == "exact" and not model.is_kinematic:
        raise ValueError(
            f"method='exact' needs drive=ms.PrescribedVelocity(v), got "
            f"{type(model.drive).__name__}; use method='time_average'"
        )


def _speeds(model: Model, velocities: Any) -> np.ndarray:
    speeds = check.real_array("velocities", velocities)
    limit = model.params.max_velocity
    if np.any(speeds == 0.0) or np.any(np.abs(speeds) > limit):
        bad = float(speeds[(speeds == 0.0) | (np.abs(speeds) > limit)][0])
        raise ValueError(
            f"drive velocity {bad!r} m s-1 must be nonzero with |v| <= 1e6 g T0 = {limit:.6g} "
            "m s-1 (at v = 0 the contact transmits an undetermined static force)"
        )
    return speeds


def _exact_points(model: Model, cycle: NormalCycle, speeds: np.ndarray) -> dict[str, np.ndarray]:
    """The exact steady state at each drive speed [m/s] on the shared normal ``cycle``."""
    c = model.pack()
    speeds = np.ascontiguousarray(np.abs(speeds))
    mu_k = kinetic_coefficients(speeds, c)
    mean_n = np.full(speeds.size, cycle.mean_normal_force)
    zeros = np.zeros(speeds.size)
    if not model.is_compliant or cycle.pieces is None:  # sliding at v throughout (identity 6)
        return dict(
            mu_eff=mu_k, mu_kinetic=mu_k, ratio=np.ones(speeds.size),
            v_tilde=np.full(speeds.size, math.nan), mean_friction_force=mu_k * mean_n,
            mean_normal_force=mean_n, stick_fraction=zeros, error=zeros,
        )  # fmt: skip
    if isinstance(model.tangential, TangentialSpring):
        kconst, lam = float(c[TANGENTIAL_STIFFNESS]), 0.0
        critical = c[MU] * cycle.rate_max / kconst
    else:
        kconst, lam = 0.0, float(c[TANGENTIAL_STIFFNESS])
        critical = c[MU] * cycle.ratio_max / lam
    out = np.zeros((speeds.size, cp.R_COLUMNS))
    cp.steady_friction(
        speeds, float(c[MU_STATIC]), float(c[MU]), kconst, lam, cycle.pieces, cycle.source,
        cycle.period, MAX_PERIODS, out,
    )  # fmt: skip
    mean_f = out[:, cp.R_FORCE]
    mu_eff = mean_f / mean_n
    v_tilde = speeds / critical if 0.0 < critical < math.inf else np.full(speeds.size, math.nan)
    return dict(
        mu_eff=mu_eff, mu_kinetic=mu_k, ratio=mu_eff / mu_k, v_tilde=v_tilde,
        mean_friction_force=mean_f, mean_normal_force=mean_n,
        stick_fraction=out[:, cp.R_STICK], error=EXACT_ERROR[cycle.kind] + out[:, cp.R_ERROR],
    )  # fmt: skip


def _points(model, speeds, amplitude, method, cache, options):
    """(fields by name over ``speeds``, methods used, period [s]) for a kinematic model.
    ``cache``: normal cycles by (normal model, amplitude)
    (:func:`normal_period.normal_cycles`), filled here as needed."""
    from microslip.analysis.periodic import NotPeriodOneError

    if method != "time_average":
        key = (normal_period.normal_model(model), amplitude)
        if key not in cache:
            cache.update(normal_period.normal_cycles([(model, amplitude)]))
        cycle = cache[key]
        if isinstance(cycle, NotPeriodOneError):
            if model.is_compliant and method == "exact":
                raise ValueError(f"method='exact': {cycle}") from None
            # rigid: μ_eff = μ_k whatever the normal motion; <N> = m g (identity 1)
            weight = model.params.mass * model.params.g
            cycle = None if model.is_compliant else NormalCycle(model.excitation.period, weight)
        if cycle is not None:
            return _exact_points(model, cycle, speeds), {"exact"}, cycle.period
    rows = [
        time_average(model.replace(**{"drive.velocity": float(v)}), amplitude, **options)
        for v in speeds
    ]
    fields = {name: np.array([r[name] for r in rows]) for name in _FIELDS}
    return fields, {"time_average"}, rows[0]["period"]


def effective_friction(
    model: Model,
    *,
    amplitude: float | None = None,
    method: str = "auto",
    rtol: float = 1e-11,
    transient: float | None = None,
    window: float | None = None,
    blocks: int = 8,
) -> EffectiveFriction:
    """μ_eff = <F_t>/<N> [-] of the driven body in the steady state.

    F_t is the friction force the contact transmits, positive along the drive: -Ft
    sgn(drive) with ``SimulationResult.Ft`` (the force on the body, eq. 2.5); sgn(drive)
    is the sign of v (PrescribedVelocity), F (ConstantForce), F0 (HarmonicDrive) or v_d
    (SpringDrive), + where it is 0.

    Parameters
    ----------
    model : Model
        Any normal part; tangential None/Rigid, TangentialSpring or MindlinSpring;
        friction Coulomb, StaticKinetic or Stribeck (rigid only); a drive.
    amplitude : float, optional
        Free normal vibration only (no excitation): A = y0 - y_min [m] at t = 0.
    method : {"auto", "exact", "time_average"}
        "exact": kinematic drive and a periodic or constant normal motion (module
        docstring); "time_average": a simulation; "auto": "exact" where it applies.
    rtol : float
        Relative tolerance of the event method (time average only).
    transient, window : float, optional
        Time average: simulated time [s] discarded first, then averaged; default 64
        reference periods each (the normal period: excitation, free vibration, or 1/f0;
        the harmonic drive's if longer).
    blocks : int
        Time average: sub-windows for the error estimate (>= 2).

    Returns
    -------
    EffectiveFriction
    """
    _check(model, method)
    if method == "time_average" or not model.is_kinematic:
        fields = time_average(
            model, amplitude, rtol=rtol, transient=transient, window=window, blocks=blocks
        )
        return EffectiveFriction(**fields, method="time_average")
    options = dict(rtol=rtol, transient=transient, window=window, blocks=blocks)
    speeds = _speeds(model, [model.drive.velocity])
    fields, methods, period = _points(model, speeds, amplitude, method, {}, options)
    return EffectiveFriction(
        **{name: float(values[0]) for name, values in fields.items()},
        period=float(period), method=methods.pop(),
    )  # fmt: skip


# -- curves and maps -------------------------------------------------------------------------
_VARIABLES = {
    "mu_eff": ("1", "effective friction coefficient <F_t>/<N>"),
    "mu_kinetic": ("1", "reference kinetic friction coefficient mu_k"),
    "ratio": ("1", "mu_eff / mu_k"),
    "v_tilde": ("1", "dimensionless drive speed v / v_c, v_c = max mu_k (dN/dt) / k_t"),
    "stick_fraction": ("1", "fraction of the time the contact point sticks"),
    "mean_friction_force": ("N", "mean friction force <F_t> along the drive"),
    "mean_normal_force": ("N", "mean normal force <N>"),
    "error": ("1", "estimated relative error of mu_eff"),
}
_VELOCITY = {"units": "m s-1", "long_name": "drive velocity v"}


def _kinematic(model: Model, method: str) -> None:
    _check(model, method)
    if not model.is_kinematic:
        raise ValueError(
            f"effective_friction_curve needs drive=ms.PrescribedVelocity(v) (its velocity is "
            f"the swept axis), got drive={type(model.drive).__name__}"
        )


def _dataset(fields, dims, coords, model, methods, period) -> xr.Dataset:
    data = {
        name: (dims, np.asarray(fields[name]), {"units": unit, "long_name": text})
        for name, (unit, text) in _VARIABLES.items()
    }
    data["period"] = (
        dims[:-1], np.asarray(period), {"units": "s", "long_name": "period of the normal motion"},
    )  # fmt: skip
    attrs = {**model.to_attrs(), "method": ",".join(sorted(methods))}
    return xr.Dataset(data, coords=coords, attrs=attrs)


def effective_friction_curve(
    model: Model, velocities: Any, *, amplitude: float | None = None, method: str = "auto"
) -> xr.Dataset:
    """μ_eff over drive speeds (dim "velocity" [m s-1]); the normal motion is computed once.

    ``model`` needs ``drive=PrescribedVelocity`` (each speed replaces its velocity);
    ``velocities`` [m/s] nonzero. Variables (all over "velocity"): mu_eff, mu_kinetic,
    ratio, v_tilde, stick_fraction, error [1], mean_friction_force, mean_normal_force [N]
    (:class:`EffectiveFriction`); ``period`` [s] a scalar. Attributes: the model's
    (``Model.to_attrs``) and ``method`` ("exact" or "time_average").
    """
    _kinematic(model, method)
    speeds = _speeds(model, velocities)
    fields, methods, period = _points(model, speeds, amplitude, method, {}, _DEFAULTS)
    coords = {"velocity": ("velocity", speeds, _VELOCITY)}
    return _dataset(fields, ("velocity",), coords, model, methods, period)


_DEFAULTS = dict(rtol=1e-11, transient=None, window=None, blocks=8)


def effective_friction_map(
    model: Model,
    velocities: Any,
    name: str,
    values: Any,
    *,
    amplitude: float | None = None,
    method: str = "auto",
) -> xr.Dataset:
    """μ_eff over (``name``, "velocity"): a curve per value of a second axis.

    ``name`` is a dotted model field ("excitation.amplitude", "tangential.stiffness",
    "friction.mu_static", "damping.ratio", "mu", ...) or "amplitude", the free
    vibration's A [m]; ``values`` in its SI unit. Each value's normal motion is computed
    once (and shared between values that change only the tangential side). Variables as
    :func:`effective_friction_curve`, dims (``name``, "velocity"); ``period`` over
    ``name``.
    """
    _kinematic(model, method)
    speeds = _speeds(model, velocities)
    if not isinstance(name, str):
        raise ValueError(f"name must be a model field name or 'amplitude', got {name!r}")
    if name == "amplitude":
        unit, text = "m", "free normal vibration amplitude A = y0 - y_min"
    else:
        if model.canonical_name(name) == "drive.velocity":
            raise ValueError("drive.velocity is the velocity axis; choose another field")
        unit, text = model.unit(name), name
    values = check.real_array(name, values)
    rows, methods, periods = [], set(), []
    points = [
        (model, float(value)) if name == "amplitude"
        else (model.replace(**{name: float(value)}), amplitude)
        for value in values
    ]  # fmt: skip
    # Each distinct normal motion once, side by side (shared by the rows it serves).
    cache = {} if method == "time_average" else normal_period.normal_cycles(points)
    for point, amp in points:
        fields, used, period = _points(point, speeds, amp, method, cache, _DEFAULTS)
        rows.append(fields)
        methods |= used
        periods.append(period)
    fields = {key: np.stack([r[key] for r in rows]) for key in _VARIABLES}
    coords = {
        name: (name, values, {"units": unit, "long_name": text}),
        "velocity": ("velocity", speeds, _VELOCITY),
    }
    return _dataset(fields, (name, "velocity"), coords, model, methods, np.array(periods))
