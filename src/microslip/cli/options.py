"""Options of each command: typed, merged from ``--config`` and flags, checked for sense.

Every option has one kind; a TOML value of another type is refused in one line naming
the key and the file. Options that would do nothing in the chosen mode (``--dt`` with
the steady method, ``--workers`` with ``--scheduler``, ...) are refused too, naming
where they came from (flag or config key).
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np


class CliError(ValueError):
    """An input error to report in one line."""


# Kinds: "float" (finite real), "int", "str", "bool", "values" (a range string, a number or
# a list of numbers), "params" (NAME=RANGE strings), "state" (four numbers), "pair" (a
# string "START:END" or a list of two numbers).
SIMULATE = {
    "force": "float", "amplitude": "float", "initial_state": "state", "duration": "float",
    "method": "str", "dt": "float", "rtol": "float", "atol": "float", "samples": "int",
    "save_every": "int", "out": "str", "plot": "str", "overwrite": "bool", "allow_large": "bool",
}  # fmt: skip
MAP = {
    "force": "values", "amplitude": "values", "out": "str", "plot": "str", "method": "str",
    "duration": "float", "dt": "float", "scheduler": "str", "workers": "int", "chunk": "int",
    "quiet": "bool", "overwrite": "bool", "allow_large": "bool", "backend": "str",
}  # fmt: skip
SWEEP = {**MAP, "param": "params"}
FIGURES = {
    "out": "str", "only": "str", "dpi": "int", "quiet": "bool", "overwrite": "bool",
    "extensions": "bool",
}  # fmt: skip
INFO = {"json": "bool"}
RESPONSE = {
    "frequencies": "pair", "amplitudes": "pair", "max_points": "int", "out": "str",
    "plot": "str", "overwrite": "bool",
}  # fmt: skip
FRICTION = {
    "velocities": "values", "axis": "str", "amplitude": "float", "out": "str", "plot": "str",
    "overwrite": "bool",
}  # fmt: skip
SCHEMAS = {
    "info": INFO, "simulate": SIMULATE, "figures": FIGURES, "map": MAP, "sweep": SWEEP,
    "response": RESPONSE, "friction": FRICTION,
}  # fmt: skip
#: The TOML table of each command's options, where it is not the command's name:
#: ``[friction]`` is the friction law's table, so ``microslip friction`` reads
#: ``[effective-friction]``.
TABLES = {"friction": "effective-friction"}
#: Commands that take the model's parts (--damping, --tangential, [drive], ...).
PART_COMMANDS = ("info", "simulate", "map", "sweep", "response", "friction")


@dataclass
class Options:
    """Parameters and options of one command, with where each option came from."""

    params: Any
    values: dict[str, Any] = field(default_factory=dict)
    origin: dict[str, str] = field(default_factory=dict)
    param_origin: dict[str, str] = field(default_factory=dict)  # Parameters field -> source
    parts: dict[str, Any] = field(default_factory=dict)  # slot -> model_options.PartChoice

    def model(self, provided: dict[str, tuple[float, str]] | None = None) -> Any:
        """The :class:`~microslip.model.composition.Model` of the parameters and parts;
        ``provided``: fields the command sets itself (see ``model_options.build_model``)."""
        from microslip.cli.model_options import build_model

        return build_model(self.params, self.parts, provided)

    def part_origin(self) -> dict[str, str]:
        """Where each given part field came from, by dotted name."""
        out: dict[str, str] = {}
        for choice in self.parts.values():
            out.update(choice.origins())
        return out

    def __contains__(self, name: str) -> bool:
        return name in self.values

    def get(self, name: str, default: Any = None) -> Any:
        return self.values.get(name, default)

    def __getitem__(self, name: str) -> Any:
        return self.values[name]

    def flag(self, name: str) -> str:
        """How the user gave option ``name``: ``--flag`` or ``key in [table] of FILE``."""
        return self.origin.get(name, "--" + name.replace("_", "-"))

    def refuse_together(self, first: str, second: str, reason: str) -> None:
        if first in self and second in self:
            raise CliError(
                f"{self.flag(first)} cannot be combined with {self.flag(second)}: {reason}"
            )

    def refuse(self, name: str, reason: str) -> None:
        if name in self:
            raise CliError(f"{self.flag(name)} has no effect {reason}; remove it")


def _typed(kind: str, key: str, value: Any, where: str) -> Any:
    """A config value checked against its kind (``CliError`` naming ``key`` otherwise)."""

    def fail(expected: str) -> CliError:
        return CliError(f"{where}: {key} must be {expected}, got {value!r}")

    is_number = isinstance(value, (int, float)) and not isinstance(value, bool)
    if kind == "float":
        if not is_number:
            raise fail("a number")
        if not _fits_float(value):
            raise fail("a finite number")
        return float(value)
    if kind == "int":
        if isinstance(value, bool) or not isinstance(value, int):
            raise fail("an integer")
        if abs(value) > INT_LIMIT:
            raise fail(f"an integer of at most {INT_LIMIT}")
        return value
    if kind == "str":
        if not isinstance(value, str):
            raise fail("a string")
        return value
    if kind == "bool":
        if not isinstance(value, bool):
            raise fail("true or false")
        return value
    if kind == "values":
        if isinstance(value, str):
            return value
        if is_number and _fits_float(value):
            return repr(float(value))
        if (
            isinstance(value, list)
            and value
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
            and all(_fits_float(v) for v in value)
        ):
            return ",".join(repr(float(v)) for v in value)
        raise fail('a range string "start:stop:count", a number or a list of numbers')
    if kind == "params":
        items = [value] if isinstance(value, str) else value
        if not isinstance(items, list) or not items or not all(isinstance(v, str) for v in items):
            raise fail('a string "NAME=RANGE" or a list of them')
        return list(items)
    if kind == "state":
        if isinstance(value, str):
            return value
        if (
            isinstance(value, list)
            and len(value) == 4
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
            and all(_fits_float(v) for v in value)
        ):
            return ",".join(repr(float(v)) for v in value)
        raise fail("four finite numbers y,ydot,x,xdot (a list or a string)")
    if kind == "pair":
        if isinstance(value, str):
            return value
        if (
            isinstance(value, list)
            and len(value) == 2
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
            and all(_fits_float(v) for v in value)
        ):
            return ":".join(repr(float(v)) for v in value)
        raise fail('a string "START:END" or a list of two finite numbers')
    raise AssertionError(kind)  # pragma: no cover - the schemas above use known kinds


def command_table(command: str) -> str:
    """The TOML table holding the options of ``command``."""
    return TABLES.get(command, command)


def gather(args: argparse.Namespace, command: str) -> Options:
    """(Parameters, options) from the ``--config`` file, then the flags (flags win).

    A list option (``param``) given both in the file and as flags is refused: the
    flags would silently drop the file's entries.
    """
    from microslip.cli.model_options import gather_parts, refuse_parts
    from microslip.io.config import (
        command_options,
        load_config,
        parameters_from_config,
        parts_from_config,
    )
    from microslip.model.parameters import Parameters

    schema = SCHEMAS[command]
    param_values: dict[str, Any] = {}
    opts = Options(params=None)
    data: dict[str, Any] | None = None
    source = None
    if args.config is not None:
        data = load_config(args.config)
        source = str(args.config)
        for key, value in parameters_from_config(data, source).items():
            param_values[key] = value
            opts.param_origin[key] = f"{key} in [parameters] of {source}"
        table = command_table(command)
        where = f"{source} [{table}]"
        known = {command_table(name): set(keys) for name, keys in SCHEMAS.items()}
        for key, value in command_options(data, table, known, source).items():
            opts.values[key] = _typed(schema[key], key, value, where)
            opts.origin[key] = f"{key} in [{table}] of {source}"
    for name in Parameters.field_names():
        if getattr(args, name) is not None:
            param_values[name] = getattr(args, name)
            opts.param_origin[name] = "--" + name.replace("_", "-")
    for name in schema:
        value = getattr(args, name, None)
        if value is None:
            continue
        if name == "param" and name in opts.origin:
            raise CliError(
                f"--param cannot be combined with {opts.origin[name]}: give every "
                "NAME=RANGE in one place"
            )
        opts.values[name] = value
        opts.origin[name] = "--" + name.replace("_", "-")
    opts.params = Parameters(**param_values)
    if command in PART_COMMANDS:
        tables = parts_from_config(data, str(source)) if data is not None else {}
        opts.parts = gather_parts(args, tables, source)
    else:
        refuse_parts(args, data, str(source), command, "draws the paper's model, without parts")
    return opts


INT_LIMIT = 2**62  # larger counts cannot be allocated or indexed (numpy int64)


def _fits_float(value: int | float) -> bool:
    try:
        return math.isfinite(float(value))
    except OverflowError:  # a TOML integer beyond 1.8e308
        return False


def parse_range(name: str, text: str) -> np.ndarray:
    """Values of a range option: ``start:stop:count`` (inclusive, evenly spaced),
    ``start:stop:count:log`` (inclusive, evenly spaced in log10, 0 < start), ``a,b,c`` or
    one number (:func:`microslip.io.ranges.parse_values`); ``CliError`` naming ``name``."""
    from microslip.io.ranges import parse_values

    text = refuse_underscores(name, str(text)).strip()
    head, sep, scale = text.rpartition(":")
    log = bool(sep) and scale.strip().lower() == "log"
    try:
        values = parse_values(name, head if log else text)
    except ValueError as error:
        raise CliError(str(error)) from None
    if not log:
        return values
    if head.count(":") != 2:
        raise CliError(f"{name}: expected start:stop:count:log, got {text!r}")
    if values[0] <= 0.0:
        raise CliError(f"{name}: a log range needs 0 < start, got {text!r}")
    return np.geomspace(values[0], values[-1], values.size)


def refuse_underscores(name: str, text: str) -> str:
    """``CliError`` for ``1_0``: Python reads it as 10, a user more likely mistyped."""
    if "_" in str(text):
        raise CliError(f"{name}: '_' is not allowed in a number, got {text!r}")
    return str(text)


def real(text: str) -> float:
    """argparse type: a float (inf and nan too, for Parameters to name the field and the
    rule broken), but not ``1_0``."""
    if "_" in text:
        raise argparse.ArgumentTypeError(f"'_' is not allowed in a number, got {text!r}")
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None


def finite(text: str) -> float:
    """argparse type: a finite float, else a one-line error (argparse names the flag)."""
    value = real(text)
    if not np.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be finite, got {text!r}")
    return value


def integer(text: str) -> int:
    """argparse type: a decimal integer of at most :data:`INT_LIMIT` in size."""
    if "_" in text:
        raise argparse.ArgumentTypeError(f"'_' is not allowed in a number, got {text!r}")
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if abs(value) > INT_LIMIT:
        raise argparse.ArgumentTypeError(f"must be at most {INT_LIMIT}, got {text!r}")
    return value


def path_text(text: str) -> str:
    """argparse type: a non-empty path (``Path('')`` would mean the current directory)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("empty path")
    return text
