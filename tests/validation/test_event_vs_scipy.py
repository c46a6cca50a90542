"""method="event" against an independent scipy DOP853 solution (``scipy_reference.py``).

The reference shares no code with microslip: it integrates (2.4)–(2.5) in natural scales
with its own event-driven restarts (contact, stick → slip, slip → stick). Paper cases:
F = 0.5 N with A = y0/3, 2y0/3, y0 (Figs. 4–5) and 1.3 y0 (loss of contact, Fig. 6).
"""

import numpy as np
import pytest

import microslip as ms

P = ms.Parameters()
Y0 = P.static_deflection
DURATION = 0.015  # ≈ 20–22 normal periods
T_EVAL = np.linspace(0.0, DURATION, 301)
TIGHT = {"rtol": 1e-12, "atol": 1e-14}
NAMES = ms.integrators.EVENT_NAMES
FRACTIONS = [1 / 3, 2 / 3, 1.0, 1.3]


def relative_errors(r, ref):
    ex = np.max(np.abs(r.x - ref.x)) / np.max(np.abs(ref.x))
    ey = np.max(np.abs(r.y - ref.y)) / np.max(np.abs(ref.y))
    return ex, ey


@pytest.mark.parametrize("fraction", FRACTIONS)
def test_event_method_matches_scipy(reference, fraction):
    amplitude = fraction * Y0
    ref = reference(P, force=0.5, amplitude=amplitude, t_eval=T_EVAL)
    assert ref.x[-1] > 0.0
    r = ms.simulate(P, force=0.5, amplitude=amplitude, duration=DURATION, t_eval=T_EVAL, **TIGHT)
    ex, ey = relative_errors(r, ref)
    assert ex < 1e-8  # measured <= 4.3e-10
    assert ey < 1e-8  # measured <= 1.9e-10
    np.testing.assert_allclose(r.xdot, ref.xdot, rtol=0, atol=1e-8 * np.max(np.abs(ref.xdot)))
    np.testing.assert_allclose(r.ydot, ref.ydot, rtol=0, atol=1e-8 * np.max(np.abs(ref.ydot)))


@pytest.mark.parametrize("fraction", FRACTIONS)
def test_event_method_at_default_tolerances(reference, fraction):
    amplitude = fraction * Y0
    ref = reference(P, force=0.5, amplitude=amplitude, t_eval=T_EVAL)
    r = ms.simulate(P, force=0.5, amplitude=amplitude, duration=DURATION, t_eval=T_EVAL)
    ex, ey = relative_errors(r, ref)
    # The requirement for method="event" at its defaults (rtol 1e-11, atol 1e-13):
    # measured x <= 4.4e-9 (A = y0/3, the smallest slips), y <= 2.2e-9.
    assert ex < 1e-8
    assert ey < 1e-8


@pytest.mark.parametrize("fraction", FRACTIONS)
def test_switching_instants_match_scipy(reference, fraction):
    amplitude = fraction * Y0
    ref = reference(P, force=0.5, amplitude=amplitude, t_eval=T_EVAL)
    r = ms.simulate(P, force=0.5, amplitude=amplitude, duration=DURATION, **TIGHT)
    kinds = ["slip_start", "stick_start"]
    if fraction != 1.0:  # at A = y0 the top just grazes y = 0: contact events are marginal
        kinds += ["contact_lost", "contact_made"]
    for kind in kinds:
        mine = r.event_t[r.event_kind == NAMES.index(kind)]
        theirs, _x = ref.events_of(kind)
        assert mine.size == theirs.size, kind
        np.testing.assert_allclose(mine, theirs, rtol=0, atol=1e-9 * P.natural_period)
    if fraction > 1.0:
        assert np.count_nonzero(r.event_kind == NAMES.index("contact_lost")) >= 15
    stops = r.event_kind == NAMES.index("stick_start")
    _t, x_ref = ref.events_of("stick_start")
    np.testing.assert_allclose(r.event_states[stops, 2], x_ref, rtol=1e-8)


@pytest.mark.parametrize(
    ("fields", "fraction", "force"),
    [
        ({"m2": 1.5, "mu": 0.3, "mass": 2.0}, 0.8, 2.0),
        ({"m2": 1.5, "mu": 0.3, "mass": 2.0}, 1.4, 2.0),
        ({"m2": 3.0, "mu": 0.2, "area": 3e-3}, 1.2, 0.5),
    ],
    ids=["m2=1.5", "m2=1.5-flight", "m2=3-flight"],
)
def test_other_parameters_match_scipy(reference, fields, fraction, force):
    p = ms.Parameters(**fields)
    amplitude = fraction * p.static_deflection
    duration = 12 * ms.free_period(p, amplitude)
    t_eval = np.linspace(0.0, duration, 301)
    ref = reference(p, force=force, amplitude=amplitude, t_eval=t_eval)
    r = ms.simulate(p, force=force, amplitude=amplitude, duration=duration, t_eval=t_eval, **TIGHT)
    ex, ey = relative_errors(r, ref)
    assert ex < 1e-8  # measured <= 5e-11
    assert ey < 1e-8  # measured <= 4e-10
    assert ref.event_kind.count("stick_start") >= 10


@pytest.mark.parametrize("fraction", [0.5, 1.0])
def test_linear_spring_closed_form(reference, fraction):
    """m2 = 1 and F > μ m g (1 + A/y0): harmonic normal motion and permanent sliding,

    y = y0 − A cos ωt,  x = ½ (F/m − μ g) t² + μ g (A/y0)(1 − cos ωt)/ω²,  ω² = g/y0,

    a closed form for both the reference and the event method."""
    p = ms.Parameters(m2=1.0, c_n=2e10)
    y0 = p.mass * p.g / (p.area * p.c_n)
    omega = np.sqrt(p.g / y0)
    amplitude = fraction * y0
    force = 1.01 * p.mu * p.mass * p.g * (1.0 + fraction)
    t = np.linspace(0.0, 20 * 2 * np.pi / omega, 401)
    y = y0 - amplitude * np.cos(omega * t)
    x = (
        0.5 * (force / p.mass - p.mu * p.g) * t**2
        + p.mu * p.g * fraction * (1.0 - np.cos(omega * t)) / omega**2
    )
    ref = reference(p, force=force, amplitude=amplitude, t_eval=t)
    r = ms.simulate(p, force=force, amplitude=amplitude, duration=t[-1], t_eval=t, **TIGHT)
    for sol in (ref, r):  # measured: y <= 3.2e-11 y0, x <= 1.5e-14 max x
        np.testing.assert_allclose(sol.y, y, rtol=0, atol=1e-10 * y0)
        np.testing.assert_allclose(sol.x, x, rtol=0, atol=1e-10 * np.max(x))
        assert np.all(sol.xdot[1:] > 0.0)
