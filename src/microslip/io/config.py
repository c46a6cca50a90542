"""TOML configuration files: ``[parameters]``, the model's parts, one table per command.

Example::

    [parameters]        # any Parameters field, SI units
    mu = 0.12
    c_n = 4.0e16

    [damping]           # normal damping of the contact (default: none, the paper's)
    law = "viscous"     # "none", "viscous" or "hunt-crossley"
    ratio = 0.03        # damping ratio zeta at the working point [-]

    [excitation]        # normal excitation (default: none, free vibration)
    kind = "harmonic-force"   # "none", "harmonic-force", "base-motion", "prescribed-penetration"
    amplitude = 0.5     # P0 [N] (harmonic-force) or Z, Delta [m]
    frequency = 1400.0  # f [Hz]
    # mean = 1e-7       # delta_m [m], prescribed-penetration only

    [simulate]          # any option of `microslip simulate`, by its long flag name
    force = 0.5
    amplitude = 1.5e-7
"""

from __future__ import annotations

import math
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
    except UnicodeDecodeError as error:  # TOML is UTF-8; say where, not only the byte
        raise ValueError(
            f"config file {str(path)!r} is not UTF-8 text (byte {error.start}); save it as UTF-8"
        ) from None
    except IsADirectoryError:
        raise ValueError(f"config file {str(path)!r} is a directory") from None
    except (OSError, tomllib.TOMLDecodeError) as error:
        raise ValueError(f"config file {str(path)!r} is unreadable: {error}") from None
    return data


#: The tables of the model's parts and the type of each key ("str" or "float").
PART_TABLES: dict[str, dict[str, str]] = {
    "damping": {"law": "str", "ratio": "float"},
    "excitation": {"kind": "str", "amplitude": "float", "frequency": "float", "mean": "float"},
}


def parts_from_config(data: dict[str, Any], source: str) -> dict[str, dict[str, Any]]:
    """The ``[damping]`` and ``[excitation]`` tables, checked for unknown keys and types.

    Returns ``{table: {key: value}}`` for the tables present (numbers as floats). Which
    keys a kind needs, and their ranges, are checked when the model is built
    (:mod:`microslip.cli.model_options`).
    """
    out: dict[str, dict[str, Any]] = {}
    for name, schema in PART_TABLES.items():
        if name not in data:
            continue
        table = data[name]
        if not isinstance(table, dict):
            raise ValueError(f"{source}: [{name}] must be a table")
        values: dict[str, Any] = {}
        for key, value in table.items():
            if key not in schema:
                raise ValueError(
                    f"{source}: unknown key {key!r} in [{name}]; known: {', '.join(schema)}"
                )
            if schema[key] == "str":
                if not isinstance(value, str):
                    raise ValueError(f"{source}: {key} in [{name}] must be a string, got {value!r}")
            else:
                value = _number(value)
                if value is None:
                    raise ValueError(
                        f"{source}: {key} in [{name}] must be a finite number, got {table[key]!r}"
                    )
            values[key] = value
        out[name] = values
    return out


def _number(value: Any) -> float | None:
    """``value`` as a finite float, or None (a TOML boolean is not a number here)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    try:
        number = float(value)
    except OverflowError:  # an integer beyond 1e308
        return None
    return number if math.isfinite(number) else None


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
        try:
            number = None if isinstance(value, bool) else float(value)
        except (TypeError, ValueError, OverflowError):  # OverflowError: an int beyond 1e308
            number = None
        if number is None or not isinstance(value, (int, float)):
            unit = Parameters.field_unit(key)
            raise ValueError(
                f"{source}: {key} in [parameters] must be a number [{unit}], got {value!r}"
            )
        values[key] = number
    return values


def command_options(
    data: dict[str, Any], command: str, schemas: dict[str, set[str]], source: str
) -> dict[str, Any]:
    """The ``[command]`` table, checked against the command's option names.

    ``schemas`` maps every command to its option names: a file shared between commands
    may hold the other commands' tables, but each is checked too (a misspelled key is
    refused, whichever command reads the file), and so is every top-level name (a
    misspelled ``[paramters]`` would otherwise be ignored without a word).
    """
    known_tables = {"parameters", *PART_TABLES, *schemas}
    for name, table in data.items():
        if name not in known_tables:
            raise ValueError(
                f"{source}: unknown table [{name}]; known: {', '.join(sorted(known_tables))}"
            )
        if not isinstance(table, dict):
            raise ValueError(f"{source}: [{name}] must be a table")
    options: dict[str, Any] = {}
    for name, allowed in schemas.items():
        spelled: dict[str, str] = {}
        for key, value in data.get(name, {}).items():
            option = key.replace("-", "_")
            if option not in allowed:
                raise ValueError(
                    f"{source}: unknown option {key!r} in [{name}]; "
                    f"known: {', '.join(sorted(allowed))}"
                )
            if option in spelled:  # `initial-state` and `initial_state`: which one?
                raise ValueError(
                    f"{source}: {spelled[option]!r} and {key!r} in [{name}] are the same "
                    "option; keep one"
                )
            spelled[option] = key
            if name == command:
                options[option] = value
    return options
