"""One period of the steady normal motion, in the form the contact-point walk reads
(:mod:`microslip.analysis.contact_point`): the source tuple and its pieces, computed once
per normal set-up and shared by every drive speed, tangential stiffness and friction
coefficient (docs/theory/friction_reduction.md).
"""

from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip import validation as check
from microslip.analysis.normal_pieces import (
    CLOSED_FORM,
    CLOSED_FORM_PIECES,
    INT_N,
    TABLE,
    build_pieces,
)
from microslip.integrators.threads import thread_count
from microslip.model.coefficients import as_tuple
from microslip.model.composition import Model
from microslip.model.excitation import BaseMotion, HarmonicForce, PrescribedPenetration
from microslip.model.normal import normal_acceleration, normal_force

__all__ = ["NormalCycle", "forced_transients", "normal_cycle", "normal_cycles", "normal_model"]

FREE_PIECES = 64  # pieces per period of the free orbit's table (_coarse_base)


@dataclass(frozen=True)
class NormalCycle:
    """One period of the steady normal motion (``pieces`` None: N constant)."""

    period: float
    mean_normal_force: float
    kind: float = CLOSED_FORM
    source: tuple = ()
    pieces: np.ndarray | None = None
    rate_max: float = -math.inf  # max dN/dt in contact [N/s]
    ratio_max: float = -math.inf  # max (dN/dt)/K in contact [m/s]


def normal_model(model: Model) -> Model:
    return model.replace(tangential=None, friction=None, drive=None)


def _free_table(normal: Model, amplitude: float):
    """(T, nodes t, y, ẏ, ÿ) of the undamped free orbit from its highest point, mirrored
    from the half-orbit table (y(T - t) = y(t))."""
    from microslip.analysis import orbit
    from microslip.analysis.free_vibration import _half_orbit

    c, ys, yds, summary = _half_orbit(normal.params, amplitude)
    half = float(summary[orbit.O_HALF])
    flight, step = float(summary[orbit.O_FLIGHT]), float(summary[orbit.O_STEP])
    last = int(summary[orbit.O_NODES]) - 2  # the bottom lies past node `last`
    t = flight + step * np.arange(last + 1)
    y, yd = ys[: last + 1].copy(), yds[: last + 1].copy()
    if flight > 0.0:  # free fall from the top: a parabola, exact in the quintic
        t, y, yd = np.r_[0.0, t], np.r_[summary[orbit.O_TOP], y], np.r_[0.0, yd]
    bottom = float(summary[orbit.O_BOTTOM])
    t, y, yd = np.r_[t, half], np.r_[y, bottom], np.r_[yd, 0.0]
    t = np.r_[t, 2.0 * half - t[-2::-1]]
    y = np.r_[y, y[-2::-1]]
    yd = np.r_[yd, -yd[-2::-1]]
    return 2.0 * half, t, y, yd, _accelerations(y, c)


@njit(cache=True, nogil=True)
def _accelerations(y, c):
    """ÿ [m/s^2] of the free normal motion (2.4) at the nodes y [m]."""
    laws = as_tuple(c)
    out = np.empty(y.shape[0])
    for i in range(y.shape[0]):
        out[i] = normal_acceleration(0.0, y[i], 0.0, laws)
    return out


def _coarse_base(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Piece boundaries [s] for a free-orbit table with nodes t [s], y [m]: about
    FREE_PIECES per period, with every node out of contact (y <= 0: the top and the
    contact switches) kept. The table's nodes are spaced for the interpolation (~1e-13);
    8-point Gauss–Legendre needs far fewer pieces on this smooth N(t), and the walk of
    each speed costs per piece. Inside a piece the interpolant is still read on its own
    nodes (:func:`normal_at`)."""
    stride = max(1, t.size // FREE_PIECES)
    index = np.arange(t.size)
    keep = (index % stride == 0) | (y <= 0.0) | (index == t.size - 1)
    return t[keep]


def forced_transients(models: list[Model]) -> dict:
    """The first transients of the forced orbits that :func:`normal_cycle` needs for these
    models (HarmonicForce or BaseMotion, nonzero amplitude), by normal model
    (:func:`normal_model`), integrated side by side over the cores
    (:func:`~microslip.analysis.periodic.transient_states`: the same bits as one orbit at
    a time). Empty for fewer than two."""
    from microslip.analysis.periodic import transient_states

    normals = dict.fromkeys(normal_model(m) for m in models)
    forced = [
        n for n in normals
        if isinstance(n.excitation, BaseMotion | HarmonicForce) and n.excitation.amplitude != 0.0
    ]  # fmt: skip
    if len(forced) < 2:
        return {}
    return dict(zip(forced, transient_states(forced), strict=True))


def normal_cycle(
    model: Model, amplitude: float | None, transient_state: np.ndarray | None = None
) -> NormalCycle:
    """The steady normal motion of ``model`` (raises NotPeriodOneError if it is not
    period-1). ``transient_state``: a forced orbit's first transient, when known
    (:func:`~microslip.analysis.periodic.transient_states`)."""
    from microslip.analysis.periodic import periodic_orbit

    normal = normal_model(model)
    params, excitation = normal.params, normal.excitation
    weight = params.mass * params.g
    if excitation is not None and amplitude is not None:
        raise ValueError(
            f"amplitude={amplitude!r} applies to the free vibration only; the excitation "
            f"{type(excitation).__name__} sets the normal motion"
        )
    c = normal.pack(0.0)
    if isinstance(excitation, PrescribedPenetration):
        if excitation.amplitude == 0.0:
            return NormalCycle(math.nan, float(normal_force(0.0, 0.0, 0.0, as_tuple(c))))
        kind, base = CLOSED_FORM, np.linspace(0.0, excitation.period, CLOSED_FORM_PIECES + 1)
        tables = (np.empty(0),) * 5
        period = excitation.period
    elif excitation is not None:
        if excitation.amplitude == 0.0:
            return NormalCycle(math.nan, weight)
        orbit = periodic_orbit(normal, transient_state=transient_state)
        kind, base, period = TABLE, orbit.t, orbit.period
        tables = (orbit.t, orbit.y, orbit.ydot, orbit.accel_start, orbit.accel_end)
    else:
        if amplitude is None:
            raise ValueError("give amplitude=A [m] of the free normal vibration")
        amplitude = check.amplitude(params, amplitude)
        if normal.damping is not None or amplitude == 0.0:
            return NormalCycle(math.nan, weight)  # decays to (or stays at) rest: N = m g
        period, t, y, yd, accel = _free_table(normal, amplitude)
        kind, base = TABLE, _coarse_base(t, y)
        tables = (t, y, yd, accel[:-1].copy(), accel[1:].copy())
    # The coefficients as the tuple the laws take (normal_pieces.normal_at reads them).
    source = (kind, *(np.ascontiguousarray(a, dtype=float) for a in tables), as_tuple(c))
    pieces, rate_max, ratio_max = build_pieces(np.ascontiguousarray(base, dtype=float), source)
    mean = float(pieces[:, INT_N].sum()) / period
    return NormalCycle(period, mean, kind, source, pieces, float(rate_max), float(ratio_max))


def normal_cycles(points: list[tuple[Model, float | None]]) -> dict:
    """The steady normal motion of each distinct normal set-up of ``points`` ((model,
    amplitude [m] or None) pairs), by (normal model, amplitude): its :class:`NormalCycle`,
    or the NotPeriodOneError of a forced response that is not period-1.

    The forced orbits' first transients run side by side over the cores
    (:func:`forced_transients`), then the cycles on numba's thread count: their compiled
    parts (the orbit, the flow map, the pieces) release the GIL. Each cycle is computed
    on its own, so its bits are those of :func:`normal_cycle` alone.
    """
    from microslip.analysis.periodic import NotPeriodOneError

    keys = list(dict.fromkeys((normal_model(model), amplitude) for model, amplitude in points))
    transients = forced_transients([normal for normal, _ in keys])

    def one(key):
        normal, amplitude = key
        try:
            return normal_cycle(normal, amplitude, transients.get(normal))
        except NotPeriodOneError as error:
            return error

    threads = min(thread_count(), len(keys))
    if threads <= 1:
        return {key: one(key) for key in keys}
    with ThreadPoolExecutor(threads) as pool:
        return dict(zip(keys, pool.map(one, keys), strict=True))
