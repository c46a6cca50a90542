"""Helpers of :func:`~microslip.analysis.spring_stick_slip.stick_slip_drive` around its one
event simulation: how long to run it, and what to read from the result.

``_estimate`` gives the first slip time and the period [s] of the constant-N closed form
(:mod:`microslip.analysis.stick_slip_closed_form`) that size the run, ``_normal_period``
the period [s] of the normal vibration; ``_slips`` finds the slips (event indices of their
starts and ends) in a :class:`~microslip.results.SimulationResult`, and ``_window`` cuts
one to a time interval [s].
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from microslip.analysis.stick_slip_closed_form import (
    checked_drive_speed,
    cycle_times,
    friction_coefficients,
)
from microslip.model.composition import Model
from microslip.model.excitation import PrescribedPenetration
from microslip.model.system import EVENT_NAMES
from microslip.model.tangential import MindlinSpring, TangentialSpring
from microslip.results import STICK, SimulationResult

_SLIP_START = EVENT_NAMES.index("slip_start")


def _estimate(model: Model) -> tuple[float, float]:
    """(first slip time, period) [s]: the constant-N closed form at the mean normal force,
    the tangential spring of a compliant contact in series with the drive's."""
    params = model.params
    normal = params.mass * params.g
    if isinstance(model.excitation, PrescribedPenetration):
        e = model.excitation
        delta = np.maximum(e.mean + e.amplitude * np.cos(np.linspace(0.0, 2 * np.pi, 256)), 0.0)
        normal = float(np.mean(params.stiffness_coefficient * delta**params.m2))
    k_d = model.drive.stiffness
    k_t = math.inf
    if isinstance(model.tangential, TangentialSpring):
        k_t = model.tangential.stiffness
    elif isinstance(model.tangential, MindlinSpring):
        k_t = model.tangential.ratio * params.contact_stiffness
    k = k_d if k_t == math.inf else k_d * k_t / (k_d + k_t)
    stick, slip, first = cycle_times(
        params.mass, k, k_d, checked_drive_speed(model), *friction_coefficients(model), normal
    )
    return first, stick + slip


def _normal_period(model: Model, amplitude: float | None) -> float:
    """Period [s] of the normal vibration; NaN when N is constant or decays."""
    if model.excitation is not None:
        return model.excitation.period if model.excitation.amplitude > 0.0 else math.nan
    if model.damping is not None or not amplitude:
        return math.nan
    from microslip.analysis.free_vibration import free_period

    return free_period(model.params, amplitude)


def _slips(result: SimulationResult) -> tuple[np.ndarray, np.ndarray]:
    """Event indices of the slips: (starts, ends); an end is the first event at or after
    the start after which the interface is stuck (-1 if it still slips at the end)."""
    # Every step boundary is kept: the sample at an event's time is the state after it.
    index = np.searchsorted(result.t, result.event_t, side="right") - 1
    stuck_after = result.state[index] == STICK
    stuck_before = np.r_[result.state[0] == STICK, stuck_after[:-1]]
    starts = np.flatnonzero((result.event_kind == _SLIP_START) & stuck_before)
    stuck_events = np.flatnonzero(stuck_after)
    ends = np.r_[stuck_events, -1][np.searchsorted(stuck_events, starts)]
    return starts, ends


def _window(result: SimulationResult, t_lo: float, t_hi: float) -> SimulationResult:
    """``result`` restricted to t_lo <= t <= t_hi [s] (samples and events)."""
    keep = (result.t >= t_lo) & (result.t <= t_hi)
    ev = (result.event_t >= t_lo) & (result.event_t <= t_hi)
    names = ("t", "y", "ydot", "x", "xdot", "u", "spring_force", "direction")
    return dataclasses.replace(
        result,
        **{name: getattr(result, name)[keep] for name in names},
        event_t=result.event_t[ev],
        event_kind=result.event_kind[ev],
        event_states=result.event_states[ev],
        settings={**result.settings, "window_s": (t_lo, t_hi)},
    )
