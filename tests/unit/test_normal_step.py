"""The normal tape's own contact-switch search (integrators/normal_step.py) against the
core located switching that ``simulate(method="rk4")`` runs (integrators/switching.py).

The tape integrates the normal motion of a copy of the model whose tangential side
cannot switch (a rigid contact driven kinematically at 1 m/s), and locates its contact
switches with the core search on (y, ẏ) alone. ``simulate`` on that very model, with the
same fixed step, goes through the core ``first_switch``: its step boundaries and switch
instants must be the tape's rows, the same bits (normal_tape's module doc). A search
that took the wrong side, missed the interior extremum of a function (a touchdown and
lift-off inside one step), located the separation inside the overlap as a gap flip or
set the wrong mode after it would move a boundary or a state.
"""

from __future__ import annotations

import numpy as np
import pytest

import microslip as ms
from microslip.integrators import normal_tape as nt
from microslip.simulation import initial_state_from_amplitude

PARAMS = ms.Parameters()
Y0 = PARAMS.static_deflection
T0 = PARAMS.natural_period
DRIVE = ms.PrescribedVelocity(1.0)  # the tape copy's drive (normal_tape.normal_coefficients)

CASES = {
    # Undamped, flights: the contact gap alone.
    "paper, flights": (ms.Model(PARAMS, drive=DRIVE), 2.0 * Y0),
    # Flights shorter than a step: lift-off and touchdown inside one step, which only the
    # interior extremum of δ shows.
    "paper, grazing flights": (ms.Model(PARAMS, drive=DRIVE), (1.0 + 1e-5) * Y0),
    # Viscous damping separates inside the overlap (the SEPARATION function), forced.
    "viscous, forced": (
        ms.Model(
            PARAMS, damping=ms.Viscous(0.3), excitation=ms.HarmonicForce(12.0, 1200.0), drive=DRIVE
        ),
        0.0,
    ),
    # Hertz contact (m2 = 1.5), flights.
    "hertz, flights": (ms.Model(ms.Parameters(m2=1.5), drive=DRIVE), 2.0 * Y0),
    # The surface moves (its sine and cosine shared by a step's stages: normal_step.rk4).
    "base motion, flights": (
        ms.Model(
            PARAMS,
            damping=ms.Viscous(0.05),
            excitation=ms.BaseMotion(1.5 * Y0, 0.9 / T0),
            drive=DRIVE,
        ),
        0.0,
    ),
}


def _tape(model, amplitude, duration, dt):
    """Every row of the tape of ``model`` from its state at ``amplitude`` [m]."""
    c = nt.normal_coefficients(model.pack(0.0))
    y0, ydot0 = initial_state_from_amplitude(model.params, amplitude)[:2]
    carry, tape, work = nt.tape_buffers(y0, ydot0)
    rows = []
    while True:
        n, status = nt.fill_tape(carry, c, duration, dt, tape, work)
        rows.append(tape[:n].copy())
        if status != 1:
            assert status == 0
            return np.concatenate(rows)


@pytest.mark.parametrize("case", list(CASES))
def test_tape_boundaries_are_simulate_rk4(case):
    model, amplitude = CASES[case]
    duration = 0.01
    dt = PARAMS.natural_period / 200.0
    rows = _tape(model, amplitude, duration, dt)
    run = ms.simulate(model, amplitude=amplitude, duration=duration, method="rk4", dt=dt)
    switches = np.sum(np.abs(rows[:, nt.H] - dt) > 1e-9 * dt)
    assert switches >= 4, switches  # the case has contact switches inside steps
    assert len(run.event_t) >= 2
    # simulate keeps every step boundary and switch instant: the rows' starts, then t_end.
    assert run.t.size == rows.shape[0] + 1
    np.testing.assert_array_equal(rows[:, nt.T0], run.t[:-1])
    np.testing.assert_array_equal(rows[:, nt.Y_START], run.y[:-1])
    np.testing.assert_array_equal(rows[:, nt.YDOT_START], run.ydot[:-1])
    np.testing.assert_array_equal(rows[-1, nt.Y_END], run.y[-1])
