"""The flow map of the forced normal motion over one period, with its variational matrix.

    m ÿ = m g + P(t) - N(δ, δ̇),    δ = y - z(t)        (eq. 2.4 with excitation)

is integrated from t0 over a time T in a FIXED number of equal steps of the 12-stage,
8th-order Dormand–Prince method (the DOP853 tableau; its 8th-order solution is used
without error control). Fixed steps make the flow map φ_T(s) a smooth function of the
initial state and of the parameters (frequency, amplitude), which Newton shooting and
pseudo-arclength continuation need; an adaptive step sequence would make it jump. The
8th order keeps the step count low: with ~100 steps per natural period the one-period
error is near round-off.

The 2×2 variational matrix Φ = ∂φ/∂s is integrated alongside,
dΦ/dt = [[0, 1], [-(∂N/∂y)/m, -(∂N/∂ẏ)/m]] Φ, with the partials of the model's own law
(:func:`microslip.model.damping.damped_force_partials`) taken unclipped in contact, as
the raw law is integrated there, so that Φ is the variation of the field integrated.

Contact switches (touchdown and lift-off, including the separation where N_raw reaches 0
while δ > 0 with damping) are roots of one switching function, min(δ/y0, N_raw/(m g))
(δ/y0 alone without damping): contact iff it is > 0. A switch is located inside the step
by re-stepping the same method from the step start over a fraction θ of it (Illinois
false position, as :func:`microslip.integrators.switching.locate`), the step is split
there and finished in the new mode, so the method keeps its order. A double crossing
inside one step (a short flight or a graze) is found from the extremum of the switching
function. Where the right-hand side jumps (Kelvin–Voigt touchdown, force jump c δ̇) Φ
is multiplied by the saltation matrix S = I + (f⁺ - f⁻) ∇gᵀ / (∇g·f⁻ + ∂g/∂t), which for
g = δ is [[1, 0], [(ÿ⁺ - ÿ⁻)/δ̇, 1]]; the elastic law and Hunt–Crossley have no jump.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip._refcount import NO_REFCOUNT
from microslip.integrators import threads
from microslip.integrators.bracket import bracket_start, bracket_step
from microslip.integrators.dop853_tableau import N_STAGES
from microslip.integrators.dop853_tableau import A as _A
from microslip.integrators.dop853_tableau import B as _B
from microslip.integrators.dop853_tableau import C as _C
from microslip.model.coefficients import GRAVITY, MASS, STATIC_DEFLECTION, as_tuple
from microslip.model.contact import elastic_force, elastic_stiffness
from microslip.model.damping import can_separate_in_overlap, damped_force_partials
from microslip.model.excitation import applied_force
from microslip.model.normal import gap, raw_normal_force

__all__ = ["STATE_ONLY", "VARIATIONAL", "propagate", "propagate_each"]

# Functions located inside a step.
W_CONTACT = 0  # switching function: > 0 in contact
W_CONTACT_RATE = 1  # its time derivative (extremum: a possible double crossing)
W_YDOT = 2  # ẏ (extrema of y)
W_NRATE = 3  # dN_raw/dt (extrema of N while in contact)

# Slots of the summary returned by propagate().
S_YMIN = 0
S_YMAX = 1
S_NMIN = 2
S_NMAX = 3
S_FLIGHT = 4  # 1.0 if the motion left contact somewhere
S_EVENTS = 5  # number of contact switches
S_SIZE = 6

_DIM = 6  # y, ẏ, Φ00, Φ01, Φ10, Φ11
_STATE = np.int64(2)  # y, ẏ alone (np.int64: no literal specialisation of the callees)
# ``variational`` of propagate_each (NumPy bools: one compiled form for both).
VARIATIONAL = np.bool_(True)  # with the monodromy Φ
STATE_ONLY = np.bool_(False)  # (y, ẏ) alone: a transient


@njit(cache=True, inline="always")
def _accel(t, y, yd, c, contact):
    """ÿ [m/s^2] with the contact mode held fixed (the raw law extended smoothly)."""
    force = raw_normal_force(t, y, yd, c) if contact else 0.0
    return c[GRAVITY] + (applied_force(t, c) - force) / c[MASS]


@njit(cache=True, inline="always")
def _raw_partials(t, y, yd, c):
    """(∂N_raw/∂y [N/m], ∂N_raw/∂ẏ [N s/m]) of the unclipped law that _accel integrates.

    Not the clipped :func:`microslip.model.normal.normal_force_partials`: the late stages
    of a step that ends on a separation (N_raw = 0) are low-order estimates that can lie
    just past the switch, where the clipped partials drop to 0 while the contact-mode
    field integrated there is still the raw law. Φ must be the variation of the field
    actually integrated, or the monodromy is off by O(step) at every such separation.
    """
    delta, delta_rate, _ = gap(t, y, yd, c)
    return damped_force_partials(
        elastic_force(delta, c), elastic_stiffness(delta, c), delta_rate, c
    )


@njit(cache=True, inline="always")
def _rhs(t, s, c, contact, out, dim):
    """The first ``dim`` components of the field: (ẏ, ÿ) with dim = _STATE, and the
    variational equation's four after them with dim = _DIM."""
    y = s[0]
    yd = s[1]
    out[0] = yd
    out[1] = _accel(t, y, yd, c, contact)
    if dim == _STATE:
        return
    k_y, k_v = 0.0, 0.0
    if contact:
        k_y, k_v = _raw_partials(t, y, yd, c)
    m = c[MASS]
    out[2] = s[4]
    out[3] = s[5]
    out[4] = -(k_y * s[2] + k_v * s[4]) / m
    out[5] = -(k_y * s[3] + k_v * s[5]) / m


@njit(cache=True, **NO_REFCOUNT)
def _step(t, s, h, c, contact, k, tmp, out, dim):
    """One 8th-order Dormand–Prince step of length h from (t, s) into ``out``, of the
    first ``dim`` components (_STATE: y, ẏ only; _DIM: with Φ). The components do not
    feed back into (y, ẏ), whose bits are the same either way."""
    for i in range(N_STAGES):
        for d in range(dim):
            acc = 0.0
            for j in range(i):
                acc += _A[i, j] * k[j, d]
            tmp[d] = s[d] + h * acc
        _rhs(t + _C[i] * h, tmp, c, contact, k[i], dim)
    for d in range(dim):
        acc = 0.0
        for i in range(N_STAGES):
            acc += _B[i] * k[i, d]
        out[d] = s[d] + h * acc


@njit(cache=True, **NO_REFCOUNT)
def _raw_rate(t, y, yd, c, contact):
    """dN_raw/dt [N/s] along the motion in the given mode (unclipped)."""
    delta, delta_rate, zddot = gap(t, y, yd, c)
    elastic = elastic_force(delta, c)
    d_delta, d_rate = damped_force_partials(elastic, elastic_stiffness(delta, c), delta_rate, c)
    return d_delta * delta_rate + d_rate * (_accel(t, y, yd, c, contact) - zddot)


@njit(cache=True, **NO_REFCOUNT)
def _value(which, t, s, c, contact):
    y = s[0]
    yd = s[1]
    if which == W_YDOT:
        return yd
    if which == W_NRATE:
        return _raw_rate(t, y, yd, c, contact)
    delta, delta_rate, _ = gap(t, y, yd, c)
    scale_n = c[MASS] * c[GRAVITY]
    y0 = c[STATIC_DEFLECTION]
    damped = can_separate_in_overlap(c)
    if which == W_CONTACT:
        g = delta / y0
        if damped:
            g = min(g, raw_normal_force(t, y, yd, c) / scale_n)
        return g
    # W_CONTACT_RATE: the rate of the active branch of the min.
    if damped and raw_normal_force(t, y, yd, c) / scale_n < delta / y0:
        return _raw_rate(t, y, yd, c, contact) / scale_n
    return delta_rate / y0


@njit(cache=True, **NO_REFCOUNT)
def _locate(which, s0, t, h, c, contact, lo, hi, f_lo, f_hi, k, tmp, out):
    """θ in (lo, hi] where ``which`` changes sign, by re-stepping from s0 (Newton on the
    contact function and ẏ, whose rates are known, inside the bracket; Illinois).

    Returns the first θ known to lie past the sign change, to a few ulps of t.
    """
    side_lo = f_lo > 0.0
    theta, tolerance, retained = bracket_start(t, h, lo, hi, f_lo, f_hi)
    for _ in range(200):
        if hi - lo <= tolerance:
            break
        _step(t, s0, theta * h, c, contact, k, tmp, out, _STATE)
        f_mid = _value(which, t + theta * h, out, c, contact)
        slope = math.nan  # Newton where the rate in θ (h ġ) is at hand: ~25 -> ~5 re-steps
        if which == W_CONTACT:
            slope = h * _value(W_CONTACT_RATE, t + theta * h, out, c, contact)
        elif which == W_YDOT:
            slope = h * _accel(t + theta * h, out[0], out[1], c, contact)
        theta, lo, hi, f_lo, f_hi, retained = bracket_step(
            theta, lo, hi, f_lo, f_hi, retained, f_mid, (f_mid > 0.0) == side_lo, slope,
            tolerance,
        )  # fmt: skip
    return hi


@njit(cache=True, **NO_REFCOUNT)
def _first_switch(s0, s1, t, h, c, contact, k, tmp, out):
    """θ of the first contact switch inside the step (2.0 if none)."""
    f0 = _value(W_CONTACT, t, s0, c, contact)
    f1 = _value(W_CONTACT, t + h, s1, c, contact)
    inside = f0 > 0.0
    if (f1 > 0.0) != inside:
        return _locate(W_CONTACT, s0, t, h, c, contact, 0.0, 1.0, f0, f1, k, tmp, out)
    # Same side at both ends: a double crossing needs an extremum of the switching
    # function inside the step, moving toward zero first and away from it after.
    r0 = _value(W_CONTACT_RATE, t, s0, c, contact)
    r1 = _value(W_CONTACT_RATE, t + h, s1, c, contact)
    toward = (r0 < 0.0 < r1) if inside else (r1 < 0.0 < r0)
    if not toward:
        return 2.0
    if min(abs(f0), abs(f1)) > 2.0 * abs(h) * (abs(r0) + abs(r1)):
        return 2.0  # the dip cannot reach zero within the step
    theta_x, fx = _dip(s0, t, h, c, contact, inside, r0, r1, k, tmp, out)
    if theta_x <= 1.0:
        return _locate(W_CONTACT, s0, t, h, c, contact, 0.0, theta_x, f0, fx, k, tmp, out)
    return 2.0


@njit(cache=True, **NO_REFCOUNT)
def _dip(s0, t, h, c, contact, inside, r0, r1, k, tmp, out):
    """(θ, g) of a trial past which the contact function g, moving toward zero at the
    start of the step (rate r0) and away at its end (r1), has crossed zero, or (2.0,
    NaN) if its dip does not reach zero.

    The extremum is bracketed on ġ (Illinois) and need not be found to round-off: the
    search stops at the first trial whose g has crossed, or once g at a trial is further
    from zero than the end rates could carry it across the bracket (as in
    :func:`_first_switch`). A damped contact's g = min(δ/y0, N_raw/(m g)) often has its
    extremum at a kink, where ġ jumps: found to round-off it took ~55 re-steps."""
    side_lo = r0 > 0.0
    lo, hi, f_lo, f_hi = 0.0, 1.0, r0, r1
    theta, tolerance, retained = bracket_start(t, h, lo, hi, f_lo, f_hi)
    reach = 2.0 * abs(h) * (abs(r0) + abs(r1))
    for _ in range(200):
        _step(t, s0, theta * h, c, contact, k, tmp, out, _STATE)
        g = _value(W_CONTACT, t + theta * h, out, c, contact)
        if (g > 0.0) != inside:
            return theta, g
        rate = _value(W_CONTACT_RATE, t + theta * h, out, c, contact)
        theta, lo, hi, f_lo, f_hi, retained = bracket_step(
            theta, lo, hi, f_lo, f_hi, retained, rate, (rate > 0.0) == side_lo, math.nan,
            tolerance,
        )  # fmt: skip
        if hi - lo <= tolerance or abs(g) > reach * (hi - lo):
            break
    return 2.0, math.nan


@njit(cache=True, **NO_REFCOUNT)
def _note_extrema(s0, s1, t, h, c, contact, summary, k, tmp, out):
    """Update y and N extremes with the values at the interval end and any interior ones."""
    for s in (s0, s1):
        summary[S_YMIN] = min(summary[S_YMIN], s[0])
        summary[S_YMAX] = max(summary[S_YMAX], s[0])
    r0 = s0[1]
    r1 = s1[1]
    if (r0 > 0.0) != (r1 > 0.0) and r0 != 0.0 and r1 != 0.0:
        theta = _locate(W_YDOT, s0, t, h, c, contact, 0.0, 1.0, r0, r1, k, tmp, out)
        _step(t, s0, theta * h, c, contact, k, tmp, out, _STATE)
        summary[S_YMIN] = min(summary[S_YMIN], out[0])
        summary[S_YMAX] = max(summary[S_YMAX], out[0])
    if not contact:
        summary[S_FLIGHT] = 1.0
        summary[S_NMIN] = 0.0
        return
    for tt, s in ((t, s0), (t + h, s1)):
        n = max(raw_normal_force(tt, s[0], s[1], c), 0.0)
        summary[S_NMIN] = min(summary[S_NMIN], n)
        summary[S_NMAX] = max(summary[S_NMAX], n)
    q0 = _raw_rate(t, s0[0], s0[1], c, contact)
    q1 = _raw_rate(t + h, s1[0], s1[1], c, contact)
    if (q0 > 0.0) != (q1 > 0.0) and q0 != 0.0 and q1 != 0.0:
        theta = _locate(W_NRATE, s0, t, h, c, contact, 0.0, 1.0, q0, q1, k, tmp, out)
        _step(t, s0, theta * h, c, contact, k, tmp, out, _STATE)
        n = max(raw_normal_force(t + theta * h, out[0], out[1], c), 0.0)
        summary[S_NMIN] = min(summary[S_NMIN], n)
        summary[S_NMAX] = max(summary[S_NMAX], n)


@njit(cache=True)
def in_contact(t, y, yd, c):
    """True when (t, y, ẏ) is in contact: δ > 0 and N_raw > 0."""
    s = np.zeros(_DIM)
    s[0] = y
    s[1] = yd
    return _value(W_CONTACT, t, s, c, True) > 0.0


@njit(cache=True, nogil=True)
def propagate(coefficients, y_start, yd_start, t0, duration, n_steps, record, variational):
    """Integrate the normal motion from (t0, y, ẏ) over ``duration`` [s] in n_steps steps.

    Returns (state (2,) at t0 + duration, Φ (2, 2), nodes (4, n) rows t, y, ẏ and
    node count in the last column unused, accel (2, n-1) rows ÿ at interval starts and
    ends, summary (S_SIZE,)). Nodes and extremes are filled only when ``record``; Φ only
    when ``variational`` (NaN otherwise: a transient needs the state alone, and skipping
    Φ does not change its bits).
    """
    c = as_tuple(coefficients)  # the laws' one compiled form (docs/design.md)
    dim = _DIM if variational else _STATE
    s = np.zeros(_DIM)
    s[0] = y_start
    s[1] = yd_start
    s[2] = 1.0
    s[5] = 1.0
    k = np.zeros((N_STAGES, _DIM))
    tmp = np.zeros(_DIM)
    out = np.zeros(_DIM)
    s1 = np.zeros(_DIM)
    capacity = 3 * n_steps + 8 if record else 1
    nodes = np.zeros((3, capacity))
    accel = np.zeros((2, capacity))
    summary = np.zeros(S_SIZE)
    summary[S_YMIN] = np.inf
    summary[S_YMAX] = -np.inf
    summary[S_NMIN] = np.inf
    summary[S_NMAX] = 0.0
    contact = in_contact(t0, y_start, yd_start, c)
    count = 0
    if record:
        nodes[0, 0] = t0
        nodes[1, 0] = y_start
        nodes[2, 0] = yd_start
    h_grid = duration / n_steps
    t = t0
    for step in range(n_steps):
        t_end = t0 + (step + 1) * h_grid if step < n_steps - 1 else t0 + duration
        for _split in range(64):
            h = t_end - t
            if h <= 0.0:
                break
            _step(t, s, h, c, contact, k, tmp, s1, dim)
            theta = _first_switch(s, s1, t, h, c, contact, k, tmp, out)
            switched = theta <= 1.0
            if switched:
                _step(t, s, theta * h, c, contact, k, tmp, s1, dim)
                t_new = t + theta * h
            else:
                t_new = t_end
            if record:
                accel[0, count] = _accel(t, s[0], s[1], c, contact)
                accel[1, count] = _accel(t_new, s1[0], s1[1], c, contact)
                _note_extrema(s, s1, t, t_new - t, c, contact, summary, k, tmp, out)
                count += 1
                nodes[0, count] = t_new
                nodes[1, count] = s1[0]
                nodes[2, count] = s1[1]
            s[:dim] = s1[:dim]
            t = t_new
            if not switched:
                break
            summary[S_EVENTS] += 1.0
            contact = not contact
            if not variational:
                continue
            # Saltation for g = δ: S = [[1, 0], [(ÿ⁺ - ÿ⁻)/δ̇, 1]] (0 where ÿ is continuous).
            before = _accel(t, s[0], s[1], c, not contact)
            after = _accel(t, s[0], s[1], c, contact)
            delta_rate = gap(t, s[0], s[1], c)[1]
            if after != before and delta_rate != 0.0:
                factor = (after - before) / delta_rate
                s[4] += factor * s[2]
                s[5] += factor * s[3]
    state = s[:2].copy()
    phi = np.empty((2, 2))
    if not variational:
        s[2:] = np.nan
    phi[0, 0] = s[2]
    phi[0, 1] = s[3]
    phi[1, 0] = s[4]
    phi[1, 1] = s[5]
    if record:
        return state, phi, nodes[:, : count + 1].copy(), accel[:, :count].copy(), summary
    return state, phi, nodes[:, :1].copy(), accel[:, :0].copy(), summary


def propagate_each(cs, starts, durations, n_steps, record, ends, phis, summaries, variational):
    """:func:`propagate` from t0 = 0 for each row i, in parallel: coefficients cs[i],
    state starts[i] = (y [m], ẏ [m/s]), durations[i] [s] in n_steps[i] (int64) steps;
    fills ends[i] (2,), phis[i] (2, 2; NaN unless ``variational``, a NumPy bool) and
    summaries[i] (S_SIZE,). Each row
    is integrated on its own, so its bits do not depend on the other rows or the thread
    count (:func:`~microslip.integrators.threads.run_ranges`).
    """
    threads.run_ranges(
        _propagate_rows, cs.shape[0], cs, starts, durations, n_steps, record, ends, phis,
        summaries, variational, interruptible=False,
    )  # fmt: skip


@njit(cache=True, nogil=True)
def _propagate_rows(lo, hi, cs, starts, durations, n_steps, record, ends, phis, summaries,
                    variational):  # fmt: skip
    """Rows [lo, hi) of :func:`propagate_each`."""
    for i in range(lo, hi):
        end, phi, _nodes, _accel, summary = propagate(
            cs[i], starts[i, 0], starts[i, 1], 0.0, durations[i], n_steps[i], record, variational
        )
        ends[i, :] = end
        phis[i, :, :] = phi
        summaries[i, :] = summary
