"""The sweep definition: validation, chunk geometry and identity."""

import numpy as np
import pytest

from microslip import Parameters
from microslip.sweeps import SweepSpec

F = np.linspace(0.1, 0.9, 5)
A = np.linspace(0.0, 3e-7, 10)


def test_chunks_cover_the_grid_exactly_once():
    spec = SweepSpec.build(None, {"mu": [0.1, 0.2], "m2": [1.5, 2.0, 2.5]}, F, A, amplitude_chunk=4)
    assert spec.dims == ("mu", "m2", "force", "amplitude")
    assert spec.shape == (2, 3, 5, 10)
    assert spec.chunk_grid == (2, 3, 3)
    covered = np.zeros(spec.shape, dtype=int)
    for key in spec.chunks():
        covered[spec.region(key)] += 1
    assert (covered == 1).all()
    assert spec.params_at((1, 2, 0)) == Parameters(mu=0.2, m2=2.5)


def test_fingerprint_tracks_every_input():
    base = SweepSpec.build(None, None, F, A)
    assert base.fingerprint() == SweepSpec.build(None, None, F, A).fingerprint()
    assert base.fingerprint() != SweepSpec.build(None, None, F, A * 1.0000001).fingerprint()
    assert base.fingerprint() != SweepSpec.build(Parameters(mu=0.2), None, F, A).fingerprint()
    changed = SweepSpec.build(None, None, F[:-1], A)
    assert changed.differences(base.definition()) == ["forces"]


@pytest.mark.parametrize(
    ("axes", "forces", "amplitudes", "message"),
    [
        ({"stiffness": [1.0]}, F, A, "unknown parameter 'stiffness'"),
        ({"force": [1.0]}, F, A, "sweep axis of its own"),
        ({"mu": [-0.1]}, F, A, "mu must be >= 0"),
        ({"mass": [1.0, np.nan]}, F, A, "mass must be finite"),
        ({"mu": []}, F, A, "mu must not be empty"),
        (None, [], A, "force must not be empty"),
        (None, [-0.1, 0.2], A, "force must be >= 0"),
        (None, F, [np.nan], "amplitude must be finite"),
        (None, F, [-1e-7], "amplitude must be >= 0"),
    ],
)
def test_bad_sweeps(axes, forces, amplitudes, message):
    with pytest.raises(ValueError, match=message):
        SweepSpec.build(None, axes, forces, amplitudes)


def test_bad_method_and_chunk():
    with pytest.raises(ValueError, match="method"):
        SweepSpec.build(None, None, F, A, method="fast")
    with pytest.raises(ValueError, match="amplitude_chunk"):
        SweepSpec.build(None, None, F, A, amplitude_chunk=0)
