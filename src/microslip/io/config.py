"""TOML configuration files: ``[parameters]`` plus one table per command.

Example::

    [parameters]        # any Parameters field, SI units
    mu = 0.12
    c_n = 4.0e16

    [simulate]          # any option of `microslip simulate`, by its long flag name
    force = 0.5
    amplitude = 1.5e-7
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

from microslip.model.parameters import Parameters

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def load_config(path: str | Path) -> dict[str, Any]:
    """Read a TOML file; ``ValueError`` naming the file if it is missing or malformed."""
    path = Path(path)
    try:
        with path.open("rb") as handle:
            data = tomllib.load(handle)
    except FileNotFoundError:
        raise ValueError(f"config file {str(path)!r} does not exist") from None
    except (OSError, tomllib.TOMLDecodeError) as error:
        raise ValueError(f"config file {str(path)!r} is unreadable: {error}") from None
    return data


def parameters_from_config(data: dict[str, Any], source: str) -> dict[str, float]:
    """The ``[parameters]`` table, checked for unknown fields and for numbers."""
    table = data.get("parameters", {})
    if not isinstance(table, dict):
        raise ValueError(f"{source}: [parameters] must be a table")
    known = Parameters.field_names()
    values: dict[str, float] = {}
    for key, value in table.items():
        if key not in known:
            raise ValueError(
                f"{source}: unknown parameter {key!r} in [parameters]; known: {', '.join(known)}"
            )
        # TOML booleans are not numbers here, though Python's bool is an int
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            unit = Parameters.field_unit(key)
            raise ValueError(
                f"{source}: {key} in [parameters] must be a number [{unit}], got {value!r}"
            )
        values[key] = float(value)
    return values


def command_options(data: dict[str, Any], command: str, allowed: set[str], source: str) -> dict:
    """The ``[command]`` table, checked against the command's option names."""
    table = data.get(command, {})
    if not isinstance(table, dict):
        raise ValueError(f"{source}: [{command}] must be a table")
    for key in table:
        if key.replace("-", "_") not in allowed:
            raise ValueError(
                f"{source}: unknown option {key!r} in [{command}]; "
                f"known: {', '.join(sorted(allowed))}"
            )
    unknown_tables = set(data) - {"parameters", command}
    for name in unknown_tables:
        if not isinstance(data[name], dict):
            raise ValueError(f"{source}: unexpected top-level key {name!r}")
    return {key.replace("-", "_"): value for key, value in table.items()}
