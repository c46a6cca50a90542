"""The paper's figures for any parameter set: their scales, units and drive.

The paper draws Figs. 2–7 for its own data (Sec. 3). The model has natural scales
(Sec. 3): the time T0 = 1/f0, the static deflection y0, the weight m g and the static
friction force μ m g of eq. (4.1). With the drive F a fixed fraction of μ m g and the
amplitude a fixed fraction of y0, the normal motion y/y0 and the tangential motion
x/(μ g T0²) depend on t/T0 and m2 only (eqs. 2.3–2.5 divided by m g), so the paper's
figure for other data is the same picture on these scales. :func:`figure_scales` gives,
for one parameter set, the time windows, the drive and the unit of every plotted
quantity: the paper's unit (ms, µm, mm/s, nm, µm/s, N, m/s²) moved by whole SI
prefixes (factors of 1000) as the quantity's natural scale moves away from the paper's.
For the paper's data every ratio is exactly 1, so the figures are the paper's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from microslip.model.parameters import Parameters

__all__ = [
    "FigureNotDrawable",
    "FigureScales",
    "Unit",
    "combine_refusals",
    "figure_scales",
    "prefixed_unit",
    "require_friction",
]

PAPER = Parameters()
PAPER_FORCE = 0.5  # tangential drive of Sec. 4 and Figs. 4–6 for the paper's data [N]

_PREFIXES = {
    -18: "a", -15: "f", -12: "p", -9: "n", -6: "µ", -3: "m", 0: "", 3: "k", 6: "M", 9: "G",
}  # fmt: skip


class FigureNotDrawable(ValueError):
    """A figure of the paper that has no meaning for the given parameters.

    ``figure`` names it ("fig5", or several separated by commas) and ``reason`` says why,
    in one line. ``written`` lists the files that were written before this was raised
    (the other figures of the same request).
    """

    def __init__(self, figure: str, reason: str, written: tuple = (), parts: tuple = ()) -> None:
        self.figure = figure
        self.reason = reason
        self.written = tuple(written)
        self.parts: tuple[FigureNotDrawable, ...] = tuple(parts) or (self,)  # one per figure
        super().__init__(f"{figure} cannot be drawn for these parameters: {reason}")


@dataclass(frozen=True, slots=True)
class Unit:
    """A plotted unit: the SI value times ``factor`` is the plotted number."""

    factor: float
    symbol: str

    def label(self, quantity: str) -> str:
        """Axis label "quantity [symbol]"."""
        return f"{quantity} [{self.symbol}]"


def prefixed_unit(base: str, paper_exponent: int, ratio: float, suffix: str = "") -> Unit:
    """The unit ``prefix + base + suffix`` for a quantity whose natural scale is ``ratio``
    times the paper's, where the paper plots it in 10^paper_exponent ``base``.

    The exponent moves by multiples of 3, to the nearest one in decades, so the plotted
    numbers stay within a factor of about 30 of the paper's. Outside the prefix table
    (a..G) the unit is written as a power of ten.
    """
    if not (math.isfinite(ratio) and ratio > 0.0):
        ratio = 1.0
    exponent = paper_exponent + 3 * round(math.log10(ratio) / 3.0)
    prefix = _PREFIXES.get(exponent)
    symbol = f"{prefix}{base}{suffix}" if prefix is not None else f"10^{exponent} {base}{suffix}"
    return Unit(10.0 ** (-exponent), symbol)


@dataclass(frozen=True, slots=True)
class FigureScales:
    """Time windows, drive and plotted units of the paper's figures for one parameter set.

    Attributes
    ----------
    time_ratio : float
        T0 / T0 of the paper [-]; the time windows of Figs. 4–6 scale with it.
    drive : float
        F of Figs. 4–6 [N]: 0.5 N times μ m g / (μ m g of the paper), 0 for μ = 0.
    force_ratio : float
        μ m g / (μ m g of the paper) [-]; the forces of Fig. 7 scale with it.
    length_ratio : float
        y0 / y0 of the paper [-]; the amplitudes of Fig. 7 scale with it.
    t, y, ydot, yddot, R, Ft, x, xdot, xddot : Unit
        Plotted units of time, normal displacement, velocity and acceleration, normal
        reaction, friction force (and F), tangential displacement, velocity and
        acceleration.
    """

    time_ratio: float
    drive: float
    force_ratio: float
    length_ratio: float
    t: Unit
    y: Unit
    ydot: Unit
    yddot: Unit
    R: Unit
    Ft: Unit
    x: Unit
    xdot: Unit
    xddot: Unit


def figure_scales(params: Parameters) -> FigureScales:
    """The scales of the paper's figures for ``params`` (see the module docstring)."""
    p, q = params, PAPER
    time_ratio = p.natural_period / q.natural_period
    length_ratio = p.static_deflection / q.static_deflection
    force_ratio = p.static_friction_force / q.static_friction_force
    # Tangential quantities scale with the friction deceleration μ g; with μ = 0 there is
    # none, and g keeps the units sensible for a drive that the caller gives.
    mu_g = (p.mu if p.mu > 0 else q.mu) * p.g / (q.mu * q.g)
    return FigureScales(
        time_ratio=time_ratio,
        drive=PAPER_FORCE * force_ratio,
        force_ratio=force_ratio,
        length_ratio=length_ratio,
        t=prefixed_unit("s", -3, time_ratio),
        y=prefixed_unit("m", -6, length_ratio),
        ydot=prefixed_unit("m", -3, length_ratio / time_ratio, "/s"),
        yddot=prefixed_unit("m", 0, p.g / q.g, "/s$^2$"),
        R=prefixed_unit("N", 0, p.mass * p.g / (q.mass * q.g)),
        Ft=prefixed_unit("N", 0, force_ratio if force_ratio > 0 else p.mass * p.g / (q.mass * q.g)),
        x=prefixed_unit("m", -9, mu_g * time_ratio**2),
        xdot=prefixed_unit("m", -6, mu_g * time_ratio, "/s"),
        xddot=prefixed_unit("m", 0, mu_g, "/s$^2$"),
    )


def require_friction(params: Parameters, figure: str) -> None:
    """FigureNotDrawable for μ = 0: Figs. 4–7 show stick–slip under dry friction."""
    if params.mu == 0.0:
        raise FigureNotDrawable(
            figure,
            "mu = 0: without friction there is no stick-slip, and the drive of the "
            "paper's figures (a fraction of mu m g) would be 0",
        )


def combine_refusals(refused: list[FigureNotDrawable], written: list) -> FigureNotDrawable:
    """One FigureNotDrawable for several figures, one line, naming each and its reason,
    and how many files of the other figures were written (listed in ``written``)."""
    parts = [part for error in refused for part in error.parts]
    names = ", ".join(part.figure for part in parts)
    by_reason: dict[str, list[str]] = {}  # one reason, said once, for all it concerns
    for part in parts:
        by_reason.setdefault(part.reason, []).append(part.figure)
    if len(by_reason) == 1:
        reasons = parts[0].reason
    else:
        reasons = "; ".join(f"{', '.join(figs)}: {why}" for why, figs in by_reason.items())
    kept = f" ({len(written)} files of the other figures were written)" if written else ""
    return FigureNotDrawable(names, reasons + kept, written=tuple(written), parts=tuple(parts))
