"""The closed-form stick–slip cycle of a body pulled through a spring on a rigid contact
at constant N (docs/theory/stick_slip_drive.md): the reference of
:mod:`microslip.analysis.spring_stick_slip`, which also sizes its runs with it.

    Δ = (μ_s − μ_k) N / k_d,  ω = sqrt(k_d / m),  force drop 2 (μ_s − μ_k) N,
    stick time 2 Δ / v_d,  slip time (2/ω)(π − arctan(Δ ω / v_d)),
    period = stick + slip time,  slip distance = v_d · period.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from microslip import validation as check
from microslip.model.capabilities import require
from microslip.model.composition import Model, as_model
from microslip.model.drive import SpringDrive
from microslip.model.friction import StaticKinetic

__all__ = [
    "ConstantNormalCycle",
    "checked_drive_speed",
    "constant_normal_cycle",
    "cycle_times",
    "friction_coefficients",
]


@dataclass(frozen=True)
class ConstantNormalCycle:
    """Closed-form cycle at constant N (rigid contact, undamped), SI units.

    Attributes: ``period`` = ``stick_time`` + ``slip_time`` [s]; ``force_drop``
    2(μ_s − μ_k)N [N]; ``peak_force`` μ_s N [N], |F| at a slip start; ``slip_distance``
    |v_d| · period [m]; ``peak_velocity`` |v_d| + sqrt(v_d² + Δ²ω²) [m/s];
    ``first_slip_time`` μ_s N / (k_d |v_d|) [s] from a relaxed spring at t = 0.
    """

    period: float
    stick_time: float
    slip_time: float
    force_drop: float
    peak_force: float
    slip_distance: float
    peak_velocity: float
    first_slip_time: float


def friction_coefficients(model: Model) -> tuple[float, float]:
    """(μ_s, μ_k) of the model's friction law (Coulomb: μ, μ)."""
    if model.paper_choice("friction"):
        return model.params.mu, model.params.mu
    return model.friction.mu_static, model.friction.mu_kinetic


def checked_drive_speed(model: Model) -> float:
    """|v_d| [m/s] of the spring drive; v_d = 0 is refused (it never slips)."""
    if model.drive.velocity == 0.0:
        raise ValueError("drive.velocity=0.0 m s-1: a spring drive at rest never slips")
    return abs(model.drive.velocity)


def cycle_times(mass, k, k_d, speed, mu_s, mu_k, normal) -> tuple[float, float, float]:
    """(stick time, slip time, first slip time) [s] of the constant-N closed form."""
    omega = math.sqrt(k_d / mass)
    half = (mu_s - mu_k) * normal / k
    slip = 2.0 / omega * (math.pi - math.atan(half * omega / speed))
    return 2.0 * half / speed, slip, mu_s * normal / (k * speed)


def constant_normal_cycle(
    model: Model, *, normal_force: float | None = None
) -> ConstantNormalCycle:
    """The closed-form cycle of a rigid contact at constant N (docs/theory/stick_slip_drive.md).

    Parameters
    ----------
    model : Model
        Rigid tangential contact, Coulomb or StaticKinetic friction, a SpringDrive with
        v_d != 0; its normal motion is not looked at.
    normal_force : float, optional
        N [N] > 0; default m g (at rest, and the mean of any bounded normal motion).

    Returns
    -------
    ConstantNormalCycle
        With μ_s = μ_k (Coulomb) the stick time is 0 and the slip a whole oscillation
        2π/ω: the velocity touches 0 without sticking (sliding, no force drop).
    """
    model = as_model(model)
    require(
        model, "constant_normal_cycle",
        allowed={"friction": (None, StaticKinetic), "drive": (SpringDrive,)},
        instead="it holds for a rigid contact with Coulomb or StaticKinetic friction and "
        "a SpringDrive; use stick_slip_drive for the others",
    )  # fmt: skip
    params = model.params
    normal = params.mass * params.g if normal_force is None else normal_force
    normal = check.real("normal_force", normal, minimum=0.0, strict=True)
    speed = checked_drive_speed(model)
    mu_s, mu_k = friction_coefficients(model)
    k_d = model.drive.stiffness
    stick, slip, first = cycle_times(params.mass, k_d, k_d, speed, mu_s, mu_k, normal)
    omega_half = math.sqrt(k_d / params.mass) * (mu_s - mu_k) * normal / k_d
    return ConstantNormalCycle(
        period=stick + slip,
        stick_time=stick,
        slip_time=slip,
        force_drop=2.0 * (mu_s - mu_k) * normal,
        peak_force=mu_s * normal,
        slip_distance=speed * (stick + slip),
        peak_velocity=speed + math.hypot(speed, omega_half),
        first_slip_time=first,
    )
