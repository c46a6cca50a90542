"""``simulate``: one trajectory of the slider, eqs. (2.2)–(2.5), with exact stick and flight."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from microslip import validation as check
from microslip.integrators import integrate
from microslip.model.coefficients import pack
from microslip.model.parameters import Parameters
from microslip.results import SimulationResult

__all__ = ["RK4_MAX_STEP_FRACTION", "initial_state_from_amplitude", "simulate"]

# An RK4 step must resolve the contact vibration: at most this fraction of T0 = 1/f0.
RK4_MAX_STEP_FRACTION = 0.1
DEFAULT_RK4_STEPS_PER_PERIOD = 200
# Defaults of the event method: x(t) within ~5e-9 relative of an independent integration.
DEFAULT_RTOL = 1e-11
DEFAULT_ATOL = 1e-13


def initial_state_from_amplitude(params: Parameters, amplitude: float) -> tuple[float, ...]:
    """The paper's initial state for amplitude A = y0 - y_min [m] (Sec. 3–4).

    The slider starts at rest at its highest point: y = y0 - A, ẏ = 0, x = ẋ = 0.
    """
    return (params.static_deflection - amplitude, 0.0, 0.0, 0.0)


def natural_tolerances(params: Parameters, atol: float) -> np.ndarray:
    """Absolute tolerances per component, ``atol`` times the natural scales (REFERENCE fact 7).

    y: y0 [m], ẏ: y0 ω0 [m/s], x: μ y0 [m], ẋ: μ y0 ω0 [m/s] (μ replaced by 1 when 0).
    """
    y0 = params.static_deflection
    w0 = params.natural_angular_frequency
    mu = params.mu if params.mu > 0 else 1.0
    return atol * np.array([y0, y0 * w0, mu * y0, mu * y0 * w0])


def simulate(
    params: Parameters | None = None,
    *,
    force: float,
    duration: float,
    amplitude: float | None = None,
    initial_state: Sequence[float] | None = None,
    method: str = "event",
    dt: float | None = None,
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    t_eval: Sequence[float] | np.ndarray | None = None,
    save_every: int = 1,
) -> SimulationResult:
    """Simulate the slider under a constant tangential force.

    Parameters
    ----------
    params : Parameters, optional
        Model constants; the paper's data by default.
    force : float
        Constant tangential drive F [N] (Sec. 4); F < 0 pushes the slider towards -x
        (backward sliding; with an ``initial_state`` sliding forward, a reversal).
    duration : float
        Simulated time [s] from t = 0; the output ends exactly at ``duration``.
    amplitude : float, optional
        A = y0 - y_min [m] >= 0: start at rest at the highest point y = y0 - A
        (the paper's initial conditions). Give this or ``initial_state``.
    initial_state : (y [m], ẏ [m/s], x [m], ẋ [m/s]), optional
        An explicit initial state instead of ``amplitude``.
    method : {"event", "rk4"}
        ``"event"``: adaptive Dormand–Prince 8(5,3) (DOP853) with every switching instant located
        and the integration restarted there. ``"rk4"``: the paper's fixed-step classical
        Runge–Kutta on the grid k·dt, with switching instants located inside the step so
        it keeps 4th order through stick–slip and loss of contact.
    dt : float, optional
        RK4 step [s]; default T0/200. Must be <= T0/10 (T0 = 1/f0).
    rtol, atol : float
        Tolerances of ``"event"``: relative, and absolute in units of the natural
        scales y0, y0 ω0, μ y0, μ y0 ω0.
    t_eval : array, optional
        Output times [s] in [0, duration], non-decreasing; each is computed by a step
        of the method from the last step boundary (same accuracy as the steps).
    save_every : int
        Without ``t_eval``: keep every n-th step boundary (step ends and switching
        instants), plus t = 0 and t = duration.

    Returns
    -------
    SimulationResult
    """
    params = Parameters() if params is None else params
    if not isinstance(params, Parameters):
        raise ValueError(f"params must be a microslip.Parameters, got {type(params).__name__}")
    force = check.real("force", force)
    duration = check.real("duration", duration, minimum=0.0, strict=True)
    method = check.one_of("method", method, ("event", "rk4"))
    save_every = check.positive_int("save_every", save_every)
    rtol = check.real("rtol", rtol, minimum=0.0, strict=True)
    atol = check.real("atol", atol, minimum=0.0, strict=True)
    if (amplitude is None) == (initial_state is None):
        raise ValueError("give exactly one of amplitude or initial_state")
    if amplitude is not None:
        amplitude = check.real("amplitude", amplitude, minimum=0.0)
        state0 = initial_state_from_amplitude(params, amplitude)
    else:
        values = check.real_array("initial_state", initial_state)
        if values.size != 4:
            raise ValueError(f"initial_state must be (y, ydot, x, xdot), got {values.size} values")
        state0 = tuple(float(v) for v in values)

    period = params.natural_period
    if method == "rk4":
        dt = period / DEFAULT_RK4_STEPS_PER_PERIOD if dt is None else dt
        dt = check.real("dt", dt, minimum=0.0, strict=True)
        if dt > RK4_MAX_STEP_FRACTION * period:
            raise ValueError(
                f"dt={dt!r} s is too large to resolve the contact vibration "
                f"(T0 = {period:.4g} s); use dt <= {RK4_MAX_STEP_FRACTION * period:.4g} s"
            )
    elif dt is not None:
        raise ValueError("dt applies to method='rk4' only; method='event' adapts its step")

    if t_eval is not None:
        t_eval = check.real_array("t_eval", t_eval)
        if np.any(np.diff(t_eval) < 0):
            raise ValueError("t_eval must be non-decreasing")
        if t_eval[0] < 0.0 or t_eval[-1] > duration:
            raise ValueError(f"t_eval must lie in [0, duration={duration!r}] s")

    raw = integrate(
        method,
        pack(params, force),
        state0,
        0.0,
        duration,
        dt=dt or 0.0,
        h_initial=period / DEFAULT_RK4_STEPS_PER_PERIOD,
        h_max=period / 8.0,
        rtol=rtol,
        atol=natural_tolerances(params, atol),
        t_eval=t_eval,
        save_every=save_every,
    )
    settings = {"dt_s": dt, "rtol": rtol if method == "event" else None}
    settings.update({"atol_natural": atol if method == "event" else None})
    settings.update({"n_steps": raw.n_steps, "n_rejected": raw.n_rejected})
    if amplitude is not None:
        settings["amplitude_m"] = amplitude
    return SimulationResult(
        params=params,
        force=force,
        method=method,
        t=raw.t,
        y=raw.states[:, 0],
        ydot=raw.states[:, 1],
        x=raw.states[:, 2],
        xdot=raw.states[:, 3],
        direction=raw.direction,
        event_t=raw.event_t,
        event_kind=raw.event_kind,
        event_states=raw.event_states,
        settings=settings,
    )
