"""Python driver around the compiled switching loop: buffers, streaming, status.

The state is a float64 vector of the model's size (:mod:`microslip.model.system`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from microslip.integrators import kernel
from microslip.integrators.methods import DOP853, RK4
from microslip.model.samples import full_states
from microslip.model.switches import initial_mode
from microslip.model.system import EVENT_NAMES

METHODS = {"rk4": RK4, "event": DOP853}
MAX_STEPS_PER_CALL = 1 << 20  # steps of one kernel call when every n-th step is kept


@dataclass(frozen=True)
class RawTrajectory:
    """Samples and switching instants straight from the kernel (SI units)."""

    t: np.ndarray  # [s]
    states: np.ndarray  # (n, n_state), the model's state layout
    direction: np.ndarray  # the model's mode at each sample (today sgn ẋ: -1, 0 stick, +1)
    event_t: np.ndarray  # [s]
    event_kind: np.ndarray  # codes of EVENT_NAMES
    event_states: np.ndarray  # (n_events, n_state), state just after each switch
    n_steps: int
    n_rejected: int


def integrate(
    method: str,
    coeffs: np.ndarray,
    state0: np.ndarray,
    t0: float,
    t_end: float,
    *,
    dt: float = 0.0,
    h_max: float = np.inf,
    h_initial: float = 0.0,
    rtol: float = 1e-10,
    atol: np.ndarray | None = None,
    t_eval: np.ndarray | None = None,
    save_every: int = 1,
    buffer_size: int = 1 << 16,
) -> RawTrajectory:
    """Integrate the model of ``coeffs`` from ``state0`` (a state vector of the model's
    size) at ``t0`` to ``t_end`` [s] with located switching.

    Inputs are assumed validated (see :func:`microslip.simulate`).
    """
    code = METHODS[method]
    if t_eval is None:
        # Ctrl-C reaches Python only between kernel calls: a call ends when its output
        # buffer is full, so bound its steps (~1e6, well under a second) by the buffer.
        buffer_size = int(min(buffer_size, max(64, MAX_STEPS_PER_CALL // save_every)))
    s0 = np.array(full_states(np.ravel(state0)), dtype=np.float64)
    n_state = s0.size
    atol = np.zeros(n_state) if atol is None else np.asarray(atol, dtype=float)
    t_eval = np.empty(0) if t_eval is None else np.asarray(t_eval, dtype=float)
    # The coefficients as a tuple, as the kernels pass them: one compiled initial_mode
    # (and normal force) for both, not a second one for an array (~2 s of cold compile).
    direction0 = initial_mode(t0, s0, tuple(np.asarray(coeffs, dtype=np.float64)))
    carry = np.zeros(kernel.carry_size(n_state))
    carry[kernel.C_T] = t0
    carry[kernel.C_STATE :] = s0
    carry[kernel.C_MODE] = direction0
    carry[kernel.C_H] = h_initial
    carry[kernel.C_K] = 1
    carry[kernel.C_T0] = t0

    t_parts, s_parts, d_parts = [], [], []
    e_t, e_k, e_s = [], [], []
    if t_eval.size == 0:  # step output starts with the initial state
        t_parts.append(np.array([t0]))
        s_parts.append(np.array([s0]))
        d_parts.append(np.array([direction0]))
    while True:
        out_t = np.empty(buffer_size)
        out_s = np.empty((buffer_size, n_state))
        out_d = np.empty(buffer_size)
        ev_t = np.empty(buffer_size // 4)
        ev_k = np.empty(buffer_size // 4, dtype=np.int64)
        ev_s = np.empty((buffer_size // 4, n_state))
        n, n_ev, status = kernel.integrate_chunk(
            code, carry, t_end, dt, h_max, rtol, atol, coeffs, t_eval, save_every,
            out_t, out_s, out_d, ev_t, ev_k, ev_s,
        )  # fmt: skip
        t_parts.append(out_t[:n].copy())
        s_parts.append(out_s[:n].copy())
        d_parts.append(out_d[:n].copy())
        e_t.append(ev_t[:n_ev].copy())
        e_k.append(ev_k[:n_ev].copy())
        e_s.append(ev_s[:n_ev].copy())
        if status == kernel.DONE:
            break
        if status == kernel.STALLED:
            raise RuntimeError(
                f"switching stalled at t={float(carry[kernel.C_T])!r} s: more than "
                f"{kernel.MAX_SWITCHES_PER_STEP} switches "
                "without progress (inconsistent friction law?)"
            )
        if status == kernel.STEP_UNDERFLOW:
            raise RuntimeError(
                f"step size underflow at t={float(carry[kernel.C_T])!r} s; loosen rtol/atol"
            )
    return RawTrajectory(
        t=np.concatenate(t_parts),
        states=np.concatenate(s_parts),
        direction=np.concatenate(d_parts),
        event_t=np.concatenate(e_t),
        event_kind=np.concatenate(e_k),
        event_states=np.concatenate(e_s),
        n_steps=int(carry[kernel.C_STEPS]),
        n_rejected=int(carry[kernel.C_REJECTS]),
    )


__all__ = ["EVENT_NAMES", "METHODS", "RawTrajectory", "integrate"]
