"""Parameters: the paper's defaults, derived quantities against closed forms, validation."""

import dataclasses
import math

import pytest

import microslip as ms

PAPER = {"mass": 1.0, "g": 9.81, "area": 42.735e-4, "c_n": 4.52e16, "m2": 2.0, "mu": 0.1}


def test_defaults_are_the_papers_data():
    p = ms.Parameters()
    assert p.to_dict() == PAPER
    assert ms.Parameters.field_names() == tuple(PAPER)


@pytest.mark.parametrize(
    "fields",
    [{}, {"m2": 1.5, "mu": 0.3, "mass": 2.5}, {"m2": 3.0, "area": 1e-3, "g": 1.62}],
    ids=["paper", "m2=1.5", "m2=3"],
)
def test_derived_quantities_match_closed_forms(fields):
    p = ms.Parameters(**fields)
    m, g, s, c_n, m2, mu = (p.mass, p.g, p.area, p.c_n, p.m2, p.mu)
    y0 = (m * g / (s * c_n)) ** (1.0 / m2)
    k_n = m2 * s * c_n * y0 ** (m2 - 1.0)  # dR/dy at the working point C
    assert p.stiffness_coefficient == pytest.approx(s * c_n, rel=1e-15)
    assert p.static_deflection == pytest.approx(y0, rel=1e-14)
    assert p.contact_stiffness == pytest.approx(k_n, rel=1e-13)
    assert p.natural_angular_frequency == pytest.approx(math.sqrt(m2 * g / y0), rel=1e-14)
    assert p.natural_frequency == pytest.approx(math.sqrt(k_n / m) / (2 * math.pi), rel=1e-13)
    assert p.natural_period == pytest.approx(2 * math.pi * math.sqrt(m / k_n), rel=1e-13)
    assert p.time_scale == pytest.approx(math.sqrt(y0 / g), rel=1e-14)
    assert p.static_friction_force == pytest.approx(mu * m * g, rel=1e-15)
    # The working point is an equilibrium: S c_n y0^m2 = m g.
    assert s * c_n * p.static_deflection**m2 == pytest.approx(m * g, rel=1e-13)


def test_contact_stiffness_is_the_papers_formula_for_m2_2():
    p = ms.Parameters()
    assert p.contact_stiffness == pytest.approx(
        2.0 * math.sqrt(p.mass * p.g * p.area * p.c_n), rel=1e-14
    )


@pytest.mark.parametrize("fraction", [0.0, 0.2, 0.5, 0.999, 1.0, 1.3, 3.0])
def test_motion_threshold_closed_form(fraction):
    p = ms.Parameters()
    y0 = (p.mass * p.g / (p.area * p.c_n)) ** 0.5
    amplitude = fraction * y0
    expected = p.mu * p.area * p.c_n * max(y0 - amplitude, 0.0) ** 2
    assert p.motion_threshold(amplitude) == pytest.approx(expected, rel=1e-13, abs=0.0)
    if fraction >= 1.0:
        assert p.motion_threshold(amplitude) == 0.0
    if fraction == 0.0:
        assert p.motion_threshold(0.0) == pytest.approx(p.mu * p.mass * p.g, rel=1e-14)


@pytest.mark.parametrize(("e_n", "m1"), [(4.52e16**-0.5, 0.5), (3.2e-7, 0.4), (1e-9, 0.7)])
def test_from_interface_round_trip(e_n, m1):
    p = ms.Parameters.from_interface(e_n=e_n, m1=m1, mass=2.0, mu=0.2)
    assert p.m2 == pytest.approx(1.0 / m1, rel=1e-15)
    assert p.c_n == pytest.approx(e_n ** (-1.0 / m1), rel=1e-14)
    assert (p.mass, p.mu, p.g, p.area) == (2.0, 0.2, 9.81, 42.735e-4)
    # Back to the interface law (2.1): delta = e_n p^m1  <=>  p = c_n delta^m2.
    assert p.c_n ** (-1.0 / p.m2) == pytest.approx(e_n, rel=1e-13)


def test_from_interface_recovers_the_paper():
    p = ms.Parameters.from_interface(e_n=4.52e16**-0.5, m1=0.5)
    assert p.c_n == pytest.approx(4.52e16, rel=1e-14)
    assert p.m2 == 2.0


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"e_n": 0.0, "m1": 0.5}, "e_n"),
        ({"e_n": -1.0, "m1": 0.5}, "e_n"),
        ({"e_n": math.nan, "m1": 0.5}, "e_n"),
        ({"e_n": 1e-8, "m1": 0.0}, "m1"),
        ({"e_n": 1e-8, "m1": math.inf}, "m1"),
        ({"e_n": 1e-8, "m1": 0.5, "c_n": 1.0}, "c_n"),
        ({"e_n": 1e-8, "m1": 0.5, "m2": 2.0}, "m2"),
        ({"e_n": "1e-8", "m1": 0.5}, "e_n"),  # a string, not a number
        ({"e_n": True, "m1": 0.5}, "e_n"),
    ],
)
def test_from_interface_rejects_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        ms.Parameters.from_interface(**kwargs)


def test_frozen():
    p = ms.Parameters()
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.mass = 2.0  # type: ignore[misc]


def test_replace_copies_and_validates():
    p = ms.Parameters()
    q = p.replace(mu=0.25, m2=1.5)
    assert (q.mu, q.m2, p.mu, p.m2) == (0.25, 1.5, 0.1, 2.0)
    with pytest.raises(ValueError, match=r"mass.*-1"):
        p.replace(mass=-1.0)


def test_replace_unknown_field_names_it():
    with pytest.raises(ValueError, match="frobnicate"):
        ms.Parameters().replace(frobnicate=1.0)


BAD = [
    (name, value)
    for name in ("mass", "area", "c_n", "m2", "g")
    for value in (0.0, -1.0, math.nan, math.inf, -math.inf)
] + [("mu", -0.1), ("mu", math.nan), ("mu", math.inf), ("m2", 51.0)]


@pytest.mark.parametrize(("name", "value"), BAD)
def test_bad_values_name_the_field_and_the_value(name, value):
    with pytest.raises(ValueError) as info:
        ms.Parameters(**{name: value})
    message = str(info.value)
    assert name in message
    assert repr(value) in message


@pytest.mark.parametrize("value", ["1.0", None, True, [1.0], 1j])
def test_non_numbers_are_rejected(value):
    with pytest.raises(ValueError, match="mass"):
        ms.Parameters(mass=value)


def test_zero_friction_is_allowed_and_ints_become_floats():
    p = ms.Parameters(mu=0, mass=2)
    assert p.mu == 0.0 and isinstance(p.mu, float)
    assert p.mass == 2.0 and isinstance(p.mass, float)
    assert p.static_friction_force == 0.0
