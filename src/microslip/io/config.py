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

    [tangential]        # tangential contact (default: rigid, the paper's)
    kind = "spring"     # "rigid", "spring" (stiffness [N m-1]) or "mindlin" (ratio [1])
    stiffness = 1.0e6   # k_t [N m-1]

    [friction]          # friction law (default: coulomb with mu of [parameters])
    law = "static-kinetic"    # "coulomb", "static-kinetic" or "stribeck"
    mu_static = 0.15    # mu_s [1]
    mu_kinetic = 0.1    # mu_k [1]
    # velocity = 1e-4   # v_s [m s-1], stribeck only
    # exponent = 2.0    # q [1], stribeck only

    [drive]             # tangential drive (default: none, the force of each command)
    kind = "harmonic"   # "none", "constant-force", "harmonic", "spring", "prescribed-velocity"
    mean = 0.2          # F0 [N] (harmonic); constant-force: force [N]
    amplitude = 0.1     # F1 [N] (harmonic)
    frequency = 100.0   # f_d [Hz] (harmonic)
    # stiffness, velocity: k_d [N m-1] and v_d [m s-1] (spring); velocity (prescribed-velocity)

    [simulate]          # any option of `microslip simulate`, by its long flag name
    amplitude = 1.5e-7
    duration = 0.01

The options of ``microslip friction`` are in ``[effective-friction]`` (``[friction]`` is
the friction law's table). A physical law is chosen with ``law`` (damping, friction),
any other part with ``kind``; the kinds and fields are those of :data:`PART_TABLES`,
spelled as on the command line (``--friction static-kinetic --friction-mu-static 0.15``).
A field key may be written with ``_`` or ``-`` (``mu_static`` or ``mu-static``), not both.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
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


@dataclass(frozen=True)
class PartTable:
    """How one slot of a :class:`~microslip.model.composition.Model` is spelled in a
    TOML table and on the command line (``[friction] law = "stribeck"``,
    ``--friction stribeck``). Class names, not classes: reading it loads no numba."""

    selector: str  # the key naming the kind: "law" or "kind"
    kinds: dict[str, str | None]  # kind -> class name exported by microslip (None: no part)
    fields: tuple[str, ...]  # every numeric field of any kind, in flag order
    paper: str  # the kind of the paper's model, used when the slot is not given


#: The part tables, by slot (the Model attribute and the table name), in flag order.
PART_TABLES: dict[str, PartTable] = {
    "damping": PartTable(
        "law", {"none": None, "viscous": "Viscous", "hunt-crossley": "HuntCrossley"},
        ("ratio",), "none",
    ),
    "excitation": PartTable(
        "kind",
        {"none": None, "harmonic-force": "HarmonicForce", "base-motion": "BaseMotion",
         "prescribed-penetration": "PrescribedPenetration"},
        ("amplitude", "frequency", "mean"), "none",
    ),
    "tangential": PartTable(
        "kind", {"rigid": "Rigid", "spring": "TangentialSpring", "mindlin": "MindlinSpring"},
        ("stiffness", "ratio"), "rigid",
    ),
    "friction": PartTable(
        "law", {"coulomb": "Coulomb", "static-kinetic": "StaticKinetic", "stribeck": "Stribeck"},
        ("mu_static", "mu_kinetic", "velocity", "exponent"), "coulomb",
    ),
    "drive": PartTable(
        "kind",
        {"none": None, "constant-force": "ConstantForce", "harmonic": "HarmonicDrive",
         "spring": "SpringDrive", "prescribed-velocity": "PrescribedVelocity"},
        ("force", "mean", "amplitude", "frequency", "stiffness", "velocity"), "none",
    ),
}  # fmt: skip


def parts_from_config(data: dict[str, Any], source: str) -> dict[str, dict[str, Any]]:
    """The part tables (:data:`PART_TABLES`), checked for unknown keys and types.

    Returns ``{table: {key: value}}`` for the tables present (numbers as floats, keys
    spelled with ``_``). Which keys a kind needs, and their ranges, are checked when the
    model is built (:mod:`microslip.cli.model_options`).
    """
    out: dict[str, dict[str, Any]] = {}
    for name, spec in PART_TABLES.items():
        if name not in data:
            continue
        table = data[name]
        if not isinstance(table, dict):
            raise ValueError(f"{source}: [{name}] must be a table")
        values: dict[str, Any] = {}
        spelled: dict[str, str] = {}
        for key, value in table.items():
            canonical = key.replace("-", "_")
            if canonical != spec.selector and canonical not in spec.fields:
                raise ValueError(
                    f"{source}: unknown key {key!r} in [{name}]; "
                    f"known: {', '.join((spec.selector, *spec.fields))}"
                )
            if canonical in spelled:  # `mu_static` and `mu-static`: which one?
                raise ValueError(
                    f"{source}: {spelled[canonical]!r} and {key!r} in [{name}] are the same "
                    "key; keep one"
                )
            spelled[canonical] = key
            if canonical == spec.selector:
                if not isinstance(value, str):
                    raise ValueError(f"{source}: {key} in [{name}] must be a string, got {value!r}")
            else:
                value = _number(value)
                if value is None:
                    raise ValueError(
                        f"{source}: {key} in [{name}] must be a finite number, got {table[key]!r}"
                    )
            values[canonical] = value
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
