"""The immutable result of one simulation, with derived forces and an xarray view."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from microslip.model.composition import Model
from microslip.model.parameters import Parameters
from microslip.model.samples import interface_samples, normal_samples
from microslip.model.system import EVENT_NAMES

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
    N : compressive normal force N >= 0 [N] of the composed normal law (the paper's |R|,
        eq. 2.3, with damping and excitation); ``R`` is the same array
    delta : penetration δ = y - z(t) [m] (z the surface motion; δ = y without one)
    u : contact point position [m] of a compliant tangential contact (= x with a rigid
        one)
    spring_force : tangential spring force f [N] of a compliant contact (the force on
        the body is -f; 0 with a rigid one)
    drive_force : tangential drive force F(t) [N] on the body (kinematic drive: the
        force that keeps ẋ = v, = -F_t)
    Ft : friction force on the slider [N], signed as in (2.5): m ẍ = F + F_t
        (rigid, sliding: -μ N sgn ẋ; stick: -F, the paper's real friction force F_tr;
        compliant: -f)
    friction_limit : μ_s N [N], the potential static friction force (Fig. 5, thin lines)
    state : 0 stick, 1 slip (in contact), 2 flight (loss of contact: δ <= 0 or N_raw <= 0);
        stick and slip of the contact point with a compliant tangential contact
    direction : slip direction of the interface at each sample (-1, 0 = stick, +1): the
        body's (rigid) or the contact point's (compliant)
    event_t, event_kind, event_states : switching instants [s], their kinds (names in
        ``EVENT_NAMES``) and the state (y, ẏ, x, ẋ, u, f) just after each switch
    model : the Model simulated (``Model(params)`` when not given)
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
    model: Model | None = None
    u: np.ndarray | None = None
    spring_force: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.model is None:
            object.__setattr__(self, "model", Model(self.params))
        if self.u is None:
            object.__setattr__(self, "u", np.asarray(self.x, dtype=float).copy())
        if self.spring_force is None:
            object.__setattr__(self, "spring_force", np.zeros_like(self.x, dtype=float))

    @cached_property
    def _interface(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        # (F, F_t, μ_s N) from the model's drive, friction law and tangential contact.
        states = np.ascontiguousarray(
            np.column_stack([self.y, self.ydot, self.x, self.xdot, self.u, self.spring_force]),
            dtype=float,
        )
        return interface_samples(
            np.ascontiguousarray(self.t, dtype=float),
            states,
            np.ascontiguousarray(self.direction, dtype=float),
            self.model.pack(self.force),
        )

    @cached_property
    def _normal(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        # (N, N_raw, δ) from the composed normal law the integrators used.
        c = self.model.pack(self.force)
        t = np.ascontiguousarray(self.t, dtype=float)
        y = np.ascontiguousarray(self.y, dtype=float)
        ydot = np.ascontiguousarray(self.ydot, dtype=float)
        return normal_samples(t, y, ydot, c)

    @property
    def N(self) -> np.ndarray:
        return self._normal[0]

    @property
    def R(self) -> np.ndarray:
        return self.N

    @property
    def delta(self) -> np.ndarray:
        return self._normal[2]

    @property
    def friction_limit(self) -> np.ndarray:
        return self._interface[2]

    @property
    def drive_force(self) -> np.ndarray:
        return self._interface[0]

    @property
    def Ft(self) -> np.ndarray:
        return self._interface[1]

    @property
    def xddot(self) -> np.ndarray:
        if self.model.is_kinematic:
            return np.zeros_like(self.t)
        accel = (self.drive_force + self.Ft) / self.params.mass
        if self.model.is_compliant:
            return accel
        return np.where(self.direction != 0.0, accel, 0.0)

    @property
    def state(self) -> np.ndarray:
        code = np.where(self.direction != 0.0, SLIP, STICK)
        contact = (self.delta > 0.0) & (self._normal[1] > 0.0)
        return np.where(contact, code, FLIGHT).astype(np.int8)

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
                "R": var(self.R, "N", "compressive normal reaction |R| (eq. 2.3; = N)"),
                "N": var(self.N, "N", "compressive normal force N of the composed law"),
                "delta": var(self.delta, "m", "penetration delta = y - z (> 0 overlap)"),
                "Ft": var(self.Ft, "N", "friction force on the slider (eq. 2.5 sign)"),
                "friction_limit": var(self.friction_limit, "N", "static friction limit mu_s N"),
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
                **self.model.to_attrs(),
                **{k: v for k, v in self.settings.items() if v is not None},
            },
        )
        if self.model.is_compliant:
            ds["u"] = var(self.u, "m", "contact point position")
            ds["spring_force"] = var(
                self.spring_force, "N", "tangential contact spring force f (on the body: -f)"
            )
        if self.model.drive is not None:
            ds["F"] = var(self.drive_force, "N", "tangential drive force on the body")
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
