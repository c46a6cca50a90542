"""Parameters, forces and amplitudes: refused outside their documented physical ranges.

Issue 8, defect 5: degenerate inputs used to pass (y0 ~ 1e150 m, T0 = 1e76 s), crash
(ZeroDivisionError, step size underflow) or overflow; each must now give one clear
ValueError naming the quantity and its value, while the extreme valid values still run.
"""

import math
import re
import warnings

import numpy as np
import pytest

import microslip as ms
from microslip.model.parameters import DERIVED_RANGES, FIELD_RANGES

PAPER = ms.Parameters()


def c_n_for(y0, *, mass=1.0, g=9.81, area=42.735e-4, m2=2.0):
    """The c_n that gives the static deflection y0 [m]: S c_n y0^m2 = m g (2.3)."""
    return math.exp(math.log(mass * g / area) - m2 * math.log(y0))


@pytest.mark.parametrize(
    ("fields", "quantity", "value_text"),
    [
        ({"c_n": 1e-300}, "y0", "4.791e+151 m"),  # was accepted: T0 = 1e76 s
        ({"c_n": 1e300}, "y0", "4.791e-149 m"),
        ({"c_n": 1e300, "area": 1e300}, "area", "1e+300"),  # was ZeroDivisionError
        ({"mass": 1e-300}, "mass", "1e-300"),  # was accepted
        ({"m2": 25.0}, "m2", "25.0"),
        ({"mu": 11.0}, "mu", "11.0"),
        ({"g": 1e5}, "g", "100000.0"),
    ],
)
def test_degenerate_parameters_are_refused_naming_the_quantity(fields, quantity, value_text):
    with pytest.raises(ValueError) as info:
        ms.Parameters(**fields)
    message = str(info.value)
    assert quantity in message and value_text in message
    assert "\n" not in message


def test_from_interface_overflow_is_a_value_error():
    with pytest.raises(ValueError, match="c_n"):
        ms.Parameters.from_interface(e_n=1e-300, m1=0.1)  # e_n^(-1/m1) = 1e3000


@pytest.mark.parametrize(("name", "end"), [(n, e) for n in FIELD_RANGES for e in (0, 1)])
def test_field_range_ends_are_accepted_and_just_outside_refused(name, end):
    value = FIELD_RANGES[name][end]
    # Pick c_n so that y0 = 1e-6 m: only the field under test is at its limit.
    others = {"mass": 1.0, "g": 9.81, "area": 42.735e-4, "m2": 2.0}
    others[name] = value
    fields = {name: value}
    if name != "mu":
        fields["c_n"] = c_n_for(1e-6, **{k: v for k, v in others.items()})
    p = ms.Parameters(**fields)
    assert getattr(p, name) == value
    outside = value * (1 - 1e-9) if end == 0 else value * (1 + 1e-9)
    if name == "mu" and end == 0:
        outside = -1e-12
    with pytest.raises(ValueError, match=name):
        ms.Parameters(**{**fields, name: outside})


def at(y0, **fields):
    """Fields with c_n chosen for the static deflection y0 [m]."""
    return {**fields, "c_n": c_n_for(y0, **fields)}


def g_for_f0(f0, y0, m2):
    """g that gives f0 = sqrt(m2 g / y0) / (2 pi) [Hz] (Sec. 3)."""
    return (2.0 * math.pi * f0) ** 2 * y0 / m2


@pytest.mark.parametrize(
    ("quantity", "inside", "outside"),
    [
        ("y0", at(1.001e-15), at(0.999e-15)),
        ("y0", at(0.0999), at(0.1001)),
        (
            "f0",
            at(2e-15, g=g_for_f0(0.99e8, 2e-15, 2.0)),
            at(2e-15, g=g_for_f0(1.01e8, 2e-15, 2.0)),
        ),
        (
            "f0",
            at(0.09, m2=0.1, g=g_for_f0(1.01e-2, 0.09, 0.1)),
            at(0.09, m2=0.1, g=g_for_f0(0.99e-2, 0.09, 0.1)),
        ),
        # S c_n = m g / y0^m2 at m2 = 20: y0 = 1.2e-14 m fits, 1e-14 m does not.
        ("S c_n", at(1.2e-14, m2=20.0), at(1e-14, m2=20.0)),
    ],
)
def test_derived_range_ends(quantity, inside, outside):
    p = ms.Parameters(**inside)
    assert all(math.isfinite(v["value"]) and v["value"] >= 0 for v in p.describe().values())
    with pytest.raises(ValueError) as info:
        ms.Parameters(**outside)
    low, high = DERIVED_RANGES[quantity][:2]
    assert f"{quantity} = " in str(info.value)
    assert f"[{low:g}, {high:g}]" in str(info.value)


def test_ranges_are_documented_in_the_docstring():
    rows = {}
    for line in ms.Parameters.__doc__.splitlines():
        found = re.search(r"\[([-+.e0-9]+), ([-+.e0-9]+)\]", line)
        if found:
            label = line[: found.start()].strip()  # "mass m", "y0", "S c_n"
            key = label if label == "S c_n" else label.split()[0]
            rows[key] = (float(found.group(1)), float(found.group(2)))
    documented = rows
    for name, (low, high) in FIELD_RANGES.items():
        assert documented[name] == (low, high), name
    for name, (low, high, _unit, _description) in DERIVED_RANGES.items():
        assert documented[name] == (low, high), name
    doc = " ".join(ms.Parameters.__doc__.split())
    assert "1e6 m g" in doc and "1e3 y0" in doc


# -- forces and amplitudes ---------------------------------------------------------------
def test_huge_force_is_refused_not_step_size_underflow():
    with pytest.raises(ValueError) as info:
        ms.simulate(force=1e308, amplitude=1e-7, duration=0.01)
    assert "1e+308" in str(info.value) and "9.81e+06" in str(info.value)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_force_at_the_limit_runs_and_just_above_is_refused(sign):
    limit = PAPER.max_force
    assert limit == 1e6 * PAPER.mass * PAPER.g
    r = ms.simulate(force=sign * limit, amplitude=0.0, duration=5 * PAPER.natural_period)
    # Far above mu m g the slider slides freely: x = (F - sgn(F) mu m g) t^2 / (2 m).
    t = r.t[-1]
    expected = (sign * limit - sign * PAPER.static_friction_force) * t * t / 2
    assert r.x[-1] == pytest.approx(expected, rel=1e-6)
    with pytest.raises(ValueError, match="force"):
        ms.simulate(force=sign * limit * (1 + 1e-9), amplitude=0.0, duration=1e-3)


def test_amplitude_limit_everywhere():
    top = PAPER.max_amplitude
    assert top == pytest.approx(1e3 * PAPER.static_deflection, rel=1e-15)
    r = ms.simulate(force=0.5, amplitude=top, duration=2e-3)
    assert np.isfinite(r.y).all() and r.y[0] == pytest.approx(PAPER.static_deflection - top)
    assert math.isfinite(ms.mean_velocity(force=0.5, amplitude=top))
    assert ms.free_period(PAPER, top) > PAPER.natural_period
    above = top * (1 + 1e-9)
    calls = [
        lambda: ms.simulate(force=0.5, amplitude=above, duration=2e-3),
        lambda: ms.mean_velocity(force=0.5, amplitude=above),
        lambda: ms.stick_slip_cycle(force=0.5, amplitude=above),
        lambda: ms.free_period(PAPER, above),
        lambda: ms.turning_points(PAPER, above),
        lambda: ms.velocity_map(forces=[0.5], amplitudes=[0.0, above]),
    ]
    for call in calls:
        with pytest.raises(ValueError, match=r"amplitude.*1e3 y0"):
            call()


def test_steady_state_still_requires_a_nonnegative_force():
    for call in (ms.mean_velocity, ms.stick_slip_cycle):
        with pytest.raises(ValueError, match=r"force must be >= 0 N.*simulate\(\) accepts F < 0"):
            call(force=-0.1, amplitude=1e-7)
        with pytest.raises(ValueError, match="force"):
            call(force=2 * PAPER.max_force, amplitude=1e-7)


def test_initial_state_beyond_the_amplitude_limit_is_refused():
    y0 = PAPER.static_deflection
    with pytest.raises(ValueError, match="initial_state"):
        ms.simulate(force=0.5, initial_state=(y0, 10.0, 0.0, 0.0), duration=1e-3)
    with pytest.raises(ValueError, match="initial_state"):
        ms.simulate(force=0.5, initial_state=(2e3 * y0, 0.0, 0.0, 0.0), duration=1e-3)
    # Rest at y0 - 1e3 y0 is the largest motion allowed: it runs.
    r = ms.simulate(force=0.5, initial_state=(y0 - PAPER.max_amplitude, 0, 0, 0), duration=1e-3)
    assert np.isfinite(r.x).all()


CORNERS = [
    {"m2": 20.0, "c_n": c_n_for(1e-2, m2=20.0)},
    {"m2": 0.1, "c_n": c_n_for(1e-3, m2=0.1)},
    {"mass": 1e-9, "g": 1e-3, "area": 1e4, "c_n": c_n_for(0.1, mass=1e-9, g=1e-3, area=1e4)},
    {"mass": 1e6, "g": 1e4, "area": 1e-12, "c_n": c_n_for(1e-9, mass=1e6, g=1e4, area=1e-12)},
    {"m2": 1.5, "c_n": c_n_for(1.01e-15, m2=1.5)},
    {"m2": 1.0},  # the paper's c_n with m2 = 1: y0 = 5.1e-14 m
    {"mu": 10.0},
]


@pytest.mark.parametrize("fields", CORNERS, ids=lambda f: ",".join(sorted(f)))
def test_extreme_valid_parameters_give_finite_results(fields):
    p = ms.Parameters(**fields)
    y0, mg = p.static_deflection, p.mass * p.g
    for force, amplitude in [(0.9 * p.mu * mg, p.max_amplitude), (0.5 * p.mu * mg, y0 / 2)]:
        for method in ("event", "rk4"):
            r = ms.simulate(
                p, force=force, amplitude=amplitude, duration=20 * p.natural_period, method=method
            )
            assert np.isfinite(r.x).all() and np.isfinite(r.y).all()
            assert r.x[-1] >= 0.0
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # no overflow or invalid-value warnings
            v = ms.mean_velocity(p, force=force, amplitude=amplitude)
        assert math.isfinite(v) and v >= 0.0
    r = ms.simulate(p, force=-p.max_force, amplitude=0.0, duration=5 * p.natural_period)
    assert np.isfinite(r.x).all() and r.x[-1] < 0.0
