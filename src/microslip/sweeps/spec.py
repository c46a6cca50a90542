"""The definition of a sweep: a grid over Parameters fields, force and amplitude, in chunks.

A chunk is one combination of the parameter axes, every force, and a run of consecutive
amplitudes: at a given amplitude the steady-state method shares one normal orbit across
all forces, so forces are never split.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from microslip import validation as check
from microslip.model.parameters import Parameters

METHODS = ("steady", "time")
ChunkKey = tuple[int, ...]  # parameter-axis indices..., amplitude-chunk index


@dataclass(frozen=True)
class SweepSpec:
    """A sweep of the mean sliding velocity (SI units).

    Attributes
    ----------
    base : the parameters not swept
    param_axes : ((field name, values), ...) swept Parameters fields, in order
    forces : tangential forces F [N]
    amplitudes : normal vibration amplitudes A [m]
    method : "steady" (exact steady state) or "time" (batched RK4 over ``duration``)
    duration : simulated time per point for "time" [s]
    dt : RK4 step for "time" [s]; None means T0/200 of each parameter set
    amplitude_chunk : amplitudes per chunk
    """

    base: Parameters
    param_axes: tuple[tuple[str, tuple[float, ...]], ...]
    forces: tuple[float, ...]
    amplitudes: tuple[float, ...]
    method: str = "steady"
    duration: float = 0.05
    dt: float | None = None
    amplitude_chunk: int = 8

    @classmethod
    def build(
        cls,
        params: Parameters | None,
        axes: Mapping[str, Any] | None,
        forces: Any,
        amplitudes: Any,
        *,
        method: str = "steady",
        duration: float = 0.05,
        dt: float | None = None,
        amplitude_chunk: int | None = None,
    ) -> SweepSpec:
        """Validate every input and build the spec (``ValueError`` naming the culprit)."""
        params = Parameters() if params is None else params
        if not isinstance(params, Parameters):
            raise ValueError(f"params must be a microslip.Parameters, got {type(params).__name__}")
        method = check.one_of("method", method, METHODS)
        param_axes = []
        for name, values in (axes or {}).items():
            if name in ("force", "amplitude"):
                raise ValueError(f"{name!r} is a sweep axis of its own; pass it as {name}=...")
            if name not in Parameters.field_names():
                known = ", ".join(Parameters.field_names())
                raise ValueError(f"unknown parameter {name!r} in sweep; known: {known}")
            array = check.real_array(name, values)
            for value in array:  # each value must make valid Parameters
                params.replace(**{name: float(value)})
            param_axes.append((name, tuple(float(v) for v in array)))
        forces = check.real_array("force", forces)
        if np.any(forces < 0):
            raise ValueError(f"force must be >= 0 N, got {float(forces[forces < 0][0])!r}")
        amplitudes = check.real_array("amplitude", amplitudes)
        if np.any(amplitudes < 0):
            raise ValueError(
                f"amplitude must be >= 0 m, got {float(amplitudes[amplitudes < 0][0])!r}"
            )
        duration = check.real("duration", duration, minimum=0.0, strict=True)
        if dt is not None:
            dt = check.real("dt", dt, minimum=0.0, strict=True)
        if amplitude_chunk is None:
            amplitude_chunk = 8 if method == "steady" else max(1, 4096 // len(forces))
        amplitude_chunk = check.positive_int("amplitude_chunk", amplitude_chunk)
        return cls(
            base=params,
            param_axes=tuple(param_axes),
            forces=tuple(float(f) for f in forces),
            amplitudes=tuple(float(a) for a in amplitudes),
            method=method,
            duration=duration,
            dt=dt,
            amplitude_chunk=min(amplitude_chunk, len(amplitudes)),
        )

    # -- geometry ---------------------------------------------------------------------
    @property
    def dims(self) -> tuple[str, ...]:
        return (*(name for name, _ in self.param_axes), "force", "amplitude")

    @property
    def shape(self) -> tuple[int, ...]:
        return (*(len(v) for _, v in self.param_axes), len(self.forces), len(self.amplitudes))

    @property
    def chunk_grid(self) -> tuple[int, ...]:
        """Number of chunks along each parameter axis and along amplitude."""
        n_amp = math.ceil(len(self.amplitudes) / self.amplitude_chunk)
        return (*(len(v) for _, v in self.param_axes), n_amp)

    def chunks(self) -> Iterator[ChunkKey]:
        yield from itertools.product(*(range(n) for n in self.chunk_grid))

    @property
    def n_chunks(self) -> int:
        return math.prod(self.chunk_grid)

    def amplitude_slice(self, key: ChunkKey) -> slice:
        start = key[-1] * self.amplitude_chunk
        return slice(start, min(start + self.amplitude_chunk, len(self.amplitudes)))

    def region(self, key: ChunkKey) -> tuple:
        """Index of the chunk's block in the full (params..., force, amplitude) array."""
        return (*key[:-1], slice(None), self.amplitude_slice(key))

    def params_at(self, key: ChunkKey) -> Parameters:
        changes = {
            name: values[i] for (name, values), i in zip(self.param_axes, key[:-1], strict=True)
        }
        return self.base.replace(**changes) if changes else self.base

    # -- identity -----------------------------------------------------------------------
    def definition(self) -> dict[str, Any]:
        """Everything that determines the result, as JSON-able data (floats exact via repr)."""
        return {
            "base": {k: repr(v) for k, v in self.base.to_dict().items()},
            "param_axes": [[name, [repr(v) for v in values]] for name, values in self.param_axes],
            "forces": [repr(v) for v in self.forces],
            "amplitudes": [repr(v) for v in self.amplitudes],
            "method": self.method,
            "duration": repr(self.duration) if self.method == "time" else None,
            "dt": repr(self.dt) if self.method == "time" else None,
            "amplitude_chunk": self.amplitude_chunk,
        }

    def fingerprint(self) -> str:
        text = json.dumps(self.definition(), sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()

    def differences(self, other_definition: dict[str, Any]) -> list[str]:
        """Names of the definition entries that differ from ``other_definition``."""
        mine = self.definition()
        keys = set(mine) | set(other_definition)
        return sorted(k for k in keys if mine.get(k) != other_definition.get(k))
