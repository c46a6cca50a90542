"""Units, time windows and drive of the paper's figures for any parameter set."""

from __future__ import annotations

import math

import pytest

import microslip as ms
from microslip.plotting.scales import (
    FigureNotDrawable,
    combine_refusals,
    figure_scales,
    prefixed_unit,
    require_friction,
)

P = ms.Parameters()


@pytest.mark.parametrize(
    ("ratio", "symbol", "factor"),
    [
        (1.0, "µm", 1e6),
        (20.0, "µm", 1e6),  # within a factor 10^1.5 of the paper's scale: same unit
        (40.0, "mm", 1e3),
        (1 / 40, "nm", 1e9),
        (1e-7, "pm", 1e12),  # 10^-7 is nearer 10^-6 than 10^-9
        (1e-12, "am", 1e18),
        (1e-15, "10^-21 m", 1e21),  # beyond the prefix table: a power of ten
        (0.0, "µm", 1e6),  # no scale (e.g. mu = 0 in a ratio): the paper's unit
    ],
)
def test_prefixed_unit_moves_by_whole_prefixes(ratio, symbol, factor):
    unit = prefixed_unit("m", -6, ratio)
    assert unit.symbol == symbol
    assert unit.factor == pytest.approx(factor, rel=1e-12)
    assert unit.label("$y$") == f"$y$ [{symbol}]"


def test_paper_data_gives_the_paper_units_and_drive_exactly():
    u = figure_scales(P)
    assert (u.time_ratio, u.force_ratio, u.length_ratio) == (1.0, 1.0, 1.0)
    assert u.drive == 0.5
    symbols = [getattr(u, n).symbol for n in ("t", "y", "ydot", "R", "Ft", "x", "xdot")]
    assert symbols == ["ms", "µm", "mm/s", "N", "N", "nm", "µm/s"]
    assert u.yddot.symbol == u.xddot.symbol == "m/s$^2$"


@pytest.mark.parametrize(
    "changes", [{"mass": 5.0}, {"m2": 1.5}, {"m2": 1.0}, {"mu": 0.3, "mass": 0.2}, {"g": 1.62}]
)
def test_scales_follow_the_parameter_sets_own_scales(changes):
    p = P.replace(**changes)
    u = figure_scales(p)
    # the drive is the paper's fraction of the static friction force mu m g (eq. 4.1)
    assert u.drive / (p.mu * p.mass * p.g) == pytest.approx(0.5 / (0.1 * 1.0 * 9.81), rel=1e-12)
    assert u.time_ratio * P.natural_period == pytest.approx(p.natural_period, rel=1e-12)
    assert u.length_ratio * P.static_deflection == pytest.approx(p.static_deflection, rel=1e-12)
    # each unit keeps its quantity's natural scale within a factor 10^1.5 of the paper's
    # plotted number: y0 in u.y, T0 in u.t, m g in u.R
    for value, unit, paper in (
        (p.static_deflection, u.y, P.static_deflection * 1e6),
        (p.natural_period, u.t, P.natural_period * 1e3),
        (p.mass * p.g, u.R, P.mass * P.g),
    ):
        assert abs(math.log10(value * unit.factor / paper)) <= 1.5 + 1e-9


def test_m2_1_gives_picometres_and_microseconds():
    u = figure_scales(P.replace(m2=1.0))  # y0 = m g / (S c_n) = 5.1e-14 m, T0 = 0.45 µs
    assert u.y.symbol == "pm" and u.t.symbol == "µs"


def test_no_friction_is_refused_in_one_line_naming_mu():
    require_friction(P, "fig4")  # mu > 0: nothing to say
    with pytest.raises(FigureNotDrawable, match=r"^fig4 cannot be drawn .*mu = 0") as info:
        require_friction(P.replace(mu=0.0), "fig4")
    assert isinstance(info.value, ValueError) and "\n" not in str(info.value)


def test_refusals_combine_into_one_line_naming_every_figure():
    parts = [FigureNotDrawable("fig4", "why 4"), FigureNotDrawable("fig7", "why 7")]
    first = combine_refusals(parts[:1], ["a.png", "a.nc"])
    assert str(first) == (
        "fig4 cannot be drawn for these parameters: why 4 "
        "(2 files of the other figures were written)"
    )
    both = combine_refusals([first, parts[1]], ["a.png", "a.nc"])
    assert both.figure == "fig4, fig7"
    assert str(both).count("files of the other figures") == 1  # not repeated when nested
    assert "fig4: why 4; fig7: why 7" in str(both) and "\n" not in str(both)
    assert both.written == ("a.png", "a.nc")


def test_a_reason_shared_by_several_figures_is_said_once():
    parts = [FigureNotDrawable(name, "mu = 0") for name in ("fig4", "fig5")]
    combined = combine_refusals([*parts, FigureNotDrawable("fig7", "other")], [])
    assert str(combined) == (
        "fig4, fig5, fig7 cannot be drawn for these parameters: fig4, fig5: mu = 0; fig7: other"
    )
    same = combine_refusals(parts, [])
    assert str(same) == "fig4, fig5 cannot be drawn for these parameters: mu = 0"
