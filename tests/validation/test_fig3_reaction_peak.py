"""Fig. 3 and docs/model-facts.md, facts 3–4: the normal reaction over a free vibration.

* A = y0 (just touching at the top), m2 = 2: |R| runs from 0 to exactly 3 m g ("from
  nearly 0 up to approximately 3 times its static value", Sec. 3). In general, for A = y0
  energy conservation gives S c_n y_max^(m2+1)/(m2+1) = m g y_max, so max|R| = (m2 + 1) m g.
* The time average of |R| over a period is exactly m g, with or without loss of contact
  (Sec. 4: "the mean values of the normal reaction ... do not undergo any change").
"""

import numpy as np
import pytest
from scipy.integrate import trapezoid

import microslip as ms

TIGHT = {"rtol": 1e-12, "atol": 1e-14}


@pytest.mark.parametrize("m2", [1.5, 2.0, 3.0])
def test_peak_reaction_at_a_equal_y0(m2):
    p = ms.Parameters(m2=m2)
    y0, mg = p.static_deflection, p.mass * p.g
    low, high = ms.turning_points(p, y0)
    assert low == 0.0
    assert high == pytest.approx((m2 + 1.0) ** (1.0 / m2) * y0, rel=1e-13)  # √3 y0 for m2 = 2
    # The lowest point is reached at half the period (time symmetry of the orbit).
    period = ms.free_period(p, y0)
    r = ms.simulate(p, force=0.0, amplitude=y0, duration=period, t_eval=[period / 2], **TIGHT)
    assert r.R[0] == pytest.approx((m2 + 1.0) * mg, rel=1e-10)


def test_fig3_reaction_range_is_0_to_3mg():
    p = ms.Parameters()
    y0, mg = p.static_deflection, p.mass * p.g
    period = ms.free_period(p, y0)
    t_eval = np.linspace(0.0, 3 * period, 30001)
    r = ms.simulate(p, force=0.0, amplitude=y0, duration=3 * period, t_eval=t_eval)
    assert r.R.min() == 0.0
    assert r.R.max() <= 3.0 * mg * (1.0 + 1e-9)
    assert r.R.max() >= 3.0 * mg * (1.0 - 1e-6)  # sampling: (ω Δt)² ~ 1e-6
    # Friction limit μ|R| in Fig. 3b: from 0 to 3 μ m g.
    assert r.friction_limit.max() == pytest.approx(3.0 * p.mu * mg, rel=1e-6)


@pytest.mark.parametrize("fraction", [0.5, 1.0, 1.5, 2.0])
def test_mean_reaction_over_one_period_is_mg(fraction):
    p = ms.Parameters()
    y0, mg = p.static_deflection, p.mass * p.g
    period = ms.free_period(p, fraction * y0)
    t_eval = np.linspace(0.0, period, 8193)
    r = ms.simulate(p, force=0.5, amplitude=fraction * y0, duration=period, t_eval=t_eval, **TIGHT)
    if fraction > 1.0:
        assert np.any(r.R == 0.0) and np.any(r.state == 2)  # loss of contact
    # Quadrature of the simulated |R| over exactly one period (measured <= 3e-12).
    assert trapezoid(r.R, r.t) / period == pytest.approx(mg, rel=1e-9)
    # Impulse balance of (2.4): ∫|R| dt = m g T − m (ẏ(T) − ẏ(0)); the orbit closes.
    assert abs(r.ydot[-1] - r.ydot[0]) < 1e-10 * p.g * period
    assert r.y[-1] == pytest.approx(r.y[0], abs=1e-10 * y0)


def test_mean_reaction_over_many_periods_is_mg():
    p = ms.Parameters()
    mg = p.mass * p.g
    for fraction in (1 / 3, 1.3):
        period = ms.free_period(p, fraction * p.static_deflection)
        periods = 20
        t_eval = np.linspace(0.0, periods * period, 40 * 1024 + 1)
        amplitude = fraction * p.static_deflection
        r = ms.simulate(
            p, force=0.5, amplitude=amplitude, duration=t_eval[-1], t_eval=t_eval, **TIGHT
        )
        assert trapezoid(r.R, r.t) / t_eval[-1] == pytest.approx(mg, rel=1e-8)
        # ... although the instantaneous reaction varies widely.
        assert r.R.max() > 1.5 * mg and r.R.min() < 0.5 * mg
