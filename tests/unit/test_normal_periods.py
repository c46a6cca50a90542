"""Which time-sweep set-ups run on a repeated one-period tape (sweeps/compute.py,
``_normal_periods``; integrators/periodic_tape.py): a conservative free vibration
started at rest above its equilibrium, with the period T(A) of ``free_period``, or at
rest at its equilibrium (N = m g for ever: any period, T0 taken); every other set-up
(damped, forced, moving at t = 0) is filled step by step (period 0). A damped or
forced set-up given a period would repeat a motion that is not periodic."""

from __future__ import annotations

import numpy as np

import microslip as ms
from microslip.sweeps.compute import _normal_periods

P = ms.Parameters()
Y0 = P.static_deflection


def test_only_conservative_free_vibrations_from_rest_get_a_period():
    free = ms.Model(P)
    spring = ms.Model(P, tangential=ms.TangentialSpring(P.contact_stiffness))
    damped = ms.Model(P, damping=ms.Viscous(0.05))
    forced = ms.Model(P, excitation=ms.HarmonicForce(2.0, 1400.0))
    cases = [
        (free, (Y0 - 1e-7, 0.0), ms.free_period(P, 1e-7)),
        (spring, (Y0 - 4e-7, 0.0), ms.free_period(P, 4e-7)),  # with loss of contact
        (damped, (Y0 - 1e-7, 0.0), 0.0),
        (forced, (Y0, 0.0), 0.0),
        (free, (Y0, 0.0), P.natural_period),  # at rest at equilibrium: no vibration
        (free, (Y0 - 1e-7, 1e-4), 0.0),  # moving at t = 0: not the top of its orbit
    ]
    periods = _normal_periods([m for m, _, _ in cases], np.array([s for _, s, _ in cases]))
    assert np.array_equal(periods, [t for _, _, t in cases])
