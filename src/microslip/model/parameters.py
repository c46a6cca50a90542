"""Physical parameters of the slider–slideway system (Grudziński & Kostek 2005, Sec. 2–3).

All quantities are SI. The defaults are the paper's data (Sec. 3).
"""

from __future__ import annotations

import functools
import math
from dataclasses import asdict, dataclass, field, fields, replace
from typing import Any

import numpy as np

from microslip import validation as check

__all__ = [
    "AMPLITUDE_LIMIT_FACTOR",
    "DERIVED_RANGES",
    "FIELD_RANGES",
    "FORCE_LIMIT_FACTOR",
    "PARAMETER_UNITS",
    "POSITION_LIMIT",
    "Parameters",
    "derived_log10",
]

# Supported ranges of the fields (SI units), wide enough for any real contact; mu may be
# 0 (frictionless). c_n has m2-dependent units and is bounded through the derived ranges.
FIELD_RANGES: dict[str, tuple[float, float]] = {
    "mass": (1e-9, 1e6),
    "g": (1e-3, 1e4),
    "area": (1e-12, 1e4),
    "m2": (0.1, 20.0),
    "mu": (0.0, 10.0),
}
# Derived quantities: (low, high, unit, description). "S c_n" bounds keep the reaction
# S c_n y^m2 of (2.3) and its factors finite and normal for y up to the lowest point.
DERIVED_RANGES: dict[str, tuple[float, float, str, str]] = {
    "y0": (1e-15, 1e-1, "m", "static deflection"),
    "f0": (1e-2, 1e8, "Hz", "natural frequency"),
    "S c_n": (1e-280, 1e280, "N m-m2", "stiffness coefficient"),
}
# Forces and amplitudes accepted by the solvers: |F| <= 1e6 m g, A <= 1e3 y0.
FORCE_LIMIT_FACTOR = 1e6
AMPLITUDE_LIMIT_FACTOR = 1e3
# Initial tangential state accepted by simulate: |x0| <= POSITION_LIMIT and
# |ẋ0| <= FORCE_LIMIT_FACTOR g T0. x enters no force of (2.2)-(2.5) (translation
# invariance), so x0 only shifts the output; 1e6 m exceeds any slideway and keeps x
# resolved to 2.2e-16 x 1e6 m = 2.2e-10 m. The speed bound is the speed the largest
# accepted force gains in one normal period, far above any steady sliding speed.
POSITION_LIMIT = 1e6


def derived_log10(mass: Any, g: Any, area: Any, c_n: Any, m2: Any) -> dict[str, Any]:
    """log10 of y0 [m], f0 [Hz], T0 [s] and S c_n, without overflow (arrays broadcast).

    y0 = (m g / (S c_n))^(1/m2) and f0 = sqrt(m2 g / y0) / (2π) (Sec. 3), in logarithms
    so that any finite positive input gives a finite answer.
    """
    log_sc = np.log10(area) + np.log10(c_n)
    log_y0 = (np.log10(mass) + np.log10(g) - log_sc) / m2
    log_f0 = 0.5 * (np.log10(m2) + np.log10(g) - log_y0) - math.log10(2.0 * math.pi)
    return {"y0": log_y0, "f0": log_f0, "T0": -log_f0, "S c_n": log_sc}


def _spec(unit: str, description: str, positive: bool = True) -> dict[str, Any]:
    return {"unit": unit, "description": description, "positive": positive}


def _power_text(exponent: float) -> str:
    """10^exponent as text: the number where representable, else 1e<exponent>."""
    if abs(exponent) < 300.0:
        return f"{10.0**exponent:.4g}"
    return f"1e{exponent:.0f}"


@dataclass(frozen=True, slots=True)
class Parameters:
    """Constants of the model, eqs. (2.1)–(2.5).

    Attributes
    ----------
    mass : float
        Slider mass m [kg].
    g : float
        Gravitational acceleration g [m/s^2].
    area : float
        Nominal contact area S [m^2].
    c_n : float
        Interface stiffness constant c_n of eq. (2.3) [N/m^(2+m2)]; for m2 = 2 this is N/m^4.
    m2 : float
        Interface exponent m2 = 1/m1 of eq. (2.3) [-].
    mu : float
        Coulomb friction coefficient μ of eq. (2.2) [-].

    Notes
    -----
    Every field must be a finite real number within a range wide enough for any real
    contact (``FIELD_RANGES``), and the derived quantities must be physically sensible
    (``DERIVED_RANGES``), else ``ValueError`` names the culprit:

    ======================  =======================  ======================================
    quantity                range                    why
    ======================  =======================  ======================================
    mass m                  [1e-9, 1e6] kg           a microgram to a thousand tonnes
    g                       [1e-3, 1e4] m/s^2        microgravity to a centrifuge
    area S                  [1e-12, 1e4] m^2         a square micrometre to 100 m x 100 m
    c_n                     > 0, finite              bounded through y0, f0 and S c_n
    m2                      [0.1, 20]                interface exponent 1/m1 (real: 1-3)
    mu                      [0, 10]                  Coulomb coefficient
    y0                      [1e-15, 1e-1] m          static deflection at the working point
    f0                      [1e-2, 1e8] Hz           small-amplitude normal frequency
    S c_n                   [1e-280, 1e280]          keeps S c_n y^m2 representable in (2.3)
    ======================  =======================  ======================================

    The derived quantities are checked in logarithms, so an extreme input is refused
    with its value instead of overflowing; within these ranges the closed forms below
    are finite and the compiled kernels never meet inf or a subnormal S c_n. Forces and
    amplitudes given to the solvers must satisfy |F| <= ``max_force`` = 1e6 m g and
    A <= ``max_amplitude`` = 1e3 y0. m2 <= 20 keeps the steady-state orbit tables
    (:mod:`microslip.analysis.orbit`) within their capacity up to A = 1e3 y0 (60 % full
    at m2 = 20; they overflow near m2 = 30). y0 down to 1e-15 m admits the paper's c_n
    with m2 = 1 (y0 = 5.1e-14 m).
    """

    mass: float = field(default=1.0, metadata=_spec("kg", "slider mass m"))
    g: float = field(default=9.81, metadata=_spec("m s-2", "gravitational acceleration g"))
    area: float = field(default=42.735e-4, metadata=_spec("m2", "nominal contact area S"))
    c_n: float = field(
        default=4.52e16, metadata=_spec("N m-(2+m2)", "interface stiffness constant c_n")
    )
    m2: float = field(default=2.0, metadata=_spec("1", "interface exponent m2 = 1/m1"))
    mu: float = field(
        default=0.1, metadata=_spec("1", "Coulomb friction coefficient mu", positive=False)
    )

    def __post_init__(self) -> None:
        for f in fields(self):
            value = check.real(f.name, getattr(self, f.name))  # a finite float
            if f.metadata["positive"] and value <= 0.0:
                raise ValueError(f"{f.name} must be > 0 [{f.metadata['unit']}], got {value!r}")
            if not f.metadata["positive"] and value < 0.0:
                raise ValueError(f"{f.name} must be >= 0 [{f.metadata['unit']}], got {value!r}")
            low, high = FIELD_RANGES.get(f.name, (0.0, math.inf))
            if not low <= value <= high:
                raise ValueError(
                    f"{f.name}={value!r} [{f.metadata['unit']}] is outside the supported "
                    f"range [{low:g}, {high:g}]"
                )
            object.__setattr__(self, f.name, value)
        logs = derived_log10(self.mass, self.g, self.area, self.c_n, self.m2)
        for name, (low, high, unit, description) in DERIVED_RANGES.items():
            exponent = float(logs[name])
            if not math.log10(low) <= exponent <= math.log10(high):
                raise ValueError(
                    f"{description} {name} = {_power_text(exponent)} {unit} is outside the "
                    f"supported range [{low:g}, {high:g}] {unit} ({self._fields_text()})"
                )

    def _fields_text(self) -> str:
        return ", ".join(f"{name}={getattr(self, name)!r}" for name in self.field_names())

    # -- construction -------------------------------------------------------------------
    @classmethod
    def from_interface(cls, *, e_n: float, m1: float, **others: float) -> Parameters:
        """Build parameters from the interface law (2.1), δ = e_n p^m1.

        Parameters
        ----------
        e_n : float
            Interface compliance constant [m Pa^-m1].
        m1 : float
            Interface exponent of (2.1) [-].
        **others
            Any other field (mass [kg], g [m/s^2], area [m^2], mu [-]).

        Uses m2 = 1/m1 and c_n = e_n^(-1/m1), Sec. 2.
        """
        for name, value in (("e_n", e_n), ("m1", m1)):
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ValueError(f"{name} must be a real number, got {value!r}")
            if not math.isfinite(value) or value <= 0.0:
                raise ValueError(f"{name} must be finite and > 0, got {value!r}")
        for name in ("c_n", "m2"):
            if name in others:
                raise ValueError(f"{name} is derived from e_n and m1; do not pass it too")
        # In logarithms: e_n^(-1/m1) overflows for extreme inputs; the constructor then
        # refuses the c_n (or the derived y0, f0) with its value.
        log_c_n = -math.log10(float(e_n)) / float(m1)
        if abs(log_c_n) > 300.0:
            raise ValueError(
                f"c_n = e_n^(-1/m1) = 1e{log_c_n:.4g} is not representable (e_n={e_n!r}, m1={m1!r})"
            )
        return cls(c_n=float(e_n) ** (-1.0 / m1), m2=1.0 / m1, **others)

    def replace(self, **changes: float) -> Parameters:
        """A copy with some fields changed (validated like the constructor)."""
        unknown = set(changes) - set(self.field_names())
        if unknown:
            raise ValueError(
                f"unknown parameter {sorted(unknown)[0]!r}; known: {', '.join(self.field_names())}"
            )
        return replace(self, **changes)

    @classmethod
    @functools.cache
    def field_names(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))

    @classmethod
    def field_unit(cls, name: str) -> str:
        return {f.name: f.metadata["unit"] for f in fields(cls)}[name]

    def to_dict(self) -> dict[str, float]:
        return asdict(self)

    # -- derived quantities -------------------------------------------------------------
    @property
    def stiffness_coefficient(self) -> float:
        """S c_n, the coefficient of the reaction |R| = S c_n y^m2 [N/m^m2], eq. (2.3)."""
        return self.area * self.c_n

    @property
    def static_deflection(self) -> float:
        """Static deflection y0 = δ0 = (m g / (S c_n))^(1/m2) [m] at the working point C."""
        return (self.mass * self.g / self.stiffness_coefficient) ** (1.0 / self.m2)

    @property
    def contact_stiffness(self) -> float:
        """Tangent contact stiffness K_n = m2 S c_n y0^(m2-1) = m2 m g / y0 [N/m] at C.

        For m2 = 2 this is the paper's K_n = 2 sqrt(m g S c_n) (Sec. 3).
        """
        return self.m2 * self.mass * self.g / self.static_deflection

    @property
    def natural_angular_frequency(self) -> float:
        """ω0 = sqrt(K_n / m) [rad/s], small-amplitude normal vibration."""
        return math.sqrt(self.contact_stiffness / self.mass)

    @property
    def natural_frequency(self) -> float:
        """f0 = (1/2π) sqrt(K_n / m) [Hz] (paper: 1485 Hz)."""
        return self.natural_angular_frequency / (2.0 * math.pi)

    @property
    def natural_period(self) -> float:
        """T0 = 1/f0 [s]."""
        return 1.0 / self.natural_frequency

    @property
    def time_scale(self) -> float:
        """1/ω, ω = sqrt(g / y0) [s]: time unit of the natural scales (docs/model-facts.md)."""
        return math.sqrt(self.static_deflection / self.g)

    @property
    def static_friction_force(self) -> float:
        """F_t0 = μ m g [N], eq. (4.1): the static friction force without vibration."""
        return self.mu * self.mass * self.g

    @property
    def max_force(self) -> float:
        """Largest |F| [N] the solvers accept: ``FORCE_LIMIT_FACTOR`` m g = 1e6 m g."""
        return FORCE_LIMIT_FACTOR * self.mass * self.g

    @property
    def max_velocity(self) -> float:
        """Largest initial |ẋ| [m/s] ``simulate`` accepts: ``FORCE_LIMIT_FACTOR`` g T0."""
        return FORCE_LIMIT_FACTOR * self.g * self.natural_period

    @property
    def max_amplitude(self) -> float:
        """Largest amplitude A [m] the solvers accept: ``AMPLITUDE_LIMIT_FACTOR`` y0 = 1e3 y0."""
        return AMPLITUDE_LIMIT_FACTOR * self.static_deflection

    def motion_threshold(self, amplitude: float) -> float:
        """Smallest force that makes the slider move, μ S c_n max(y0 - A, 0)^m2 [N].

        The slider moves iff F is strictly larger (eq. 4.2; docs/model-facts.md, fact 5).
        ``amplitude`` is A = y0 - y_min [m].
        """
        top = max(self.static_deflection - float(amplitude), 0.0)
        return self.mu * self.stiffness_coefficient * top**self.m2

    def describe(self) -> dict[str, dict[str, Any]]:
        """Fields and derived quantities with units, for ``microslip info``."""
        out: dict[str, dict[str, Any]] = {}
        for f in fields(self):
            out[f.name] = {
                "value": getattr(self, f.name),
                "unit": f.metadata["unit"],
                "description": f.metadata["description"],
            }
        derived = [
            ("static_deflection", "m", "static deflection y0 at the working point C"),
            ("contact_stiffness", "N m-1", "contact stiffness K_n at C"),
            ("natural_frequency", "Hz", "small-amplitude normal frequency f0"),
            ("natural_period", "s", "normal period T0 = 1/f0"),
            ("static_friction_force", "N", "nominal static friction force F_t0 = mu m g"),
        ]
        for name, unit, description in derived:
            out[name] = {"value": getattr(self, name), "unit": unit, "description": description}
        return out


PARAMETER_UNITS = {f.name: f.metadata["unit"] for f in fields(Parameters)}
