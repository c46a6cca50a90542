"""Effective friction by time average: μ_eff = ∫F_t dt / ∫N dt over a window of a
simulation (docs/theory/friction_reduction.md), for what the exact path of
:mod:`microslip.analysis.effective_friction` does not cover (force drives, a forced
response that is not period-1).

``simulate(method="event")`` runs past a transient; each integral is a Gauss–Legendre
sum on the pieces between the recorded switching instants (exact to the integration
tolerance where the response is smooth). The error estimate is the standard error of
the ratio ΣF_b/ΣN_b over ``blocks`` equal sub-windows b (the spread of F_b - μ_eff N_b).
F_t is positive along the drive: -Ft sgn(drive), with ``SimulationResult.Ft`` the force
on the body (eq. 2.5).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from microslip import validation as check
from microslip.analysis.normal_pieces import GAUSS_NODES, GAUSS_WEIGHTS
from microslip.model.composition import Model
from microslip.model.drive import ConstantForce, HarmonicDrive
from microslip.model.friction import kinetic_coefficient

__all__ = ["time_average"]


def _drive_sign(model: Model) -> float:
    """+1 or -1: the sign of v, F, F0 or v_d of the drive (+1 where it is 0)."""
    field = {ConstantForce: "force", HarmonicDrive: "mean"}.get(type(model.drive), "velocity")
    return -1.0 if getattr(model.drive, field) < 0.0 else 1.0


def _reference_period(model: Model, amplitude: float | None) -> float:
    """The normal period [s]: excitation, free vibration, or 1/f0; the harmonic drive's
    if longer."""
    from microslip.analysis.free_vibration import free_period

    params = model.params
    if model.excitation is not None:
        period = model.excitation.period
    elif model.damping is None and amplitude:
        period = free_period(params, amplitude)
    else:
        period = params.natural_period
    if isinstance(model.drive, HarmonicDrive):
        period = max(period, 1.0 / model.drive.frequency)
    return period


def time_average(
    model: Model,
    amplitude: float | None,
    *,
    rtol: float,
    transient: float | None,
    window: float | None,
    blocks: int,
) -> dict[str, float]:
    """The fields of :class:`~microslip.analysis.effective_friction.EffectiveFriction`
    but ``method``, by name, from ``simulate(method="event")`` (module docstring); the
    amplitude [m] of a free normal vibration, the options as ``effective_friction``'s."""
    from microslip.simulation import simulate

    blocks = check.positive_int("blocks", blocks)
    if blocks < 2:
        raise ValueError(f"blocks must be >= 2 (the error estimate), got {blocks!r}")
    kwargs: dict[str, Any] = {}
    if model.excitation is None:
        if amplitude is None:
            raise ValueError("give amplitude=A [m] of the free normal vibration")
        kwargs["amplitude"] = check.amplitude(model.params, amplitude)
    elif amplitude is not None:
        raise ValueError(
            f"amplitude={amplitude!r} applies to the free vibration only; the excitation "
            f"{type(model.excitation).__name__} sets the normal motion"
        )
    period = _reference_period(model, amplitude)
    transient = (
        64.0 * period if transient is None else check.real("transient", transient, minimum=0.0)
    )
    window = (
        64.0 * period if window is None else check.real("window", window, minimum=0.0, strict=True)
    )
    end = transient + window
    first = simulate(model, duration=end, method="event", rtol=rtol, **kwargs)
    # Gauss–Legendre pieces: the block edges, 16 pieces per period, every switching instant
    pieces_per_block = max(1, math.ceil(16.0 * window / (blocks * period)))
    edges = np.linspace(transient, end, blocks * pieces_per_block + 1)
    events = first.event_t[(first.event_t > transient) & (first.event_t < end)]
    cuts = np.unique(np.concatenate([edges, events]))
    block = np.minimum(np.searchsorted(edges[::pieces_per_block], cuts[:-1], side="right") - 1,
                       blocks - 1)  # fmt: skip
    half = 0.5 * np.diff(cuts)
    nodes = (0.5 * (cuts[:-1] + cuts[1:]))[:, None] + half[:, None] * GAUSS_NODES[None, :]
    weights = half[:, None] * GAUSS_WEIGHTS[None, :]
    run = simulate(model, duration=end, method="event", rtol=rtol, t_eval=nodes.ravel(), **kwargs)
    shape = nodes.shape
    force = (-_drive_sign(model) * run.Ft).reshape(shape)
    normal = run.N.reshape(shape)
    stuck = ((run.direction == 0) & (run.N > 0)).reshape(shape)
    f_block = np.bincount(block, (weights * force).sum(axis=1), minlength=blocks)
    n_block = np.bincount(block, (weights * normal).sum(axis=1), minlength=blocks)
    mean_f, mean_n = f_block.sum() / window, n_block.sum() / window
    mu_eff = mean_f / mean_n
    c = model.pack()
    speed = abs(model.drive.velocity) if model.is_kinematic else math.inf
    mu_k = float(kinetic_coefficient(speed, c))
    # standard error of the ratio estimator ΣF/ΣN over the blocks (a block may lack contact)
    spread = np.std(f_block - mu_eff * n_block, ddof=1) / (math.sqrt(blocks) * n_block.mean())
    return dict(
        mu_eff=float(mu_eff), mu_kinetic=mu_k, ratio=float(mu_eff / mu_k), v_tilde=math.nan,
        mean_friction_force=float(mean_f), mean_normal_force=float(mean_n),
        stick_fraction=float((weights * stuck).sum() / window) if model.is_compliant else 0.0,
        error=float(spread / abs(mu_eff)) if mu_eff else math.inf, period=float(period),
    )  # fmt: skip
