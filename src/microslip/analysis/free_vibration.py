"""Free normal micro-vibration of the slider, eq. (2.4), Sec. 3 and Figs. 2–3."""

from __future__ import annotations

import numpy as np

from microslip import validation as check
from microslip.analysis import orbit
from microslip.model.capabilities import require
from microslip.model.coefficients import pack
from microslip.model.composition import Model
from microslip.model.contact import potential_energy
from microslip.model.parameters import Parameters

__all__ = ["free_frequency", "free_period", "normal_energy", "turning_points"]

ORBIT_STEPS = 512  # table steps per half period at the stiffest point: error ~1e-13


def _checked(params: Parameters | Model) -> Parameters:
    """The Parameters of the paper's conservative free vibration; a Model with damping or
    an excitation is refused (its normal motion is not the conservative orbit)."""
    if isinstance(params, Model):
        require(
            params, "the free-vibration analysis (free_period, free_frequency, turning_points)",
            allowed={"damping": (None,), "excitation": (None,)},
            instead="it holds for the undamped free vibration only; use microslip.simulate "
            "for a damped decay, microslip.periodic_orbit for a forced one",
        )  # fmt: skip
        return params.params
    if not isinstance(params, Parameters):
        raise ValueError(
            f"params must be a microslip.Parameters or Model, got {type(params).__name__}"
        )
    return params


def _half_orbit(params: Parameters, amplitude: float, steps: int = ORBIT_STEPS):
    c = pack(params, 0.0)
    ys = np.empty(orbit.orbit_capacity(steps))
    yds = np.empty_like(ys)
    summary = np.empty(orbit.O_SIZE)
    if not orbit.build_half_orbit(amplitude, c, steps, ys, yds, summary):
        raise RuntimeError(f"orbit table overflow for amplitude={amplitude!r} m")
    return c, ys, yds, summary


def turning_points(params: Parameters | Model, amplitude: float) -> tuple[float, float]:
    """(y_min, y_max) [m] of the free vibration with amplitude A = y0 - y_min [m].

    0 <= A <= 1e3 y0 (``params.max_amplitude``).
    """
    params = _checked(params)
    amplitude = check.amplitude(params, amplitude)
    y_top = params.static_deflection - amplitude
    if amplitude == 0.0:
        return y_top, y_top
    # The coefficient tuple, as the laws are compiled for it (docs/design.md).
    return y_top, float(orbit.lowest_point(y_top, tuple(pack(params, 0.0))))


def normal_energy(params: Parameters, y: np.ndarray, ydot: np.ndarray) -> np.ndarray:
    """E = ½ m ẏ² + V(y) [J] (docs/model-facts.md, fact 2); constant along a free vibration."""
    ydot = np.asarray(ydot, dtype=float)
    return 0.5 * params.mass * ydot**2 + potential_energy(params, y)


def free_period(params: Parameters | Model, amplitude: float) -> float:
    """Exact period T(A) [s] of the free normal vibration with amplitude A [m].

    Twice the time from the highest point (rest) to the lowest, integrated once with
    fixed 5th-order steps (loss of contact in closed form); A = 0 gives T0 = 1/f0.
    0 <= A <= 1e3 y0 (``params.max_amplitude``).
    """
    params = _checked(params)
    amplitude = check.amplitude(params, amplitude)
    if amplitude == 0.0:
        return params.natural_period
    _c, _ys, _yds, summary = _half_orbit(params, amplitude)
    return 2.0 * float(summary[orbit.O_HALF])


def free_frequency(params: Parameters | Model, amplitude: float) -> float:
    """Frequency 1/T(A) [Hz] of the free normal vibration with amplitude A = y0 - y_min [m].

    Falls as A grows (Sec. 3, Fig. 2b,c); equals f0 in the limit A → 0.
    """
    return 1.0 / free_period(params, amplitude)
