"""The definition of a sweep: a grid over a Model's numeric fields, force and amplitude.

Axes are keyed by the model's dotted names ("mu", "params.mu", "damping.ratio",
"excitation.frequency", ...; :meth:`Model.numeric_fields`). A chunk is one combination
of the parameter axes, every force, and a run of consecutive amplitudes: at a given
amplitude the steady-state method shares one normal orbit across all forces, so forces
are never split. A model with a normal excitation has no amplitude axis (its normal
motion is set by the excitation): it is stored with one placeholder amplitude and the
result drops that axis.
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

from microslip import budget
from microslip import validation as check
from microslip.model.capabilities import require
from microslip.model.composition import Model, as_model
from microslip.model.parameters import DERIVED_RANGES, Parameters
from microslip.sweeps.axes import (
    check_fields,
    check_part_axes,
    checked_axis,
    grid_logs,
)
from microslip.sweeps.kernel_choice import (
    CUDA_CHUNK_LANES,
    SWEEP_INSTEAD,
    allowed_parts,
    checked_backend,
    estimate_work,
)

METHODS = ("steady", "time")
DEFAULT_DURATION = 0.05  # [s], "time" method
# Parameter combinations are checked on a dense grid; beyond this many it would not fit.
MAX_PARAMETER_SETS = 10_000_000
ChunkKey = tuple[int, ...]  # parameter-axis indices..., amplitude-chunk index


@dataclass(frozen=True)
class SweepSpec:
    """A sweep of the mean sliding velocity (SI units).

    Attributes
    ----------
    base : the model whose fields are not swept (its ``params``: the Parameters)
    param_axes : ((dotted field name, values), ...) swept model fields, in order
    forces : tangential forces F [N]
    amplitudes : normal vibration amplitudes A [m] (one NaN placeholder for a model
        with a normal excitation)
    method : "steady" (exact steady state) or "time" (batched RK4 over ``duration``)
    duration : simulated time per point for "time" [s]
    dt : RK4 step for "time" [s]; None means T0/200 of each parameter set
    amplitude_chunk : amplitudes per chunk
    backend : "cpu" or "cuda" (the shared-normal time kernels' lanes on a GPU:
        :mod:`microslip.integrators.shared_lanes_cuda`,
        :mod:`microslip.integrators.spring_lanes_cuda`,
        :mod:`microslip.integrators.mindlin_lanes_cuda`)
    """

    base: Model
    param_axes: tuple[tuple[str, tuple[float, ...]], ...]
    forces: tuple[float, ...]
    amplitudes: tuple[float, ...]
    method: str = "steady"
    duration: float = 0.05
    dt: float | None = None
    amplitude_chunk: int = 8
    backend: str = "cpu"

    @classmethod
    def build(
        cls,
        model_or_params: Model | Parameters | None,
        axes: Mapping[str, Any] | None,
        forces: Any,
        amplitudes: Any = None,
        *,
        method: str = "steady",
        duration: float | None = None,
        dt: float | None = None,
        amplitude_chunk: int | None = None,
        allow_large: bool | None = None,
        backend: str = "cpu",
    ) -> SweepSpec:
        """Validate every input and build the spec (``ValueError`` naming the culprit).

        Axes are keyed by the model's dotted field names (:meth:`Model.numeric_fields`);
        every combination of the swept fields must make a valid model (at most
        ``MAX_PARAMETER_SETS`` combinations; values of part fields are checked by
        building the :class:`Model`). A model with a normal excitation takes no
        amplitudes (its dims are (*axes, "force")). Forces must be in
        [0, 1e6 m g] and amplitudes in [0, 1e3 y0] for every combination. ``duration``
        [s] (default 0.05 s) and ``dt`` [s] (default T0/200 of each combination) apply
        to ``method="time"`` only: with "steady" a ``dt`` or a ``duration`` other than
        the default is refused rather than silently ignored. With "time", ``dt`` must
        be <= T0/10 for every combination (the check of ``simulate(method="rk4")``;
        the error names the combination with the shortest T0), and ``duration``
        at least ``MIN_DURATION_PERIODS`` (1e-6) T0 of every combination.

        Every axis (force, amplitude, each swept field) holds distinct values, at most
        ``MAX_AXIS_VALUES`` (1e7) of them. The work and memory are estimated from the
        sizes before any per-value structure is built: a grid whose memory exceeds the
        available memory is refused (:class:`microslip.budget.WorkLimitError`) whatever
        ``allow_large``; with ``allow_large`` False the full check of
        :meth:`check_budget` is made here too (None: left to :meth:`check_budget`).

        ``backend="cuda"`` runs the lanes of the shared-normal time kernels on a GPU
        (method "time"; a rigid contact, a TangentialSpring or a MindlinSpring, whose
        set-ups that leave contact at an m2 other than 1, 2 or >= 3 run on the batched
        kernel on the CPU as with ``backend="cpu"``; refused otherwise, and where no GPU
        can be used, with the reason).
        """
        model = as_model(model_or_params)
        method = check.one_of("method", method, METHODS)
        require(model, "sweep", allowed=allowed_parts(method), instead=SWEEP_INSTEAD)
        params = model.params
        forced = model.excitation is not None
        if forced and amplitudes is not None:
            raise ValueError(
                "amplitude applies to the free vibration; this model's normal motion is set "
                "by its excitation (sweep 'excitation.amplitude' instead)"
            )
        if not forced and amplitudes is None:
            raise ValueError("amplitude [m] is required for the free normal vibration")
        if axes is not None and not isinstance(axes, Mapping):
            raise ValueError(
                "axes must be a mapping of model field -> values, e.g. {'mu': [0.1, 0.2]}; "
                f"got {type(axes).__name__}"
            )
        # Arrays first, tuples last: sizes, work and memory are checked before anything
        # grows with the grid (a 1e9-point grid is refused in well under a second).
        arrays = []
        for name, values in (axes or {}).items():
            if name in ("force", "amplitude"):
                raise ValueError(f"{name!r} is a sweep axis of its own; pass it as {name}=...")
            if not isinstance(name, str):
                raise ValueError(f"a sweep axis name must be a string, got {name!r}")
            if name.removeprefix("params.") not in model.numeric_fields():
                if name.split(".", 1)[0] in model.parts():
                    model.canonical_name(name)  # the model's message (no such part)
                known = ", ".join(model.numeric_fields())
                raise ValueError(f"unknown parameter {name!r} in sweep; known: {known}")
            name = model.canonical_name(name)
            if any(name == other for other, _ in arrays):
                raise ValueError(f"{name!r} is given twice as a sweep axis")
            arrays.append((name, checked_axis(name, values)))
        backend = checked_backend(backend, model, method, arrays)
        forces = checked_axis("force", forces)
        if np.any(forces < 0):
            raise ValueError(
                f"force must be >= 0 N in a sweep (the mean velocity is computed for forward "
                f"sliding), got {float(forces[forces < 0][0])!r}"
            )
        amplitudes = np.array([math.nan]) if forced else checked_axis("amplitude", amplitudes)
        if not forced and np.any(amplitudes < 0):
            raise ValueError(
                f"amplitude must be >= 0 m, got {float(amplitudes[amplitudes < 0][0])!r}"
            )
        if method == "steady":
            if dt is not None:
                raise ValueError(f"dt={dt!r} applies to method='time' only, not 'steady'")
            if duration is not None and duration != DEFAULT_DURATION:
                raise ValueError(
                    f"duration={duration!r} applies to method='time' only; 'steady' computes "
                    "the long-time mean"
                )
        duration = DEFAULT_DURATION if duration is None else duration
        duration = check.real("duration", duration, minimum=0.0, strict=True)
        if dt is not None:
            dt = check.real("dt", dt, minimum=0.0, strict=True)
        if amplitude_chunk is None:
            lanes = CUDA_CHUNK_LANES if backend == "cuda" else 4096
            amplitude_chunk = 8 if method == "steady" else max(1, lanes // len(forces))
        amplitude_chunk = min(
            check.positive_int("amplitude_chunk", amplitude_chunk), len(amplitudes)
        )
        n_sets = math.prod(len(values) for _, values in arrays)
        if n_sets > MAX_PARAMETER_SETS:
            raise ValueError(
                f"the sweep has {n_sets} parameter combinations; at most "
                f"{MAX_PARAMETER_SETS} are supported"
            )
        check_fields(params, arrays)
        check_part_axes(model, arrays)
        estimate = estimate_work(
            model, arrays, len(forces), len(amplitudes), method, duration, dt, amplitude_chunk,
            forces, amplitudes,
        )  # fmt: skip
        if allow_large is not None:
            budget.check(estimate, allow_large=allow_large)
        # Memory beyond what is available cannot be had, whatever allow_large says.
        budget.check_fits(estimate)
        spec = cls(
            base=model,
            param_axes=tuple((name, tuple(float(v) for v in values)) for name, values in arrays),
            forces=tuple(float(f) for f in forces),
            amplitudes=tuple(float(a) for a in amplitudes),
            method=method,
            duration=duration,
            dt=dt,
            amplitude_chunk=amplitude_chunk,
            backend=backend,
        )
        spec._check_parameter_sets()
        return spec

    # -- checks over every parameter combination ------------------------------------------
    def _params_at_index(self, index: tuple[int, ...]) -> Parameters:
        return self.params_at((*index, 0))

    @property
    def forced(self) -> bool:
        """True for a model with a normal excitation (no amplitude axis)."""
        return self.base.excitation is not None

    def _part_axes(self) -> bool:
        return any("." in name for name, _ in self.param_axes)

    def _where(self, index: tuple[int, ...]) -> str:
        if not self.param_axes:
            return ""
        text = ", ".join(
            f"{name}={values[i]!r}"
            for (name, values), i in zip(self.param_axes, index, strict=True)
        )
        return f" at {text}"

    def _check_parameter_sets(self) -> None:
        """Every combination valid; forces, amplitudes and dt within its limits.

        Called by :meth:`build` once it has checked the number of combinations."""
        logs = grid_logs(self.base.params, self.param_axes)
        bad = np.zeros(logs["mg"].shape, dtype=bool)
        for name, (low, high, _unit, _description) in DERIVED_RANGES.items():
            bad |= ~((logs[name] >= math.log10(low)) & (logs[name] <= math.log10(high)))
        if bad.any():
            # Parameters names the quantity out of range (same formulas as the grid).
            self._params_at_index(tuple(int(i) for i in np.argwhere(bad)[0]))
        worst_mg = np.unravel_index(np.argmin(logs["mg"]), logs["mg"].shape)
        worst_y0 = np.unravel_index(np.argmin(logs["y0"]), logs["y0"].shape)
        try:
            check.force(self._params_at_index(worst_mg), max(self.forces))
        except ValueError as error:
            raise ValueError(f"{error}{self._where(worst_mg)}") from None
        if not self.forced:
            try:
                check.amplitude(self._params_at_index(worst_y0), max(self.amplitudes))
            except ValueError as error:
                raise ValueError(f"{error}{self._where(worst_y0)}") from None
        if self.method == "time" and (self.forced or self.base.is_compliant):
            self._check_time_by_set()
            return
        if self.method == "time":
            longest = np.unravel_index(np.argmax(logs["T0"]), logs["T0"].shape)
            params = self._params_at_index(longest)
            check.duration(self.duration, params.natural_period, where=self._where(longest))
        if self.method == "time" and self.dt is not None:
            worst = np.unravel_index(np.argmin(logs["T0"]), logs["T0"].shape)
            params = self._params_at_index(worst)
            check.rk4_step(self.dt, params.natural_period, where=self._where(worst))

    def _check_time_by_set(self) -> None:
        """Duration against T0 and the step against :meth:`step_period` of every set."""
        shortest = (math.inf, ())
        longest = (0.0, ())
        for index in itertools.product(*(range(len(v)) for _, v in self.param_axes)):
            period = self.step_period(self.model_at((*index, 0)))
            shortest = min(shortest, (period, index))
            longest = max(longest, (self.model_at((*index, 0)).params.natural_period, index))
        check.duration(self.duration, longest[0], where=self._where(longest[1]))
        if self.dt is not None:
            check.rk4_step(self.dt, shortest[0], where=self._where(shortest[1]))

    @staticmethod
    def step_period(model: Model) -> float:
        """The period an RK4 step must resolve [s]: the shortest of T0, the excitation
        period and the tangential oscillation on a compliant contact
        (:func:`microslip.budget.shortest_period`)."""
        return budget.shortest_period(model)

    def estimate(self) -> budget.Estimate:
        """Estimated work, run time [s] and memory [bytes] (:mod:`microslip.budget`)."""
        return estimate_work(
            self.base, self.param_axes, len(self.forces), len(self.amplitudes), self.method,
            self.duration, self.dt, self.amplitude_chunk, self.forces, self.amplitudes,
        )  # fmt: skip

    def check_budget(self, *, allow_large: bool = False) -> budget.Estimate:
        """Refuse (:class:`microslip.budget.WorkLimitError`) a sweep whose estimated run
        time exceeds 10 minutes or whose memory exceeds half the available memory,
        unless ``allow_large``; returns the estimate checked. Called by
        :func:`microslip.sweep` and the CLI."""
        estimate = self.estimate()
        budget.check(estimate, allow_large=allow_large)
        return estimate

    # -- geometry ---------------------------------------------------------------------
    @property
    def dims(self) -> tuple[str, ...]:
        """Dims of the stored array (with "amplitude", a placeholder for a forced model)."""
        return (*(name for name, _ in self.param_axes), "force", "amplitude")

    @property
    def result_dims(self) -> tuple[str, ...]:
        """Dims of the result: (*axes, "force") for a forced model."""
        return self.dims[:-1] if self.forced else self.dims

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

    def model_at(self, key: ChunkKey) -> Model:
        changes = {
            name: values[i] for (name, values), i in zip(self.param_axes, key[:-1], strict=True)
        }
        return self.base.replace(**changes) if changes else self.base

    def params_at(self, key: ChunkKey) -> Parameters:
        return self.model_at(key).params

    # -- identity -----------------------------------------------------------------------
    def definition(self) -> dict[str, Any]:
        """Everything that determines the result, as JSON-able data (floats exact via repr)."""
        return {
            "base": {k: repr(v) for k, v in self.base.params.to_dict().items()},
            "model": {k: repr(v) for k, v in self.base.to_attrs().items()},
            "param_axes": [[name, [repr(v) for v in values]] for name, values in self.param_axes],
            "forces": [repr(v) for v in self.forces],
            "amplitudes": [repr(v) for v in self.amplitudes],
            "method": self.method,
            "duration": repr(self.duration) if self.method == "time" else None,
            "dt": repr(self.dt) if self.method == "time" else None,
            "amplitude_chunk": self.amplitude_chunk,
            # Only where it is not the default: stores made before it existed still match.
            **({"backend": self.backend} if self.backend != "cpu" else {}),
        }

    def fingerprint(self) -> str:
        text = json.dumps(self.definition(), sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()

    def differences(self, other_definition: dict[str, Any]) -> list[str]:
        """Names of the definition entries that differ from ``other_definition``."""
        mine = self.definition()
        keys = set(mine) | set(other_definition)
        return sorted(k for k in keys if mine.get(k) != other_definition.get(k))
