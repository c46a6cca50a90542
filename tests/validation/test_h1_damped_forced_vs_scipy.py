"""simulate() on damped and excited contacts against an independent scipy integration.

The reference (sliding_reference.py on forced_reference.py) writes the composed laws out
again in scaled variables and locates every contact and friction switch as a terminal event.
"""

from __future__ import annotations

import numpy as np
import pytest
import sliding_reference as ref

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection
T0 = P.natural_period


def _close(actual, expected, rel):
    scale = np.max(np.abs(expected))
    np.testing.assert_allclose(actual, expected, rtol=0.0, atol=rel * scale)


@pytest.mark.parametrize(
    ("damping", "fraction"),
    # Hunt–Crossley loses less at the first impact: at A = 1.3 y0 it never lifts off
    # again after landing, at 2 y0 it does.
    [(ms.Viscous(ratio=0.05), 1.3), (ms.HuntCrossley(ratio=0.05), 1.3),
     (ms.HuntCrossley(ratio=0.05), 2.0)],
)  # fmt: skip
def test_damped_free_vibration_with_loss_of_contact(damping, fraction):
    """ζ = 0.05, starting at rest at y0 - A in flight: y(t) and the separation instants
    (for Kelvin–Voigt where N reaches 0 while δ > 0) within 1e-8 relative."""
    model = ms.Model(P, damping=damping)
    t_eval = np.linspace(0.0, 6.0 * T0, 301)
    amplitude = fraction * Y0
    r = ms.simulate(model, force=0.0, amplitude=amplitude, duration=t_eval[-1], t_eval=t_eval)
    expected = ref.solve(model, force=0.0, state0=(Y0 - amplitude, 0.0, 0.0, 0.0), t_eval=t_eval)
    _close(r.y, expected.y, 1e-8)
    _close(r.ydot, expected.ydot, 1e-8)
    lost = ms.integrators.EVENT_NAMES.index("contact_lost")
    separations = r.event_t[r.event_kind == lost]
    expected_separations = expected.events_of("contact_lost")[0]
    assert len(separations) == len(expected_separations)
    assert len(expected_separations) >= (0 if fraction < 2.0 else 1)
    assert len(expected_separations) >= (1 if isinstance(damping, ms.Viscous) else 0)
    np.testing.assert_allclose(separations, expected_separations, rtol=1e-8)
    touchdowns = r.event_t[r.event_kind == ms.integrators.EVENT_NAMES.index("contact_made")]
    np.testing.assert_allclose(touchdowns, expected.events_of("contact_made")[0], rtol=1e-8)
    # The motion decays: a later top is lower than the starting one.
    assert np.min(r.y[t_eval > 4 * T0]) > Y0 - amplitude + 0.1 * Y0
    if isinstance(damping, ms.Viscous):
        # Kelvin–Voigt separates inside the overlap: δ > 0 and N = 0 there.
        states = r.event_states[r.event_kind == lost]
        assert np.all(states[:, 0] > 0.0)


@pytest.mark.parametrize(
    "excitation",
    [
        ms.HarmonicForce(amplitude=0.6 * P.mass * P.g, frequency=1400.0),
        ms.BaseMotion(amplitude=0.4 * Y0, frequency=1400.0),
    ],
)
def test_sliding_under_normal_excitation(excitation):
    """F = 0.5 N, from rest at y0: x(t) within 1e-8 relative through stick and slip."""
    model = ms.Model(P, excitation=excitation)
    t_eval = np.linspace(0.0, 8e-3, 201)
    r = ms.simulate(model, force=0.5, duration=t_eval[-1], t_eval=t_eval)
    expected = ref.solve(model, force=0.5, state0=(Y0, 0.0, 0.0, 0.0), t_eval=t_eval)
    names = {ms.integrators.EVENT_NAMES[k] for k in r.event_kind}
    assert {"slip_start", "stick_start"} <= names  # stick-slip, not pure sliding
    assert expected.x[-1] > 0.0
    _close(r.x, expected.x, 1e-8)
    _close(r.y, expected.y, 1e-8)


def test_damped_forced_sliding_with_loss_of_contact():
    """Viscous damping, a harmonic force strong enough to lift the body off, F = 0.5 N."""
    model = ms.Model(
        P, damping=ms.Viscous(ratio=0.05),
        excitation=ms.HarmonicForce(amplitude=1.5 * P.mass * P.g, frequency=1300.0),
    )  # fmt: skip
    t_eval = np.linspace(0.0, 6e-3, 121)
    r = ms.simulate(model, force=0.5, duration=t_eval[-1], t_eval=t_eval)
    expected = ref.solve(model, force=0.5, state0=(Y0, 0.0, 0.0, 0.0), t_eval=t_eval)
    assert len(expected.events_of("contact_lost")[0]) >= 2
    _close(r.x, expected.x, 1e-8)
    _close(r.y, expected.y, 1e-8)
