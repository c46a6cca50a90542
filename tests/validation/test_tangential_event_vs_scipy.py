"""method="event" with the tangential parts against an independent scipy integration.

The reference (``tangential_reference.py``) writes the laws out again from the physics
and restarts DOP853 at every stick/slip/flight switch. Cases: a harmonic drive with
reversals and backward sliding (rigid, static/kinetic), spring drives under normal
vibration with loss of contact (static/kinetic, Stribeck), a compliant contact (constant
stiffness and Mindlin) under force drives, with the body oscillating on the tangential
spring, and the kinematic drive on a prescribed penetration with and without loss of
contact (also the flat punch, m2 = 1).
"""

import numpy as np
import pytest
from tangential_reference import reference_solution

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection
T0 = P.natural_period
KN = P.contact_stiffness
F0 = P.natural_frequency
SK = ms.StaticKinetic(mu_static=0.15, mu_kinetic=0.1)
TIGHT = {"rtol": 1e-12, "atol": 1e-14}
NAMES = ms.integrators.EVENT_NAMES
PUNCH = ms.Parameters(m2=1.0, area=1.0, c_n=KN)  # flat punch: N = K_n δ, same y0 and f0


def presc(amplitude, params=P):
    return ms.PrescribedPenetration(mean=Y0, amplitude=amplitude, frequency=F0)


# name: (model, amplitude A [m] of the free vibration or None, duration [s])
CASES = {
    "harmonic-reversals": (
        ms.Model(P, friction=SK, drive=ms.HarmonicDrive(mean=0.3, amplitude=3.0, frequency=300.0)),
        0.0, 0.01,
    ),
    "harmonic-reversals-vibrating": (
        ms.Model(P, friction=SK, drive=ms.HarmonicDrive(mean=0.3, amplitude=3.0, frequency=300.0)),
        0.8 * Y0, 0.01,
    ),
    "spring-loss-of-contact": (
        ms.Model(P, friction=SK, drive=ms.SpringDrive(stiffness=1e6, velocity=1e-3)),
        1.3 * Y0, 0.02,
    ),
    "stribeck-spring": (
        ms.Model(P, friction=ms.Stribeck(0.15, 0.1, velocity=1e-3, exponent=2.0),
                 drive=ms.SpringDrive(stiffness=1e6, velocity=1e-3)),
        0.5 * Y0, 0.02,
    ),
    "compliant-force": (
        ms.Model(P, tangential=ms.TangentialSpring(KN), friction=SK, drive=ms.ConstantForce(0.5)),
        0.8 * Y0, 0.01,
    ),
    "compliant-force-flight": (
        ms.Model(P, tangential=ms.TangentialSpring(KN), friction=SK, drive=ms.ConstantForce(0.5)),
        1.3 * Y0, 0.01,
    ),
    "compliant-harmonic": (
        ms.Model(P, tangential=ms.TangentialSpring(KN), friction=SK,
                 drive=ms.HarmonicDrive(mean=0.2, amplitude=2.0, frequency=300.0)),
        0.5 * Y0, 0.01,
    ),
    "mindlin-force": (
        ms.Model(P, tangential=ms.MindlinSpring(0.8235), friction=SK, drive=ms.ConstantForce(0.5)),
        0.8 * Y0, 0.01,
    ),
    "mindlin-spring-flight": (
        ms.Model(P, tangential=ms.MindlinSpring(0.8235), friction=SK,
                 drive=ms.SpringDrive(stiffness=1e6, velocity=1e-3)),
        1.3 * Y0, 0.01,
    ),
    "kinematic-prescribed": (
        ms.Model(P, excitation=presc(0.5 * Y0), tangential=ms.TangentialSpring(KN), friction=SK,
                 drive=ms.PrescribedVelocity(1e-4)),
        None, 0.005,
    ),
    "mindlin-kinematic-flight": (
        ms.Model(P, excitation=presc(1.5 * Y0), tangential=ms.MindlinSpring(0.8235), friction=SK,
                 drive=ms.PrescribedVelocity(1e-4)),
        None, 0.005,
    ),
    "punch-kinematic-flight": (
        ms.Model(PUNCH, excitation=presc(1.5 * Y0), tangential=ms.TangentialSpring(KN),
                 friction=SK, drive=ms.PrescribedVelocity(1e-4)),
        None, 0.005,
    ),
}  # fmt: skip
COMPLIANT = [name for name, (m, _a, _d) in CASES.items() if m.is_compliant]


def _kwargs(amplitude):
    return {} if amplitude is None else {"amplitude": amplitude}


def _reference(name, t_eval):
    model, amplitude, _duration = CASES[name]
    return reference_solution(model, t_eval=t_eval, amplitude=amplitude)


def _run(name, **kw):
    model, amplitude, duration = CASES[name]
    return ms.simulate(model, duration=duration, **_kwargs(amplitude), **kw)


def _grid(name):
    return np.linspace(0.0, CASES[name][2], 401)


def _errors(r, ref):
    def rel(a, b, scale):
        return np.max(np.abs(a - b)) / scale

    return {
        "x": rel(r.x, ref.x, np.max(np.abs(ref.x))),
        "xdot": rel(r.xdot, ref.xdot, np.max(np.abs(ref.xdot))),
        "y": rel(r.y, ref.y, np.max(np.abs(ref.y))),
        "f": rel(r.spring_force, ref.f, 0.15 * P.mass * P.g),
    }


@pytest.mark.parametrize("name", list(CASES))
def test_trajectory_matches_scipy(name):
    t_eval = _grid(name)
    ref = _reference(name, t_eval)
    r = _run(name, t_eval=t_eval, **TIGHT)
    errors = _errors(r, ref)
    # measured <= 3.9e-11 (x, ẋ, y; f relative to μ_s m g) over all cases
    assert max(errors.values()) < 1e-9, errors


@pytest.mark.parametrize("name", list(CASES))
def test_trajectory_at_default_tolerances(name):
    t_eval = _grid(name)
    ref = _reference(name, t_eval)
    r = _run(name, t_eval=t_eval)
    errors = _errors(r, ref)
    # ~1e-8 at the defaults (rtol 1e-11, atol 1e-13): measured <= 1.2e-9 (y, loss of contact)
    assert max(errors.values()) < 1e-8, errors


def _kept(times, kinds):
    """Switches compared: not at t = 0 (a start in flight may count as a slip there),
    and a grazing touchdown where the point slides at once counts once: a stick of zero
    length (contact_made, then slip_start at the same instant) is the same motion as
    a contact_made that slides."""
    kinds = list(kinds)
    keep = times > 1e-9 * T0
    for i in range(1, len(kinds)):
        if (kinds[i] == "slip_start" and kinds[i - 1] == "contact_made"
                and times[i] - times[i - 1] <= 1e-9 * T0):  # fmt: skip
            keep[i] = False
    return keep


def _switches(times, kinds):
    keep = _kept(times, kinds)
    return times[keep], [k for k, flag in zip(kinds, keep, strict=True) if flag]


@pytest.mark.parametrize("name", list(CASES))
def test_switching_instants_match_scipy(name):
    ref = _reference(name, _grid(name))
    r = _run(name, **TIGHT)
    mine, _k = _switches(r.event_t, [NAMES[k] for k in r.event_kind])
    theirs, _k = _switches(ref.event_t, ref.event_kind)
    assert mine.size == theirs.size >= 3
    np.testing.assert_allclose(mine, theirs, rtol=0, atol=1e-9 * T0)
    # measured <= 1.2e-11 T0; the state just after each switch: body position and
    # spring force
    keep_m = _kept(r.event_t, [NAMES[k] for k in r.event_kind])
    keep_r = _kept(ref.event_t, ref.event_kind)
    np.testing.assert_allclose(
        r.event_states[keep_m, 2], ref.event_states[keep_r, 2], rtol=0,
        atol=1e-9 * np.max(np.abs(ref.x)),
    )  # fmt: skip
    np.testing.assert_allclose(
        r.event_states[keep_m, 5], ref.event_states[keep_r, 5], rtol=0, atol=1e-9 * P.mass * P.g
    )


@pytest.mark.parametrize("name", CASES)
def test_switch_kinds_match_scipy(name):
    ref = _reference(name, _grid(name))
    r = _run(name, **TIGHT)
    _t, mine = _switches(r.event_t, [NAMES[k] for k in r.event_kind])
    _t, theirs = _switches(ref.event_t, ref.event_kind)
    assert mine == theirs


def test_cases_show_what_they_claim():
    """Reversals and backward sliding under the harmonic drive; loss of contact; the
    body oscillating on the tangential spring while its contact point sticks."""
    r = _run("harmonic-reversals", **TIGHT)
    assert np.count_nonzero(r.event_kind == NAMES.index("reversal")) >= 4
    assert r.xdot.min() < 0.0 < r.xdot.max()
    r = _run("spring-loss-of-contact", **TIGHT)
    assert np.count_nonzero(r.event_kind == NAMES.index("contact_lost")) >= 10
    r = _run("compliant-force", **TIGHT)
    stuck = r.direction == 0
    assert np.ptp(r.x[stuck]) > 0.0 and np.any(np.diff(np.sign(r.xdot[stuck])) != 0)


@pytest.mark.parametrize("name", COMPLIANT)
def test_contact_point_position_matches_scipy(name):
    """The massless point jumps by (μ_s − μ_k) N / k_t when it starts to slip."""
    t_eval = _grid(name)
    ref = _reference(name, t_eval)
    r = _run(name, t_eval=t_eval, **TIGHT)
    assert np.max(np.abs(r.u - ref.u)) < 1e-9 * np.max(np.abs(ref.x))
