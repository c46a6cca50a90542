"""Single Runge–Kutta steps of the composed system in a fixed mode.

A state is a float64 array of any length (its meaning is the model's business:
:mod:`microslip.model.system`); ``mode`` is the model's opaque mode, held fixed within
a step: switching instants are located around these steps, never hidden inside them.
The steps write the new state into ``out`` (which must not be ``s``; it also holds the
stage inputs), so that no step allocates. The model's :func:`derivatives` takes the
state as a tuple (:func:`~microslip.model.system.state_tuple`) and returns one: inside
a step no array crosses a compiled call, where it would be reference-counted (atomic
operations, dearer than the laws). ``work`` (a C-contiguous 2-D array of at least
:data:`WORK_ROWS` rows of the state size) holds the stages of DOP853; its rows are
indexed, never taken as views (a view is reference-counted too).
"""

from __future__ import annotations

from numba import njit

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)
from microslip.model.system import derivatives, state_tuple

# Rows of ``work`` a step may use (DOP853: 12 stages).
WORK_ROWS = 12

# The steps call the model from one place (a loop over the stages), where numba inlines
# it, and are compiled with error_model="numpy" (no ZeroDivisionError branch), as are
# the laws the model calls (model/normal.py and its parts), which take scalars and the
# coefficient tuple: a step then passes no array to a compiled call and has no raising
# branch, so numba drops the reference counting of its array arguments. The divisions
# are by the mass (> 0) and, in the error norms, by atol_i + rtol·max(|s_i|, |out_i|);
# with atol_i = 0 and a component that stays exactly 0 the norm is NaN and the adaptive
# loop rejects the step (it raised ZeroDivisionError before).


@njit(cache=True, error_model="numpy")
def rk4_step(s, t, h, mode, c, out, work):
    """Classical 4th-order Runge–Kutta step of length h [s] (the paper's method)."""
    hh = 0.5 * h
    x = state_tuple(s)
    n = len(x)
    t_stage = t
    for stage in range(4):  # one call site of the (inlined) model: see the module doc
        if stage == 1:
            for i in range(n):
                out[i] = s[i] + hh * work[0, i]
            t_stage = t + hh
        elif stage == 2:
            for i in range(n):
                out[i] = s[i] + hh * work[1, i]
        elif stage == 3:
            for i in range(n):
                out[i] = s[i] + h * work[2, i]
            t_stage = t + h
        if stage > 0:
            x = state_tuple(out)
        k = derivatives(t_stage, x, mode, c)
        for i in range(n):
            work[stage, i] = k[i]
    w = h / 6.0
    for i in range(n):
        out[i] = s[i] + w * (work[0, i] + 2.0 * work[1, i] + 2.0 * work[2, i] + work[3, i])


# Halvings of a graded approach to a switch: its finest sub-step is GRADED_FINEST of the
# step. Next to the corner of a Mindlin stiffness ∝ δ^(m2-1) a step's error falls only
# as a fractional power of its length (length^1.5 at m2 = 1.5), so the finest sub-steps
# take it far below the rest (docs/theory/numerics.md, "Order at a touchdown").
GRADED_LEVELS = 8
GRADED_FINEST = 0.5**GRADED_LEVELS


@njit(cache=True)
def rk4_graded_step(s, t, h, mode, c, out, work):
    """RK4 over [t, t + h] [s] into ``out`` on sub-steps h/2, h/4, ..., h/2^L and h/2^L
    (L = GRADED_LEVELS): finer towards t + h, each as long as what is left after it.
    The step to a switch next to which the right-hand side has a corner of fractional
    order (a Mindlin stiffness on a rough contact law, at a loss of contact): the
    sub-step next to the corner carries ~2^(-1.5 L) of a single step's error there;
    elsewhere it is RK4, 4th order. A fixed count of sub-steps: no loop can run on."""
    n = s.shape[0]
    # The sub-steps start from the last row of ``work`` (RK4 uses its first four): a view
    # taken once a step, where a copy of ``s`` allocated at every trial of a located
    # graded switch (~5 a lift-off or touchdown on a Hertz Mindlin contact).
    here = work[WORK_ROWS - 1]
    for i in range(n):
        here[i] = s[i]
    t_here = t
    length = 0.5 * h
    for level in range(GRADED_LEVELS + 1):
        if level == GRADED_LEVELS:
            length = t + h - t_here  # the last sub-step ends exactly at t + h
        rk4_step(here, t_here, length, mode, c, out, work)
        for i in range(n):
            here[i] = out[i]
        t_here += length
        length *= 0.5
