"""The vectorised RK4 pass of the batched kernel for lanes of the paper's model.

A specialisation of :func:`~microslip.integrators.steppers.rk4_step` for the paper's
model (elastic power-law contact, no damping, no excitation, constant drive): one
branch-free loop over the lanes of a block, which LLVM vectorises, with exactly the
arithmetic of the scalar step, and tests that flag a lane whose step may hold a switch
(see :mod:`microslip.integrators.batched`). The contact law is the model's own
:func:`~microslip.model.contact.elastic_force`; lanes of any other model are always
flagged and stepped by the generic scalar kernel.
"""

from __future__ import annotations

import math

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.coefficients import (
    AREA_CN,
    EXPONENT,
    FORCE,
    GRAVITY,
    MASS,
    MU,
)
from microslip.model.contact import elastic_force
from microslip.model.system import N_STATE, XDOT, YDOT, X, Y, is_paper_model

# Rows of the per-block structure-of-arrays scratch (one column per lane).
# The lane's state in the model's layout (rows 0 .. N_STATE - 1); the fast pass below
# is the paper's model and reads its variables by the names of model.system.
_S = 0
_Y, _YD, _X, _XD = _S + Y, _S + YDOT, _S + X, _S + XDOT
# The paper's lanes leave the other state variables (those of a compliant tangential
# contact) unchanged: their rates are 0 with a rigid contact (model.system).
_DIR = _S + N_STATE  # friction mode: sliding direction ±1, 0 stick
_T = _DIR + 1  # lane time if off the grid, else -1
_G, _SCN, _M2, _M, _IM = _T + 1, _T + 2, _T + 3, _T + 4, _T + 5  # g, S c_n, m2, m, 1/m
_FE, _DMU = _T + 6, _T + 7  # F if sliding else 0; direction·μ (ẍ = (FE - DMU |R|)/m)
_TLO, _THI = _T + 8, _T + 9  # band of y where the friction test μ|R(y)| < threshold flips
_FLAG = _T + 10
_S1 = _FLAG + 1  # the trial step, also for flagged lanes (rows _S1 .. _S1 + N_STATE - 1)
_Y1, _YD1, _X1, _XD1 = _S1 + Y, _S1 + YDOT, _S1 + X, _S1 + XDOT
_GEN = _S1 + N_STATE  # 1 for a lane of any other model than the paper's: always flagged
_ROWS = _GEN + 1

# Vector-pass variants, chosen per block (all give rk4_step's bits).
_UNIT_MASS = 0  # m2 == 2 and m == 1: no scaling by 1/m at all
_POW2_MASS = 1  # m2 == 2 and m a power of two: x/m == x·(1/m) exactly
_GENERAL = 2  # divisions by m; y**m2 unless m2 == 2

_BAND = 1e-12  # relative slack of the y band of a friction test (>> rounding)


@njit(cache=True)
def _accelerations(y, g, scn, m2, m, im, fe, dmu, mode):
    """(ÿ, ẍ) with the bits of the model's derivatives for the paper's model.

    N is the model's own contact law, :func:`microslip.model.contact.elastic_force`,
    inlined with a coefficient tuple holding S c_n and m2 at their slots (m2 = 2 a
    constant in the fast variants, so the power-law branch folds away). ÿ = g - N/m is
    :func:`microslip.model.normal.normal_acceleration` without excitation
    (g + (0 - N)/m has the same bits); ẍ: (F - s·(μN))/m == (FE - DMU·N)/m, since
    (s·μ)N = s·(μN) exactly for s = ±1, and for stick (FE = DMU = 0) it gives 0.0.
    """
    if mode == _GENERAL:
        r = elastic_force(y, (0.0, 0.0, scn, m2))
        return g - r / m, (fe - dmu * r) / m
    r = elastic_force(y, (0.0, 0.0, scn, 2.0))
    if mode == _UNIT_MASS:
        return g - r, fe - dmu * r
    return g - r * im, (fe - dmu * r) * im


@njit(cache=True)
def _vector_pass(lanes, h, buf, mode):
    """One RK4 step in every lane of a block, in place; flagged lanes keep their state.

    The trial step is also stored in rows _Y1.._XD1 (the scalar pass reuses it).
    Returns the number of flagged lanes (buf[_FLAG] = 1 for them).
    """
    hh = 0.5 * h
    w = h / 6.0
    h2 = 2.0 * h
    hsq = h * h
    n_flagged = 0
    for i in range(lanes):
        y = buf[_Y, i]
        yd = buf[_YD, i]
        x = buf[_X, i]
        xd = buf[_XD, i]
        d = buf[_DIR, i]
        g = buf[_G, i]
        scn = buf[_SCN, i]
        m2 = buf[_M2, i]
        m = buf[_M, i]
        im = buf[_IM, i]
        fe = buf[_FE, i]
        dmu = buf[_DMU, i]
        # rk4_step: stage k evaluates (ẏ, ÿ, ẋ, ẍ) at (y_k, ẏ_k, ẋ_k).
        a1, a3 = _accelerations(y, g, scn, m2, m, im, fe, dmu, mode)
        b0 = yd + hh * a1
        b2 = xd + hh * a3
        b1, b3 = _accelerations(y + hh * yd, g, scn, m2, m, im, fe, dmu, mode)
        c0 = yd + hh * b1
        c2 = xd + hh * b3
        c1, c3 = _accelerations(y + hh * b0, g, scn, m2, m, im, fe, dmu, mode)
        d0 = yd + h * c1
        d2 = xd + h * c3
        d1, d3 = _accelerations(y + h * c0, g, scn, m2, m, im, fe, dmu, mode)
        y1 = y + w * (yd + 2.0 * b0 + 2.0 * c0 + d0)
        yd1 = yd + w * (a1 + 2.0 * b1 + 2.0 * c1 + d1)
        x1 = x + w * (xd + 2.0 * b2 + 2.0 * c2 + d2)
        xd1 = xd + w * (a3 + 2.0 * b3 + 2.0 * c3 + d3)

        # Switching tests: conservative supersets of first_switch (module docstring).
        turn = (yd != 0.0) & ((yd > 0.0) != (yd1 > 0.0))
        delta = h2 * (abs(yd) + abs(yd1)) + hsq * (abs(a1) + abs(d1))
        delta = delta if turn else 0.0
        y_lo = min(y, y1) - delta
        y_hi = max(y, y1) + delta
        contact = ((y > 0.0) != (y1 > 0.0)) | (turn & (y_lo <= 0.0) & (y_hi >= 0.0))
        friction = (y_lo < buf[_THI, i]) & (y_hi >= buf[_TLO, i])
        v0 = d * xd
        v1 = d * xd1
        near_rest = min(v0, v1) <= h2 * (abs(a3) + abs(d3))  # always true in stick
        stop = (v1 <= 0.0) & (d != 0.0)
        flag = contact | (friction & near_rest) | stop | (buf[_T, i] >= 0.0) | (buf[_GEN, i] != 0.0)
        buf[_Y1, i] = y1
        buf[_YD1, i] = yd1
        buf[_X1, i] = x1
        buf[_XD1, i] = xd1
        for j in range(_XD + 1, _S + N_STATE):  # the contact point's rows: rates 0 here
            buf[_S1 - _S + j, i] = buf[j, i]
        buf[_Y, i] = y if flag else y1
        buf[_YD, i] = yd if flag else yd1
        buf[_X, i] = x if flag else x1
        buf[_XD, i] = xd if flag else xd1
        buf[_FLAG, i] = 1.0 if flag else 0.0
        n_flagged += 1 if flag else 0
    return n_flagged


@njit(cache=True)
def _vector_pass_unit_mass(lanes, h, buf):
    return _vector_pass(lanes, h, buf, _UNIT_MASS)


@njit(cache=True)
def _vector_pass_pow2_mass(lanes, h, buf):
    return _vector_pass(lanes, h, buf, _POW2_MASS)


@njit(cache=True)
def _vector_pass_general(lanes, h, buf):
    return _vector_pass(lanes, h, buf, _GENERAL)


@njit(cache=True)
def set_mode(buf, i, direction, c):
    """Store a lane's friction mode and the y band of its friction test.

    Stick: the stick margin μ|R| - |F| is negative iff μ|R(y)| < |F|. Slip in direction
    s: s·ẍ > 0 iff μ|R(y)| < s·F. μ|R(y)| is non-decreasing in y (also in floating
    point), so each test is "y below a critical height y_c"; the band [TLO, THI]
    brackets y_c with a relative slack far above rounding. Stick only needs THI.
    """
    force = c[FORCE]
    mu = c[MU]
    buf[_DIR, i] = direction
    buf[_FE, i] = force if direction != 0.0 else 0.0
    buf[_DMU, i] = direction * mu
    target = abs(force) if direction == 0.0 else direction * force
    if not target > 0.0:  # μ|R| < target never holds
        lo, hi = -math.inf, -math.inf
    elif not mu * c[AREA_CN] > 0.0:  # μ|R| = 0 < target always holds
        lo, hi = math.inf, math.inf
    else:
        ratio = target / (mu * c[AREA_CN])
        y_c = math.sqrt(ratio) if c[EXPONENT] == 2.0 else ratio ** (1.0 / c[EXPONENT])
        lo, hi = y_c * (1.0 - _BAND), y_c * (1.0 + _BAND)
    buf[_TLO, i] = -math.inf if direction == 0.0 else lo
    buf[_THI, i] = hi


@njit(cache=True)
def _is_power_of_two(m):
    """m = 2^k with 1/m finite: then x/m and x·(1/m) are the same rounding of x·2^-k."""
    if not (m > 0.0) or math.isinf(m):
        return False
    mantissa, _exponent = math.frexp(m)
    inv = 1.0 / m
    return mantissa == 0.5 and not math.isinf(inv) and inv * m == 1.0


@njit(cache=True)
def init_lane(buf, i, state, direction, c):
    """Load lane ``i`` of a block: its state, coefficients and mode. Returns the vector
    variant the lane allows (_UNIT_MASS, _POW2_MASS or _GENERAL)."""
    for j in range(N_STATE):
        buf[_S + j, i] = state[j]
    buf[_T, i] = -1.0  # on the grid
    buf[_G, i] = c[GRAVITY]
    buf[_SCN, i] = c[AREA_CN]
    buf[_M2, i] = c[EXPONENT]
    buf[_M, i] = c[MASS]
    buf[_IM, i] = 1.0 / c[MASS]
    buf[_GEN, i] = 0.0 if is_paper_model(c) else 1.0
    set_mode(buf, i, direction, c)
    if buf[_GEN, i] != 0.0:
        return _UNIT_MASS  # its vector step is discarded: it does not constrain the block
    if c[EXPONENT] != 2.0 or not _is_power_of_two(c[MASS]):
        return _GENERAL
    if c[MASS] != 1.0:
        return _POW2_MASS
    return _UNIT_MASS


@njit(cache=True)
def vector_pass(variant, lanes, h, buf):
    """One RK4 step of every lane of a block (see :func:`_vector_pass`)."""
    if variant == _UNIT_MASS:
        return _vector_pass_unit_mass(lanes, h, buf)
    if variant == _POW2_MASS:
        return _vector_pass_pow2_mass(lanes, h, buf)
    return _vector_pass_general(lanes, h, buf)
