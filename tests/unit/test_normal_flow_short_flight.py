"""A flight shorter than a step of the normal flow (analysis/normal_flow.py): the
contact function is inside contact at both ends of the step and dips out between, so
only the search for its extremum (``_dip``) finds the two switches.

From a slight penetration δ0 moving up at v the body leaves the contact almost at once
and falls back after ~2v/g, a third of the step here. One step must find the lift-off
and the touchdown and end where 200 steps over the same time end (where each switch
falls in a step of its own). A search that gives up on the dip too early steps over the
flight (no switch, and the end state off by the flight's missing contact force)."""

import numpy as np

import microslip as ms
from microslip.analysis.normal_flow import S_EVENTS, propagate

P = ms.Parameters()


def test_a_flight_inside_one_step_is_found():
    c = ms.Model(P).pack(0.0)
    h = P.natural_period / 13.0  # a transient's step (periodic.transient_steps)
    v = 0.5 * P.g * h / 3.0  # flight 2v/g = h/3
    delta0 = 1e-3 * v * h
    coarse = propagate(c, delta0, -v, 0.0, h, 1, False, False)
    fine = propagate(c, delta0, -v, 0.0, h, 200, False, False)
    assert fine[4][S_EVENTS] == 2.0  # lift-off and touchdown
    assert coarse[4][S_EVENTS] == 2.0
    scale = np.array([P.static_deflection, P.static_deflection / P.natural_period])
    np.testing.assert_allclose(coarse[0] / scale, fine[0] / scale, rtol=0, atol=1e-10)
