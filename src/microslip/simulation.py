"""``simulate``: one trajectory of the slider, eqs. (2.2)–(2.5), with exact stick and flight.

Any :class:`~microslip.model.composition.Model` (the paper's by default): the normal
law is the composed one of :mod:`microslip.model.normal` (damping, excitation).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from microslip import budget
from microslip import validation as check
from microslip.integrators import integrate
from microslip.model.coefficients import MU_STATIC
from microslip.model.composition import Model, as_model
from microslip.model.contact import potential_energy
from microslip.model.excitation import PrescribedPenetration
from microslip.model.parameters import POSITION_LIMIT, Parameters
from microslip.model.samples import state_array
from microslip.model.system import FT, XDOT, YDOT, U, X, Y, slip_directions
from microslip.results import SimulationResult
from microslip.validation import DEFAULT_RK4_STEPS_PER_PERIOD, RK4_MAX_STEP_FRACTION

__all__ = [
    "DEFAULT_RK4_STEPS_PER_PERIOD",
    "RK4_MAX_STEP_FRACTION",
    "initial_state_from_amplitude",
    "simulate",
]

# Defaults of the event method: x(t) within ~5e-9 relative of an independent integration.
DEFAULT_RTOL = 1e-11
DEFAULT_ATOL = 1e-13


def initial_state_from_amplitude(params: Parameters, amplitude: float) -> tuple[float, ...]:
    """The paper's initial state for amplitude A = y0 - y_min [m] (Sec. 3–4).

    The slider starts at rest at its highest point: y = y0 - A, ẏ = 0, x = ẋ = 0,
    and a relaxed tangential spring (u = x = 0, f = 0): the full state layout of
    :mod:`microslip.model.system`.
    """
    return tuple(state_array(params.static_deflection - amplitude, 0.0))


def natural_tolerances(params: Parameters, atol: float, mu: float | None = None) -> np.ndarray:
    """Absolute tolerances per component: ``atol`` times the natural scales.

    The scales are those of docs/model-facts.md, fact 7, with μ = ``params.mu`` unless
    given (the static coefficient of a friction law with its own; 1 when 0):
    y: y0 [m], ẏ: y0 ω0 [m/s], x: μ y0 [m], ẋ: μ y0 ω0 [m/s], u: μ y0 [m],
    f: μ m g [N].
    """
    y0 = params.static_deflection
    w0 = params.natural_angular_frequency
    mu = params.mu if mu is None else mu
    mu = mu if mu > 0 else 1.0
    weight = params.mass * params.g
    return atol * np.array([y0, y0 * w0, mu * y0, mu * y0 * w0, mu * y0, mu * weight])


def _checked_initial_state(params: Parameters, initial_state) -> tuple[float, ...]:
    """(y, ẏ, x, ẋ) as floats, with a normal motion no larger than A = 1e3 y0,
    |x| <= 1e6 m and |ẋ| <= 1e6 g T0."""
    values = check.real_array("initial_state", initial_state)
    if values.size not in (4, 6):
        raise ValueError(
            "initial_state must be (y, ydot, x, xdot) or (y, ydot, x, xdot, u, f), got "
            f"{values.size} values"
        )
    y, ydot = float(values[0]), float(values[1])
    y0 = params.static_deflection
    top = y0 - params.max_amplitude
    # Bound y first so that V(y) = S c_n y^(m2+1)/(m2+1) - m g y stays finite.
    if abs(y - y0) > params.max_amplitude:
        raise ValueError(
            f"initial_state y={y!r} m is farther than 1e3 y0 = {params.max_amplitude:.6g} m "
            f"from y0 = {y0:.6g} m"
        )
    energy = 0.5 * params.mass * ydot * ydot + float(potential_energy(params, y))
    if energy > float(potential_energy(params, top)):
        raise ValueError(
            f"initial_state (y={y!r} m, ydot={ydot!r} m/s) has a normal motion larger than "
            f"the supported amplitude 1e3 y0 = {params.max_amplitude:.6g} m"
        )
    x, xdot = float(values[2]), float(values[3])
    if abs(x) > POSITION_LIMIT:
        raise ValueError(
            f"initial_state x={x!r} m exceeds the supported |x| <= {POSITION_LIMIT:g} m"
        )
    if abs(xdot) > params.max_velocity:
        raise ValueError(
            f"initial_state xdot={xdot!r} m/s exceeds the supported 1e6 g T0 = "
            f"{params.max_velocity:.6g} m/s"
        )
    if values.size == 6:
        u, spring = float(values[4]), float(values[5])
        if abs(u) > POSITION_LIMIT:
            raise ValueError(
                f"initial_state u={u!r} m exceeds the supported |u| <= {POSITION_LIMIT:g} m"
            )
        if abs(spring) > params.max_force:
            raise ValueError(
                f"initial_state f={spring!r} N exceeds the supported 1e6 m g = "
                f"{params.max_force:.6g} N"
            )
        return (y, ydot, x, xdot, u, spring)
    return (y, ydot, x, xdot, x, 0.0)


def _initial_state(model: Model, amplitude, initial_state) -> tuple[np.ndarray, float | None]:
    """The validated initial state vector and the amplitude [m] (None if not given).

    Free vibration: exactly one of ``amplitude`` / ``initial_state``. Forced: rest at
    the static deflection y0 unless one is given (``amplitude``: rest at y0 - A).
    Prescribed penetration: y, ẏ carry δ(0), δ̇(0) = 0; no amplitude.
    """
    params = model.params
    excitation = model.excitation
    if isinstance(excitation, PrescribedPenetration):
        if amplitude is not None:
            raise ValueError(
                f"amplitude={amplitude!r} does not apply with PrescribedPenetration: the "
                "penetration starts at delta(0) = mean + amplitude of the excitation"
            )
        delta0 = excitation.mean + excitation.amplitude
        tangential = (0.0, 0.0, 0.0, 0.0)
        if initial_state is not None:
            values = check.real_array("initial_state", initial_state)
            if values.size not in (4, 6):
                raise ValueError(
                    "initial_state must be (y, ydot, x, xdot) or (y, ydot, x, xdot, u, f), "
                    f"got {values.size} values"
                )
            if abs(values[0] - delta0) > 1e-12 * delta0 or values[1] != 0.0:
                raise ValueError(
                    f"initial_state (y={values[0]!r} m, ydot={values[1]!r} m/s) must be the "
                    f"prescribed delta(0) = {delta0!r} m, ydot = 0 with PrescribedPenetration"
                )
            checked = _checked_initial_state(params, (delta0, 0.0, *values[2:]))
            tangential = checked[2:]
        return _with_drive(model, state_array(delta0, 0.0, *tangential)), None
    if excitation is None and (amplitude is None) == (initial_state is None):
        raise ValueError("give exactly one of amplitude or initial_state")
    if amplitude is not None and initial_state is not None:
        raise ValueError("give at most one of amplitude or initial_state")
    if amplitude is not None:
        amplitude = check.amplitude(params, amplitude)
        state = np.array(initial_state_from_amplitude(params, amplitude))
        return _with_drive(model, state), amplitude
    if initial_state is not None:
        return _with_drive(model, np.array(_checked_initial_state(params, initial_state))), None
    # forced: from rest at y0
    return _with_drive(model, state_array(params.static_deflection, 0.0)), None


def _tolerances(model: Model, atol: float, force: float) -> np.ndarray:
    """Absolute tolerances of the event method; the contact point's u, f are constant
    with a rigid tangential contact and are left out of the error norm (atol = inf)."""
    out = natural_tolerances(model.params, atol, model.pack(force)[MU_STATIC])
    if not model.is_compliant:
        out[[U, FT]] = np.inf
    return out


def _with_drive(model: Model, state: np.ndarray) -> np.ndarray:
    """``state`` with ẋ = v under a kinematic drive (the body moves at v from t = 0)."""
    if model.is_kinematic:
        if state[XDOT] not in (0.0, model.drive.velocity):
            raise ValueError(
                f"initial_state xdot={state[XDOT]!r} m/s conflicts with the prescribed "
                f"velocity drive.velocity={model.drive.velocity!r} m/s"
            )
        state[XDOT] = model.drive.velocity
    if not model.is_compliant and (state[FT] != 0.0 or state[U] != state[X]):
        raise ValueError(
            "initial_state u, f apply to a compliant tangential contact only (with a rigid "
            "one give (y, ydot, x, xdot))"
        )
    return state


def simulate(
    model_or_params: Model | Parameters | None = None,
    *,
    force: float | None = None,
    duration: float,
    amplitude: float | None = None,
    initial_state: Sequence[float] | None = None,
    method: str = "event",
    dt: float | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    t_eval: Sequence[float] | np.ndarray | None = None,
    save_every: int = 1,
    allow_large: bool = False,
) -> SimulationResult:
    """Simulate the slider under a constant tangential force.

    Parameters
    ----------
    model_or_params : Model or Parameters, optional
        The model (:class:`microslip.Model`: contact, damping, excitation) or its
        constants alone (the paper's model); the paper's data by default.
    force : float, optional
        Constant tangential drive F [N] (Sec. 4), |F| <= ``params.max_force`` = 1e6 m g;
        F < 0 pushes the slider towards -x (backward sliding; with an ``initial_state``
        sliding forward, a reversal). Required when the model has no ``drive``; refused
        when it has one (the drive sets the tangential loading).
    duration : float
        Simulated time [s] from t = 0, at least 1e-6 T0; the output ends exactly at
        ``duration``.
    amplitude : float, optional
        A = y0 - y_min [m] in [0, ``params.max_amplitude`` = 1e3 y0]: start at rest at
        the highest point y = y0 - A (the paper's initial conditions). Without
        excitation give this or ``initial_state``; with a harmonic force or base motion
        both are optional (default: rest at the static deflection y0, ẏ = 0); refused
        with a prescribed penetration (the motion starts at δ(0) = δ_m + Δ).
    initial_state : (y [m], ẏ [m/s], x [m], ẋ [m/s][, u [m], f [N]]), optional
        An explicit initial state instead of ``amplitude``; its normal motion must be
        no larger than that of A = 1e3 y0 (normal energy at most that of rest at
        y = y0 - 1e3 y0), |x| <= 1e6 m and |ẋ| <= ``params.max_velocity`` = 1e6 g T0
        (x enters no force: x0 only shifts the output). With a prescribed penetration
        y, ẏ must be δ(0), 0. The contact point u and spring force f of a compliant
        tangential contact default to u = x, f = 0 (relaxed); with a prescribed velocity
        ẋ is v.
    method : {"event", "rk4"}
        ``"event"``: adaptive Dormand–Prince 8(5,3) (DOP853) with every switching instant
        located and the integration restarted there. ``"rk4"``: the paper's fixed-step
        classical Runge–Kutta on the grid k·dt, with switching instants located inside
        the step so it keeps 4th order through stick–slip and loss of contact.
    dt : float, optional
        RK4 step [s]; default T/200 and at most T/10, T = min(T0, excitation period)
        (T0 = 1/f0).
    rtol, atol : float, optional
        Tolerances of ``"event"`` (defaults 1e-11 and 1e-13): relative, in [1e-14, 1e-2],
        and absolute in units of the natural scales y0, y0 ω0, μ y0, μ y0 ω0, in
        [1e-16, 1e-2]. Refused with ``"rk4"`` (a fixed step has no tolerance).
    t_eval : array, optional
        Output times [s] in [0, duration], non-decreasing; each is computed by a step
        of the method from the last step boundary (same accuracy as the steps).
    save_every : int
        Without ``t_eval``: keep every n-th step boundary (step ends and switching
        instants), plus t = 0 and t = duration.
        :func:`microslip.budget.default_save_every` gives the n that bounds the output.
    allow_large : bool
        Run even when the estimated run time exceeds 10 minutes or the estimated memory
        half of the available memory (:mod:`microslip.budget`); otherwise such a run is
        refused up front with :class:`microslip.budget.WorkLimitError`.

    Returns
    -------
    SimulationResult
    """
    if not isinstance(model_or_params, (Model, Parameters, type(None))):
        raise ValueError(
            "model_or_params must be a microslip.Model or microslip.Parameters, got "
            f"{type(model_or_params).__name__}"
        )
    model = as_model(model_or_params)
    params = model.params
    force = model.resolve_force(force)
    duration = check.duration(duration, params.natural_period)
    method = check.one_of("method", method, ("event", "rk4"))
    save_every = check.positive_int("save_every", save_every)
    if method == "rk4":
        for name, value in (("rtol", rtol), ("atol", atol)):  # None: not given
            if value is not None:
                raise ValueError(f"{name}={value!r} applies to method='event' only; rk4 uses dt")
    rtol = check.tolerance("rtol", DEFAULT_RTOL if rtol is None else rtol, check.RTOL_RANGE)
    atol = check.tolerance("atol", DEFAULT_ATOL if atol is None else atol, check.ATOL_RANGE)
    state0, amplitude = _initial_state(model, amplitude, initial_state)

    # The step must resolve the faster of the contact vibration and the excitation.
    period = budget.shortest_period(model)
    if method == "rk4":
        dt = period / DEFAULT_RK4_STEPS_PER_PERIOD if dt is None else dt
        dt = check.real("dt", dt, minimum=0.0, strict=True)
        check.rk4_step(dt, period)
    elif dt is not None:
        raise ValueError("dt applies to method='rk4' only; method='event' adapts its step")

    if t_eval is not None:
        t_eval = check.real_array("t_eval", t_eval)
        if np.any(np.diff(t_eval) < 0):
            raise ValueError("t_eval must be non-decreasing")
        if t_eval[0] < 0.0 or t_eval[-1] > duration:
            raise ValueError(f"t_eval must lie in [0, duration={duration!r}] s")
    if not isinstance(allow_large, bool):
        raise ValueError(f"allow_large must be True or False, got {allow_large!r}")
    estimate = budget.estimate_simulation(
        model, duration=duration, method=method, dt=dt, rtol=rtol,
        n_t_eval=None if t_eval is None else t_eval.size, save_every=save_every,
    )  # fmt: skip
    budget.check(estimate, allow_large=allow_large)

    raw = integrate(
        method,
        model.pack(force),
        state0,
        0.0,
        duration,
        dt=dt or 0.0,
        h_initial=period / DEFAULT_RK4_STEPS_PER_PERIOD,
        h_max=period / 8.0,
        rtol=rtol,
        atol=_tolerances(model, atol, force),
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
        y=raw.states[:, Y],
        ydot=raw.states[:, YDOT],
        x=raw.states[:, X],
        xdot=raw.states[:, XDOT],
        u=raw.states[:, U],
        spring_force=raw.states[:, FT],
        direction=slip_directions(raw.direction),
        event_t=raw.event_t,
        event_kind=raw.event_kind,
        event_states=raw.event_states,
        settings=settings,
        model=model,
    )
