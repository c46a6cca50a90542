"""The power law S c_n δ^m2 of eq. (2.3) and its stiffness, compiled
(``model/contact.py``), against a direct evaluation in Python: m2 = 2 (the paper's)
and m2 = 1.5 (Hertz) have fast paths (a product, a square root) that must give the
law to within an ulp or two."""

import numpy as np
import pytest

import microslip as ms
from microslip.model.coefficients import as_tuple
from microslip.model.contact import elastic_force, elastic_stiffness


@pytest.mark.parametrize("m2", [1.0, 1.5, 2.0, 2.5, 10.0 / 9.0])
def test_power_law_and_its_stiffness(m2):
    params = ms.Parameters(m2=m2)
    c = as_tuple(ms.Model(params).pack(0.0))
    scn = params.stiffness_coefficient
    y0 = params.static_deflection
    for delta in np.geomspace(1e-6 * y0, 10.0 * y0, 57):
        force = elastic_force(delta, c)
        stiffness = elastic_stiffness(delta, c)
        assert force == pytest.approx(scn * float(delta) ** m2, rel=4e-16)
        assert stiffness == pytest.approx(m2 * scn * float(delta) ** (m2 - 1.0), rel=4e-16)
    for delta in (0.0, -y0):
        assert elastic_force(delta, c) == 0.0
        assert elastic_stiffness(delta, c) == 0.0
    # at the static deflection the law carries the weight (y0 = (m g / S c_n)^(1/m2))
    assert elastic_force(y0, c) == pytest.approx(params.mass * params.g, rel=1e-14)
