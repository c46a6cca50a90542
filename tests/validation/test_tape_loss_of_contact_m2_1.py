"""The normal tape at a loss of contact where N leaves with a nonzero slope (m2 = 1).

With m2 = 1 the force S c_n δ (1 + c δ̇/(m g)) falls to 0 at δ = 0 with slope S c_n δ̇,
not 0. The loss is located to just past δ = 0, where the law's stiffness is 0; the
quartic of the piece that the loss closes must take the slope seen from inside the
contact (integrators/normal_step.py, ``end_values``). With the slope 0 there, that
piece's N was 1e-3 m g off and every lane sliding through it (rigid, spring and
Mindlin lanes alike) 2.8e-6 to 1.4e-5 of max v off the event method.

Checked against the closed form of the undamped m2 = 1 motion (harmonic in contact,
free fall in flight) and, for whole time maps, against
``simulate(method="event")`` at rtol 1e-12, which shares no code with the tape.
"""

from __future__ import annotations

import linear_contact_reference
import numpy as np
import pytest

import microslip as ms
from microslip.integrators import normal_tape as nt

P = ms.Parameters(m2=1.0)
Y0 = P.static_deflection
T0 = P.natural_period
WEIGHT = P.mass * P.g  # m g [N]


def _tape_error(steps, amplitude, force, t_end):
    """Largest |P(τ) - N(t)| [N] over the tape's pieces up to ``t_end``."""
    carry, tape, work = nt.tape_buffers(Y0 - amplitude, 0.0)
    c = nt.normal_coefficients(ms.Model(P).pack(0.0))
    rows, status = nt.fill_tape(carry, c, t_end, T0 / steps, tape, work)
    assert status == 0
    tau = np.linspace(0.0, 1.0, 17)
    worst = 0.0
    for r in range(rows):
        p = np.polyval(tape[r, nt.A0 : nt.A4 + 1][::-1], tau)
        t = tape[r, nt.T0] + tau * tape[r, nt.H]
        worst = max(worst, float(np.max(np.abs(p - force(t)))))
    return worst


def test_tape_follows_the_closed_form_through_a_loss_of_contact():
    """The tape's N within 1e-6 m g of the closed form at the default step, falling at
    4th order (>= 10x per halving) through touchdown and loss; the zero slope at the
    loss gave 1.3e-3 m g at every step."""
    amplitude = 1.3 * Y0
    force, _period, t_loss = linear_contact_reference.normal_force(P, amplitude)
    errors = [_tape_error(steps, amplitude, force, t_loss + 0.2 * T0) for steps in (100, 200, 400)]
    assert errors[1] <= 1e-6 * WEIGHT, errors
    assert errors[0] / errors[1] >= 10.0 and errors[1] / errors[2] >= 10.0, errors


FORCES = np.array([0.15, 0.5, 0.85])
FORCED = ms.HarmonicForce(6.0, 0.8 * P.natural_frequency)
CASES = {
    "rigid, free, contact lost": (ms.Model(P), 1.3 * Y0),
    "spring, free, contact lost": (
        ms.Model(P, tangential=ms.TangentialSpring(P.contact_stiffness)), 1.3 * Y0),
    "rigid, Hunt-Crossley forced, contact lost": (
        ms.Model(P, damping=ms.HuntCrossley(0.05), excitation=FORCED), None),
    "mindlin, Hunt-Crossley forced, contact lost": (
        ms.Model(P, tangential=ms.MindlinSpring(0.8235), damping=ms.HuntCrossley(0.05),
                 excitation=FORCED), None),
}  # fmt: skip


@pytest.mark.parametrize("name", list(CASES))
def test_time_map_through_a_loss_of_contact_matches_the_event_method(name):
    """x(T)/T of each lane within 1e-6 of max v of the event method (was 2.8e-6 to
    1.4e-5 with the zero slope)."""
    model, amplitude = CASES[name]
    duration = 8.0 * T0
    kwargs = {} if amplitude is None else {"amplitude": [amplitude]}
    axes = {"excitation.amplitude": [FORCED.amplitude]} if amplitude is None else None
    result = ms.sweep(model, axes, force=FORCES, method="time", duration=duration, **kwargs)
    values = np.asarray(result.values).ravel()
    reference = np.array([
        ms.simulate(model, force=float(f), duration=duration, rtol=1e-12,
                    **({} if amplitude is None else {"amplitude": amplitude})).x[-1] / duration
        for f in FORCES
    ])  # fmt: skip
    scale = np.max(np.abs(reference))
    assert scale > 0.0
    assert np.max(np.abs(values - reference)) <= 1e-6 * scale, (
        np.max(np.abs(values - reference)) / scale
    )
