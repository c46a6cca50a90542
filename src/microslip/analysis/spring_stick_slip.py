"""Stick–slip of a body pulled through a spring, F = k_d (v_d t − x).

See docs/theory/stick_slip_drive.md.

:func:`stick_slip_drive` simulates a model whose drive is a
:class:`~microslip.model.drive.SpringDrive` until the stick–slip is established and
returns its cycle statistics; :func:`stick_slip_drive_map` repeats it over drive
velocities and normal vibration amplitudes;
:func:`~microslip.analysis.stick_slip_closed_form.constant_normal_cycle` is the closed
form for a rigid contact at constant N (undamped, μ_s >= μ_k), derived on that page:

    Δ = (μ_s − μ_k) N / k_d,  ω = sqrt(k_d / m),  force drop 2 (μ_s − μ_k) N,
    stick time 2 Δ / v_d,  slip time (2/ω)(π − arctan(Δ ω / v_d)),
    period = stick + slip time,  slip distance = v_d · period.

A *slip* starts where the interface (the body on a rigid contact, the contact point on a
compliant one) switches from stick to slip (event ``slip_start`` while stuck) and ends
where it next sticks (``stick_start``, or a compliant point sticking at touchdown). A
*cycle* runs from one slip start to the next. F is the drive spring's force on the body.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from microslip import validation as check
from microslip.analysis.spring_stick_slip_run import _estimate, _normal_period, _slips, _window
from microslip.model.capabilities import require
from microslip.model.composition import Model, as_model
from microslip.model.drive import SpringDrive
from microslip.model.friction import StaticKinetic, Stribeck
from microslip.model.tangential import MindlinSpring, TangentialSpring
from microslip.results import STICK, SimulationResult

__all__ = [
    "DriveCycle",
    "stick_slip_drive",
    "stick_slip_drive_map",
]

STICK_SLIP = "stick-slip"
SLIDING = "sliding"

_ALLOWED = {
    "tangential": (None, TangentialSpring, MindlinSpring),
    "friction": (None, StaticKinetic, Stribeck),
    "drive": (SpringDrive,),
}
_INSTEAD = (
    "give the model drive=ms.SpringDrive(stiffness, velocity); microslip.simulate runs any drive"
)
# Run length: the estimated first slip plus the cycles wanted, times _MARGIN; a run with
# too few cycles is repeated _GROWTH times longer, at most _ATTEMPTS times.
_MARGIN = 1.3
_GROWTH = 2.0
_ATTEMPTS = 6
_SLIDING_SPANS = 4.0  # sliding: no stick during this many estimated periods at the end
_HISTORY = 3  # cycles (and at least as many estimated periods) kept in the history


@dataclass(frozen=True)
class DriveCycle:
    """The established spring-driven motion (SI units; ``*_std``: standard deviations).

    Attributes
    ----------
    regime : "stick-slip", or "sliding" when the interface no longer sticks (then the
        cycle quantities are NaN and ``note`` says since when it slides)
    period, period_std : time between consecutive slip starts [s]
    force_drop, force_drop_std : sgn(v_d) (F at a slip start − F at its end) [N]
    peak_force : mean |F| at the slip starts [N]
    slip_distance, slip_distance_std : body displacement from a slip start to its end
        [m] (a compliant contact: the body also moves while the point sticks, and may
        move back while it slips as the spring relaxes with a falling N)
    slip_time, stick_time : mean durations of the slips and of the sticks between [s]
    mean_velocity : mean body velocity over the cycles used [m/s]
    normal_period : period of the normal vibration [s]; NaN when N does not vibrate
    slips_per_normal_period : normal_period / period [1]; NaN without vibration
    cycles : number of cycles averaged (every complete one after the transient)
    history : the simulation over the last cycles, for plots
    note : what the numbers cover, in one line
    """

    regime: str
    period: float
    period_std: float
    force_drop: float
    force_drop_std: float
    peak_force: float
    slip_distance: float
    slip_distance_std: float
    slip_time: float
    stick_time: float
    mean_velocity: float
    normal_period: float
    slips_per_normal_period: float
    cycles: int
    history: SimulationResult
    note: str

    @property
    def is_stick_slip(self) -> bool:
        return self.regime == STICK_SLIP


def stick_slip_drive(
    model: Model,
    *,
    amplitude: float | None = None,
    cycles: int = 10,
    transient_cycles: int = 3,
    method: str = "event",
) -> DriveCycle:
    """The established stick–slip of a spring-driven model and its cycle statistics.

    Parameters
    ----------
    model : Model
        Its drive a :class:`~microslip.model.drive.SpringDrive` with v_d != 0; any
        tangential contact (rigid, TangentialSpring, MindlinSpring), friction law
        (Coulomb, StaticKinetic, Stribeck) and normal motion.
    amplitude : float, optional
        A = y0 − y_min [m] of the start at rest at y0 − A, as in
        :func:`microslip.simulate`; default: rest at y0 for a free vibration (N = m g
        throughout), ``simulate``'s default start with an excitation.
    cycles : int
        At least this many established cycles (slip start to slip start) are
        averaged, >= 1.
    transient_cycles : int
        Cycles discarded first, >= 0; when the cycles are much shorter than the
        constant-N estimate (e.g. one slip per normal period), as many estimated periods.
    method : {"event", "rk4"}
        Method of :func:`microslip.simulate` (its default tolerances or step).

    Returns
    -------
    DriveCycle

    Notes
    -----
    The run lasts 1.3 (first slip + (transient_cycles + cycles + 1) periods) of the
    constant-N closed form at the mean normal force (:func:`constant_normal_cycle`, a
    compliant contact's spring in series with the drive's); with too few cycles it is
    repeated twice as long, at most six times. "sliding": too few cycles and no stick
    during the last four estimated periods. The cost is that one event simulation:
    ~100 steps per normal period with a normal vibration, a few per stick otherwise.
    """
    model = as_model(model)
    require(model, "stick_slip_drive", allowed=_ALLOWED, instead=_INSTEAD)
    cycles = check.positive_int("cycles", cycles)
    if isinstance(transient_cycles, bool) or not isinstance(transient_cycles, (int, np.integer)):
        raise ValueError(f"transient_cycles must be an integer >= 0, got {transient_cycles!r}")
    if transient_cycles < 0:
        raise ValueError(f"transient_cycles must be an integer >= 0, got {transient_cycles!r}")
    transient_cycles = int(transient_cycles)
    method = check.one_of("method", method, ("event", "rk4"))
    first, period_est = _estimate(model)
    if model.excitation is None and amplitude is None:
        amplitude = 0.0
    normal_period = _normal_period(model, amplitude)
    wanted = transient_cycles + cycles + 1
    duration = _MARGIN * (first + wanted * period_est)
    if not math.isnan(normal_period):
        duration += 2.0 * normal_period
    from microslip.simulation import simulate

    for _attempt in range(_ATTEMPTS):
        result = simulate(model, duration=duration, amplitude=amplitude, method=method)
        starts, ends = _slips(result)
        if starts.size >= wanted:
            t_starts = result.event_t[starts]
            t_min = max(t_starts[transient_cycles], first + transient_cycles * period_est)
            used = min(int(np.searchsorted(t_starts, t_min)), starts.size - 1 - cycles)
            return _statistics(model, result, starts[used:], ends[used:], period_est, normal_period)
        stuck = np.flatnonzero(result.state == STICK)
        last_stick = result.t[stuck[-1]] if stuck.size else 0.0
        if starts.size and result.t[-1] - last_stick > _SLIDING_SPANS * period_est:
            return _sliding(result, last_stick, period_est, normal_period)
        duration *= _GROWTH
    raise RuntimeError(
        f"stick_slip_drive: fewer than {wanted} slips within {duration / _GROWTH:.6g} s "
        f"(estimated period {period_est:.6g} s), and the interface still sticks"
    )


def _statistics(model, result, starts, ends, period_est, normal_period) -> DriveCycle:
    """Statistics of the cycles from ``starts[0]`` on (every complete one)."""
    k_d, v_d = model.drive.stiffness, model.drive.velocity
    t, x = result.event_t, result.event_states[:, 2]
    begin, end = starts[:-1], ends[:-1]
    force = k_d * (v_d * t - x)
    periods = np.diff(t[starts])
    drops = math.copysign(1.0, v_d) * (force[begin] - force[end])
    distances = x[end] - x[begin]
    period = float(np.mean(periods))
    # the history: from the last slip start at least _HISTORY cycles and estimated
    # periods before the last one
    t_back = min(
        t[starts[max(0, starts.size - 1 - _HISTORY)]], t[starts[-1]] - _HISTORY * period_est
    )
    t_hist = t[starts[max(0, np.searchsorted(t[starts], t_back, side="right") - 1)]]
    spn = normal_period / period
    where = f"{begin.size} cycles from t = {t[starts[0]]:.6g} s to {t[starts[-1]]:.6g} s"
    return DriveCycle(
        regime=STICK_SLIP,
        period=period,
        period_std=float(np.std(periods)),
        force_drop=float(np.mean(drops)),
        force_drop_std=float(np.std(drops)),
        peak_force=float(np.mean(np.abs(force[begin]))),
        slip_distance=float(np.mean(distances)),
        slip_distance_std=float(np.std(distances)),
        slip_time=float(np.mean(t[end] - t[begin])),
        stick_time=float(np.mean(t[starts[1:]] - t[end])),
        mean_velocity=float((x[starts[-1]] - x[starts[0]]) / (t[starts[-1]] - t[starts[0]])),
        normal_period=normal_period,
        slips_per_normal_period=spn,
        cycles=int(begin.size),
        history=_window(result, t_hist, t[starts[-1]]),
        note=f"stick-slip: {where}"
        + ("" if math.isnan(spn) else f", {spn:.4g} slips per normal period"),
    )


def _sliding(result, last_stick, period_est, normal_period) -> DriveCycle:
    t_end = result.t[-1]
    t_lo = max(last_stick, t_end - _HISTORY * period_est)
    nan = math.nan
    cycle_fields = ("period", "period_std", "force_drop", "force_drop_std", "peak_force")
    cycle_fields += ("slip_distance", "slip_distance_std", "slip_time", "stick_time")
    return DriveCycle(
        regime=SLIDING,
        **dict.fromkeys(cycle_fields, nan),
        mean_velocity=float((result.x[-1] - np.interp(t_lo, result.t, result.x)) / (t_end - t_lo)),
        normal_period=normal_period,
        slips_per_normal_period=nan,
        cycles=0,
        history=_window(result, t_lo, t_end),
        note=(
            f"sliding: the interface has not stuck since t = {last_stick:.6g} s (run to "
            f"{t_end:.6g} s, estimated stick-slip period {period_est:.6g} s)"
        ),
    )


_MAP_VARIABLES = (
    ("period", "s", "mean time between slip starts"),
    ("force_drop", "N", "mean drive spring force drop per slip"),
    ("force_drop_std", "N", "standard deviation of the force drop"),
    ("peak_force", "N", "mean drive spring force at a slip start"),
    ("slip_distance", "m", "mean body displacement per slip"),
    ("slip_time", "s", "mean slip duration"),
    ("stick_time", "s", "mean stick duration"),
    ("mean_velocity", "m s-1", "mean body velocity"),
    ("slips_per_normal_period", "1", "normal vibration period / stick-slip period"),
)


def stick_slip_drive_map(
    model: Model,
    velocities: Sequence[float] | np.ndarray,
    amplitudes: Sequence[float] | np.ndarray | None = None,
    *,
    cycles: int = 5,
    transient_cycles: int = 2,
    method: str = "event",
):
    """The cycle of :func:`stick_slip_drive` over drive velocities × normal vibration
    amplitudes.

    Parameters
    ----------
    model : Model
        As for :func:`stick_slip_drive`; ``drive.velocity`` is replaced by each velocity.
    velocities : array of float
        Drive velocities v_d [m/s], nonzero.
    amplitudes : array of float, optional
        Free normal vibration: amplitudes A [m] (0: constant N = m g); default [0].
        With an excitation: values of ``excitation.amplitude`` (N for a harmonic force,
        m for a base motion or a prescribed penetration); default its own.
    cycles, transient_cycles, method
        As for :func:`stick_slip_drive` (fewer cycles by default).

    Returns
    -------
    xarray.Dataset
        On ``velocity`` [m s-1] × ``amplitude``: ``period`` [s], ``force_drop``,
        ``force_drop_std``, ``peak_force`` [N], ``slip_distance`` [m], ``slip_time``,
        ``stick_time`` [s], ``mean_velocity`` [m s-1], ``slips_per_normal_period`` [1]
        and ``stick_slip`` (1 stick–slip, 0 sliding: the others NaN there). One event
        simulation per point (:func:`stick_slip_drive`), run one after the other: slow
        drives cost the most (a cycle lasts ~2 (μ_s − μ_k) m g / (k_d v_d)).
    """
    import xarray as xr

    model = as_model(model)
    require(model, "stick_slip_drive_map", allowed=_ALLOWED, instead=_INSTEAD)
    speeds = check.real_array("velocities", velocities)
    if np.any(speeds == 0.0):
        raise ValueError("velocities must be nonzero [m s-1]: a spring drive at rest never slips")
    if model.excitation is None:
        unit, what = "m", "free normal vibration amplitude A = y0 - y_min"
        amps = np.zeros(1) if amplitudes is None else check.real_array("amplitudes", amplitudes)
    else:
        unit = model.unit("excitation.amplitude")
        what = f"excitation.amplitude of {type(model.excitation).__name__}"
        own = np.array([model.excitation.amplitude])
        amps = own if amplitudes is None else check.real_array("amplitudes", amplitudes)
    values = {name: np.full((speeds.size, amps.size), np.nan) for name, _u, _l in _MAP_VARIABLES}
    flag = np.zeros((speeds.size, amps.size), dtype=np.int8)
    for j, amp in enumerate(amps):
        for i, speed in enumerate(speeds):
            point = model.replace(**{"drive.velocity": float(speed)})
            kwargs = {"amplitude": float(amp)}
            if model.excitation is not None:
                point, kwargs = point.replace(**{"excitation.amplitude": float(amp)}), {}
            cycle = stick_slip_drive(
                point, cycles=cycles, transient_cycles=transient_cycles, method=method, **kwargs
            )
            flag[i, j] = cycle.is_stick_slip
            for name, _u, _l in _MAP_VARIABLES:
                values[name][i, j] = getattr(cycle, name)
    dims = ("velocity", "amplitude")
    data = {
        name: (dims, values[name], {"units": unit_, "long_name": long_})
        for name, unit_, long_ in _MAP_VARIABLES
    }
    data["stick_slip"] = (
        dims, flag, {"units": "1", "long_name": "1: stick-slip, 0: sliding",
                     "flag_values": np.array([0, 1], dtype=np.int8),
                     "flag_meanings": "sliding stick_slip"},
    )  # fmt: skip
    coords = {
        "velocity": ("velocity", speeds, {"units": "m s-1", "long_name": "drive velocity v_d"}),
        "amplitude": ("amplitude", amps, {"units": unit, "long_name": what}),
    }
    attrs = {**model.to_attrs(), "cycles": cycles, "transient_cycles": transient_cycles}
    return xr.Dataset(data, coords=coords, attrs={**attrs, "method": method})
