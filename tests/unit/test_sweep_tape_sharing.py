"""Set-ups that differ only in friction coefficients share one normal tape in a time
sweep (sweeps/compute.py, ``_normal_setups``; the runner batches such chunks together,
``tape_order``): the grouping, and the same bits as sweeping each value alone."""

from __future__ import annotations

import numpy as np
import pytest

import microslip as ms
from microslip.sweeps import SweepSpec, sweep
from microslip.sweeps.compute import _normal_periods, _normal_setups, tape_order

P = ms.Parameters()
Y0 = P.static_deflection


def _grouping(models, normal0):
    normal0 = np.asarray(normal0, dtype=float)
    setups, setup_of_row, _ = _normal_setups(models, normal0, _normal_periods(models, normal0))
    return setups.tolist(), setup_of_row.tolist()


def test_rows_share_a_set_up_when_only_friction_differs():
    forced = ms.Model(P, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(2.0, 1400.0))
    start = [[Y0, 0.0]] * 5
    models = [
        forced,
        forced.replace(mu=0.2),
        forced.replace(friction=ms.StaticKinetic(0.3, 0.2)),
        forced.replace(**{"damping.ratio": 0.06}),  # another normal motion
        forced.replace(**{"excitation.amplitude": 2.5}),  # another normal motion
    ]
    assert _grouping(models, start) == ([0, 3, 4], [0, 0, 0, 1, 2])
    # Another start (amplitude) is another set-up; so is another spring (held per
    # set-up by the spring kernel), but not another friction law on the same spring.
    free = ms.Model(P, tangential=ms.TangentialSpring(P.contact_stiffness))
    models = [free, free.replace(mu=0.3), free, free.replace(**{"tangential.stiffness": 1e7})]
    starts = [[0.5 * Y0, 0.0], [0.5 * Y0, 0.0], [0.8 * Y0, 0.0], [0.5 * Y0, 0.0]]
    assert _grouping(models, starts) == ([0, 2, 3], [0, 0, 1, 2])


def test_chunks_that_differ_only_in_friction_come_together():
    spec = SweepSpec.build(
        ms.Model(P, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(2.0, 1400.0)),
        {"mu": [0.1, 0.2, 0.3], "excitation.amplitude": [1.0, 2.0]}, [0.3],
        method="time", duration=0.001,
    )  # fmt: skip
    keys = sorted(spec.chunks(), key=tape_order(spec))
    # The excitation amplitude (a normal field) varies slowest, mu fastest.
    assert [key[:2] for key in keys] == [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (2, 1)]


CASES = {
    "forced rigid": (
        ms.Model(P, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(4.0, 1400.0)),
        {"excitation.amplitude": [2.0, 5.0]}, None,
    ),
    "damped spring": (
        ms.Model(P, damping=ms.Viscous(0.02),
                 tangential=ms.TangentialSpring(P.contact_stiffness)),
        {}, [0.5 * Y0, 1.3 * Y0],
    ),
    # A Hertz contact's set-ups that fly: the lanes cross each flight on the scalar step,
    # each row with its μ.
    "hertz mindlin": (
        ms.Model(ms.Parameters(m2=1.5), tangential=ms.MindlinSpring(0.8235)), {},
        [0.5 * ms.Parameters(m2=1.5).static_deflection,
         1.4 * ms.Parameters(m2=1.5).static_deflection],
    ),
}  # fmt: skip


@pytest.mark.parametrize("name", list(CASES))
def test_a_friction_axis_gives_each_value_the_bits_of_its_own_sweep(name):
    """A sweep over μ (one tape per normal set-up for all its values) against one sweep
    per μ (a tape each): the same bits at every point. Several values also move."""
    model, axes, amplitudes = CASES[name]
    mu = [0.05, 0.1, 0.2]
    limit = model.params.static_friction_force
    options = dict(force=np.array([0.2, 0.6, 0.95]) * limit, amplitude=amplitudes,
                   method="time", duration=4 * model.params.natural_period)  # fmt: skip
    together = np.asarray(sweep(model, {"mu": mu, **axes}, **options).values)
    for k, value in enumerate(mu):
        alone = np.asarray(sweep(model.replace(mu=value), axes or None, **options).values)
        np.testing.assert_array_equal(together[k], alone)
    assert np.unique(together.round(15)).size > 3
