"""k_t → ∞: a compliant tangential contact tends to the paper's rigid one.

The paper's model under a constant force below μ m g creeps on its free normal vibration
(A > y0: loss of contact every period) at the exact steady mean velocity of
``ms.mean_velocity(ms.Model(p), force=F, amplitude=A)`` (docs/model-facts.md, fact 6).
With a tangential spring k_t the body also oscillates on the spring at sqrt(k_t/m)
(undamped, excited at each stick and slip of the contact point) and the contact point
loads through the spring's deflection ~ F/k_t before it slips. The mean velocity over 20
normal periods (event method; K_n = 8.7e7 N/m) approaches the rigid value as k_t grows:
relative errors at k_t = 1e9, 1e10, 1e11 N/m are 0.70, 0.088, 0.0045 at A = 1.3 y0
(8 and 20 times less per decade) and 0.78, 0.0075, 0.0043 at A = 1.01 y0: about 1/k_t
over the two decades, the spring's deflection relative to the slip per period, with a
phase-dependent part from the oscillation on the spring (at 1e10 N/m and A = 1.01 y0
it nearly cancels). Stiffer still, through touchdown: the last test.
"""

import numpy as np
import pytest

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection
FORCE = 0.5  # N, below μ m g = 0.981 N
STIFFNESSES = [1e9, 1e10, 1e11]  # N/m


def compliant_mean_velocity(stiffness, amplitude):
    model = ms.Model(P, tangential=ms.TangentialSpring(stiffness), drive=ms.ConstantForce(FORCE))
    period = ms.free_period(P, amplitude)
    t_eval = np.array([2.0, 22.0]) * period  # whole normal periods after the first two
    r = ms.simulate(model, duration=t_eval[-1], amplitude=amplitude, t_eval=t_eval)
    return (r.x[1] - r.x[0]) / (t_eval[1] - t_eval[0])


@pytest.mark.parametrize("fraction", [1.3, 1.01])
def test_compliant_mean_velocity_tends_to_the_rigid_one(fraction):
    amplitude = fraction * Y0
    rigid = ms.mean_velocity(ms.Model(P), force=FORCE, amplitude=amplitude)
    assert rigid > 0.0
    errors = np.array(
        [abs(compliant_mean_velocity(k, amplitude) / rigid - 1.0) for k in STIFFNESSES]
    )
    # measured A = 1.3 y0: 0.70, 0.088, 0.0045; A = 1.01 y0: 0.78, 0.0075, 0.0043
    assert errors[-1] < 1e-2, errors
    assert np.all(errors[1:] < errors[:-1]), errors
    assert errors[0] / errors[-1] > 50.0, errors  # ~1/k_t: 100 over two decades


def test_the_rigid_model_as_a_composition_is_the_paper():
    """The reference value itself: Rigid() + ConstantForce(F) is the paper's model."""
    amplitude = 1.3 * Y0
    period = ms.free_period(P, amplitude)
    model = ms.Model(P, tangential=ms.Rigid(), drive=ms.ConstantForce(FORCE))
    t_eval = np.array([2.0, 22.0]) * period
    r = ms.simulate(model, duration=t_eval[-1], amplitude=amplitude, t_eval=t_eval)
    mean = (r.x[1] - r.x[0]) / (t_eval[1] - t_eval[0])
    rigid = ms.mean_velocity(ms.Model(P), force=FORCE, amplitude=amplitude)
    assert mean == pytest.approx(rigid, rel=1e-8)


def test_stiff_contact_through_touchdown():
    amplitude = 1.3 * Y0
    rigid = ms.mean_velocity(ms.Model(P), force=FORCE, amplitude=amplitude)
    assert compliant_mean_velocity(1e12, amplitude) == pytest.approx(rigid, rel=3e-3)


@pytest.mark.parametrize("m2", [2.0, 1.5])
def test_a_damped_forced_contact_that_separates_tends_to_the_rigid_one(m2):
    """Viscous damping and a harmonic force of 1.2 m g: the contact is lost inside the
    overlap (N_raw = 0 at δ > 0), at m2 = 1.5 while the contact point slides. There the
    event method stopped with a step size underflow: past the root, inside a trial step,
    slip's u̇ and ḟ took the flight values, a jump of ~Ṅ that no adaptive step passes.
    Now they continue the raw law to the switch, and x(T)/T tends to the rigid model's
    (whose damped, forced path is checked against scipy in
    test_h1_damped_forced_vs_scipy.py) as k_t grows. Measured relative errors at
    k_t = 1e9, 1e10, 1e11, 1e12 N/m: m2 = 2: 0.43, 0.026, 0.0086, 0.00047 (unchanged);
    m2 = 1.5: 3.9, 0.21, 0.24, 0.0051 (the body's oscillation on the spring, excited at
    each switch, is not monotone in k_t)."""
    params = ms.Parameters(m2=m2)
    parts = {"damping": ms.Viscous(0.05), "excitation": ms.HarmonicForce(12.0, 1200.0)}
    duration, force = 0.01, 0.3
    rigid = ms.simulate(ms.Model(params, **parts), force=force, duration=duration).x[-1]
    errors, separations = [], []
    for stiffness in [1e9, 1e12]:
        model = ms.Model(params, tangential=ms.TangentialSpring(stiffness), **parts)
        r = ms.simulate(model, force=force, duration=duration)
        errors.append(abs(r.x[-1] / rigid - 1.0))
        lost = r.event_kind == ms.integrators.EVENT_NAMES.index("contact_lost")
        separations.append(np.count_nonzero(r.event_states[lost, 0] > 0.0))
    assert min(separations) >= 5  # lost inside the overlap (δ = y > 0), every time
    assert errors[1] < 1e-2, errors
    assert errors[0] > 50.0 * errors[1], errors
