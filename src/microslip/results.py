"""The immutable result of one simulation, with derived forces and an xarray view."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from microslip.integrators import EVENT_NAMES
from microslip.model.contact import reaction_array
from microslip.model.friction import friction_force
from microslip.model.parameters import Parameters

STICK, SLIP, FLIGHT = 0, 1, 2
STATE_MEANINGS = "stick slip flight"


@dataclass(frozen=True)
class SimulationResult:
    """Trajectory of the slider, SI units throughout.

    Attributes
    ----------
    t : time [s]
    y, ydot : normal position [m] (y > 0 penetration, eq. 2.3) and velocity [m/s]
    x, xdot, xddot : tangential position [m], velocity [m/s], acceleration [m/s^2]
    R : compressive normal reaction |R| [N] (eq. 2.3)
    Ft : friction force on the slider [N], signed as in (2.5): m ẍ = F + F_t
        (sliding: -μ|R| sgn ẋ; stick: -F, the paper's real friction force F_tr)
    friction_limit : μ|R| [N], the potential static friction force (Fig. 5, thin lines)
    state : 0 stick, 1 slip (in contact), 2 flight (loss of contact, y <= 0)
    direction : sliding direction at each sample (-1, 0 = stick, +1)
    event_t, event_kind, event_states : switching instants [s], their kinds (names in
        ``EVENT_NAMES``) and the state (y, ẏ, x, ẋ) just after each switch
    """

    params: Parameters
    force: float
    method: str
    t: np.ndarray
    y: np.ndarray
    ydot: np.ndarray
    x: np.ndarray
    xdot: np.ndarray
    direction: np.ndarray
    event_t: np.ndarray
    event_kind: np.ndarray
    event_states: np.ndarray
    settings: dict[str, Any] = field(default_factory=dict)

    @property
    def R(self) -> np.ndarray:
        return reaction_array(self.params, self.y)

    @property
    def friction_limit(self) -> np.ndarray:
        return self.params.mu * self.R

    @property
    def Ft(self) -> np.ndarray:
        return friction_force(self.direction, self.friction_limit, self.force)

    @property
    def xddot(self) -> np.ndarray:
        return np.where(self.direction != 0.0, (self.force + self.Ft) / self.params.mass, 0.0)

    @property
    def state(self) -> np.ndarray:
        code = np.where(self.direction != 0.0, SLIP, STICK)
        return np.where(self.y > 0.0, code, FLIGHT).astype(np.int8)

    @property
    def events(self) -> list[tuple[float, str]]:
        """Switching instants as (time [s], kind) pairs."""
        return [
            (float(t), EVENT_NAMES[k]) for t, k in zip(self.event_t, self.event_kind, strict=True)
        ]

    def to_xarray(self):
        """An ``xarray.Dataset`` on dimension ``time``; every variable carries ``units``.

        Global attributes follow CF-1.10 (``Conventions``, ``title``, ``source``,
        ``references``; ``history`` is added when a file is written); the flag
        variables carry ``flag_values`` and ``flag_meanings``.
        """
        import xarray as xr

        from microslip.metadata import cf_static_attributes

        def var(values, units, long_name, **extra):
            return ("time", np.asarray(values), {"units": units, "long_name": long_name, **extra})

        ds = xr.Dataset(
            {
                "y": var(self.y, "m", "normal displacement (penetration > 0)"),
                "ydot": var(self.ydot, "m s-1", "normal velocity"),
                "x": var(self.x, "m", "tangential displacement"),
                "xdot": var(self.xdot, "m s-1", "tangential velocity"),
                "xddot": var(self.xddot, "m s-2", "tangential acceleration"),
                "R": var(self.R, "N", "compressive normal reaction |R| (eq. 2.3)"),
                "Ft": var(self.Ft, "N", "friction force on the slider (eq. 2.5 sign)"),
                "friction_limit": var(self.friction_limit, "N", "friction limit mu |R|"),
                "state": var(
                    self.state,
                    "1",
                    "contact state",
                    flag_values=np.array([STICK, SLIP, FLIGHT], dtype=np.int8),
                    flag_meanings=STATE_MEANINGS,
                ),
            },
            coords={"time": ("time", self.t, {"units": "s", "long_name": "time"})},
            attrs={
                **cf_static_attributes("microslip simulation (Grudzinski & Kostek 2005 model)"),
                "method": self.method,
                "force_N": self.force,
                **{f"param_{k}": v for k, v in self.params.to_dict().items()},
                **{k: v for k, v in self.settings.items() if v is not None},
            },
        )
        ds["event_time"] = ("event", self.event_t, {"units": "s", "long_name": "switch time"})
        ds["event_kind"] = (
            "event",
            self.event_kind.astype(np.int8),
            {
                "units": "1",
                "long_name": "switch kind",
                "flag_values": np.arange(len(EVENT_NAMES), dtype=np.int8),
                "flag_meanings": " ".join(EVENT_NAMES),
            },
        )
        return ds
