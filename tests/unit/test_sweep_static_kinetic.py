"""Time sweeps with StaticKinetic friction: what the spec accepts and refuses, where the
coefficients go, and the estimate's kinetic limit (the agreement with the event method
is tests/validation/test_time_map_static_kinetic_vs_event.py)."""

from __future__ import annotations

import numpy as np
import pytest

import microslip as ms
from microslip.sweeps import SweepSpec, sweep
from microslip.sweeps.axes import kinetic_mu_grid

P = ms.Parameters()
TANGENTIAL = {
    "rigid": None,
    "spring": ms.TangentialSpring(P.contact_stiffness),
    "mindlin": ms.MindlinSpring(0.8235),
}
RUN = dict(force=[0.3, 0.9, 1.2], amplitude=[0.0, 1e-7, 3e-7], method="time", duration=0.003)


@pytest.mark.parametrize("kind", list(TANGENTIAL))
def test_equal_coefficients_give_the_coulomb_bits(kind):
    """StaticKinetic(μ, μ) is Coulomb friction μ: the same lanes, the same bits. A sweep
    that read the law's coefficients into the wrong slots, or Parameters.mu in place of
    them, fails here (μ = 0.13 is not the paper's 0.1)."""
    coulomb = ms.Model(P.replace(mu=0.13), tangential=TANGENTIAL[kind])
    static = ms.Model(P, tangential=TANGENTIAL[kind], friction=ms.StaticKinetic(0.13, 0.13))
    expected = np.asarray(sweep(coulomb, None, **RUN).values)
    assert np.abs(expected).max() > 0.0
    assert np.array_equal(np.asarray(sweep(static, None, **RUN).values), expected)


def test_a_swept_coefficient_gives_each_value_its_own_bits():
    """An axis over friction.mu_static: each slice is the sweep at that value alone."""
    model = ms.Model(P, friction=ms.StaticKinetic(0.15, 0.1))
    values = [0.1, 0.15, 0.3]
    swept = sweep(model, {"friction.mu_static": values}, **RUN)
    assert swept.dims[0] == "friction.mu_static"
    for k, mu_s in enumerate(values):
        alone = sweep(model.replace(**{"friction.mu_static": mu_s}), None, **RUN)
        assert np.array_equal(np.asarray(swept.values[k]), np.asarray(alone.values))
    # A higher static limit holds more: never faster, somewhere strictly slower.
    v = np.asarray(swept.values)
    assert np.all(v[1] <= v[0]) and np.all(v[2] <= v[1]) and np.any(v[2] < v[0])


def test_steady_refuses_static_kinetic_and_names_the_time_method():
    model = ms.Model(P, friction=ms.StaticKinetic(0.15, 0.1))
    with pytest.raises(ms.UnsupportedModelError, match="friction=StaticKinetic") as error:
        sweep(model, None, force=[0.5], amplitude=[1e-7])
    assert "method='time' also takes" in str(error.value)
    assert "StaticKinetic friction" in str(error.value)


def test_the_estimate_counts_lanes_past_the_kinetic_limit():
    """Lanes above μ_k m g slide for ever once released (they never park): the estimate's
    limit is the kinetic coefficient's, the law's own or its axis', never the unused
    Parameters.mu (0.3 here, which would put every force below the limit)."""
    model = ms.Model(P.replace(mu=0.3), friction=ms.StaticKinetic(0.3, 0.12))
    assert kinetic_mu_grid(model, ()) == pytest.approx(0.12)
    axes = (("friction.mu_kinetic", np.array([0.05, 0.1])),)
    np.testing.assert_array_equal(kinetic_mu_grid(model, axes), [0.05, 0.1])
    assert kinetic_mu_grid(ms.Model(P.replace(mu=0.2)), ()) == pytest.approx(0.2)
    # Between μ_k m g and μ_s m g a free vibration's lanes may run away: more work than
    # the same forces under a Coulomb μ_s, where they all stay below the limit.
    forces = np.linspace(1.3, 2.9, 8)  # N, μ_k m g = 1.18 N < F < μ_s m g = 2.94 N
    options = dict(forces=forces, amplitudes=np.linspace(0.0, 2e-7, 8), method="time",
                   duration=1.0, allow_large=True)  # fmt: skip
    static = SweepSpec.build(model, None, **options).estimate()
    coulomb = SweepSpec.build(ms.Model(P.replace(mu=0.3)), None, **options).estimate()
    assert static.seconds > 2.0 * coulomb.seconds
