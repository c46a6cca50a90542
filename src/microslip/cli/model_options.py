"""The model's parts on the command line: flags and TOML tables -> a :class:`Model`.

Each part slot has a selector flag and one flag per numeric field (SI units)::

    --damping {none,viscous,hunt-crossley}   --damping-ratio Z
    --excitation {none,harmonic-force,base-motion,prescribed-penetration}
    --excitation-amplitude A  --excitation-frequency F  --excitation-mean D
    --tangential {rigid,spring,mindlin}   --tangential-stiffness K  --tangential-ratio L
    --friction {coulomb,static-kinetic,stribeck}   --friction-mu-static MU_S
    --friction-mu-kinetic MU_K  --friction-velocity V_S  --friction-exponent Q
    --drive {none,constant-force,harmonic,spring,prescribed-velocity}   --drive-force F
    --drive-mean F0  --drive-amplitude F1  --drive-frequency F_D  --drive-stiffness K_D
    --drive-velocity V

and a TOML table per slot: ``law = ...`` names a physical law (``[damping]``,
``[friction]``), ``kind = ...`` any other part (``[excitation]``, ``[tangential]``,
``[drive]``); the other keys are the fields (:mod:`microslip.io.config`). Everything is
driven by the one static table :data:`microslip.io.config.PART_TABLES` (class names,
not classes, so that building the parser loads no numba). Rules, all checked before
anything is computed:

- a flag overrides the file's value of the same field; a selector flag naming another
  kind than the file's replaces the file's whole part (an amplitude in N of a harmonic
  force must not silently become an amplitude in m of a base motion);
- a field given without its part (``--damping-ratio`` without ``--damping``), or one the
  chosen kind does not have (``--excitation-mean`` with a harmonic force), is refused;
- every field of the chosen kind must be given (no silent zero amplitude), unless the
  command sets it itself (a swept field, the range of ``microslip response``);
- values are checked by the part itself (ranges, the frequency within [1e-3 f0, 1e3 f0]),
  the message prefixed with where the value came from.

A slot left out holds the paper's choice (``None``); ``--tangential rigid`` and
``--friction coulomb`` name it explicitly (``Rigid()``, ``Coulomb()``), ``--damping none``,
``--excitation none`` and ``--drive none`` switch off a part of the config file.
"""

from __future__ import annotations

import argparse
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from microslip.cli.options import CliError, real
from microslip.io.config import PART_TABLES
from microslip.model.parameters import Parameters

if TYPE_CHECKING:  # the part modules load numba: imported on first use (see _part_class)
    from microslip.model.composition import Model

__all__ = [
    "SLOTS",
    "PartChoice",
    "Slot",
    "add_part_options",
    "build_model",
    "gather_parts",
    "kind_name",
    "require_paper_tangential",
]


def _part_class(slot: Slot, kind: str) -> type | None:
    """The part class of ``kind`` in ``slot`` (None for "none"), imported on first use."""
    name = slot.kinds[kind]
    if name is None:
        return None
    import microslip

    return getattr(microslip, name)


@dataclass(frozen=True)
class Slot:
    """One part slot as the command line spells it (from :data:`PART_TABLES`)."""

    name: str  # the Model attribute and the TOML table: "damping"
    selector: str  # the TOML key naming the kind: "law"
    kinds: dict[str, str | None]
    fields: tuple[str, ...]  # every numeric field of any kind, in flag order
    paper: str  # the kind of the paper's model ("none", "rigid", "coulomb")

    @property
    def flag(self) -> str:
        return f"--{self.name}"

    def field_flag(self, name: str) -> str:
        return f"--{self.name}-{name.replace('_', '-')}"

    def dest(self, name: str) -> str:
        return f"{self.name}_{name}"

    def kinds_with(self, name: str) -> list[str]:
        """The kinds that have the field ``name`` (imports the part classes)."""
        out = []
        for kind in self.kinds:
            cls = _part_class(self, kind)
            if cls is not None and name in cls.field_names():
                out.append(kind)
        return out


SLOTS = tuple(Slot(name, t.selector, t.kinds, t.fields, t.paper) for name, t in PART_TABLES.items())

# (slot, field) -> (metavar, help); (slot, None): the selector's help. SI units.
_HELP: dict[tuple[str, str | None], tuple[str, str]] = {
    ("damping", None): ("", "normal damping law of the contact (default: none, the paper's)"),
    ("damping", "ratio"): (
        "ZETA", "damping ratio zeta [1] at the working point, c = 2 zeta sqrt(K_n m)"),
    ("excitation", None): ("", "normal excitation (default: none, the paper's free vibration)"),
    ("excitation", "amplitude"): ("A", "P0 [N] for harmonic-force, Z [m] for base-motion, "
                                  "Delta [m] for prescribed-penetration"),
    ("excitation", "frequency"): ("F", "excitation frequency f [Hz], within [1e-3 f0, 1e3 f0]"),
    ("excitation", "mean"): ("D", "mean penetration delta_m [m] (prescribed-penetration only)"),
    ("tangential", None): ("", "tangential contact: rigid (default, the paper's), spring "
                           "(constant stiffness) or mindlin (k_t = lambda dN/ddelta)"),
    ("tangential", "stiffness"): (
        "K", "spring: tangential stiffness k_t [N m-1], within [1e-6 K_n, 1e6 K_n]"),
    ("tangential", "ratio"): ("L", "mindlin: ratio lambda [1] in [1e-3, 10] of k_t = lambda "
                              "dN/ddelta (2(1-nu)/(2-nu) for elastic spheres)"),
    ("friction", None): ("", "friction law: coulomb (default, mu of the parameters), "
                         "static-kinetic or stribeck"),
    ("friction", "mu_static"): ("MU_S", "static coefficient mu_s [1] >= mu_k"),
    ("friction", "mu_kinetic"): ("MU_K", "kinetic coefficient mu_k [1]"),
    ("friction", "velocity"): ("V_S", "stribeck: Stribeck velocity v_s [m s-1] > 0"),
    ("friction", "exponent"): ("Q", "stribeck: shape exponent q [1] in [0.1, 10]"),
    ("drive", None): ("", "tangential drive (default: none, the constant --force of the "
                      "command, the paper's Sec. 4)"),
    ("drive", "force"): ("F", "constant-force: tangential force F [N] on the body"),
    ("drive", "mean"): ("F0", "harmonic: mean force F0 [N] of F0 + F1 sin(2 pi f_d t)"),
    ("drive", "amplitude"): ("F1", "harmonic: force amplitude F1 [N] >= 0"),
    ("drive", "frequency"): ("F_D", "harmonic: drive frequency f_d [Hz], within "
                             "[1e-3 f0, 1e3 f0]"),
    ("drive", "stiffness"): ("K_D", "spring: drive spring stiffness k_d [N m-1], within "
                             "[1e-6 K_n, 1e6 K_n]"),
    ("drive", "velocity"): ("V", "spring: velocity v_d [m s-1] of the spring's far end; "
                            "prescribed-velocity: body velocity v [m s-1]"),
}  # fmt: skip


def _slot(name: str) -> Slot:
    return next(s for s in SLOTS if s.name == name)


def kind_name(slot: str, part: object | None) -> str:
    """The command-line name of ``part``'s kind ("viscous", "harmonic-force"); for
    ``None`` the paper's kind of the slot ("none", "rigid", "coulomb")."""
    spec = _slot(slot)
    if part is None:
        return spec.paper
    wanted = type(part).__name__
    return next(name for name, cls in spec.kinds.items() if cls == wanted)


def add_part_options(parser: argparse.ArgumentParser) -> None:
    """The selector and field flags of every slot (absent: None, so a file value stands)."""
    group = parser.add_argument_group("model parts (SI; default: the paper's model)")
    for slot in SLOTS:
        group.add_argument(
            slot.flag,
            dest=slot.name,
            metavar="{" + ",".join(slot.kinds) + "}",
            help=_HELP[(slot.name, None)][1],
        )
        for name in slot.fields:
            metavar, text = _HELP[(slot.name, name)]
            # real, not finite(): the part names the field and the rule broken
            group.add_argument(
                slot.field_flag(name), dest=slot.dest(name), type=real, metavar=metavar,
                help=text,
            )  # fmt: skip


@dataclass
class PartChoice:
    """The kind and field values of one slot, with where each came from."""

    slot: Slot
    kind: str = ""  # "" until gathered: the slot's paper kind
    kind_origin: str | None = None  # None: not given (the paper's choice, None)
    values: dict[str, float] = field(default_factory=dict)
    origin: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.kind = self.kind or self.slot.paper

    @property
    def given(self) -> bool:
        """True when the kind was chosen (flag, file, or the command itself)."""
        return self.kind_origin is not None

    def origins(self) -> dict[str, str]:
        """Where each given field came from, by dotted name ("damping.ratio")."""
        return {f"{self.slot.name}.{k}": v for k, v in self.origin.items()}


def _part_flags_given(args: argparse.Namespace) -> list[str]:
    given = []
    for slot in SLOTS:
        for dest, flag in [(slot.name, slot.flag)] + [
            (slot.dest(n), slot.field_flag(n)) for n in slot.fields
        ]:
            if getattr(args, dest, None) is not None:
                given.append(flag)
    return given


def refuse_parts(args: argparse.Namespace, data: Mapping[str, Any] | None, source: str,
                 command: str, reason: str) -> None:  # fmt: skip
    """For a command without parts: refuse a part table in the config file (it would be
    ignored without a word)."""
    for slot in SLOTS:
        if data is not None and slot.name in data:
            raise CliError(f"[{slot.name}] in {source}: {command} {reason}; remove it")
    flags = _part_flags_given(args)
    if flags:  # pragma: no cover - such commands have no part flags
        raise CliError(f"{flags[0]}: {command} {reason}")


def gather_parts(
    args: argparse.Namespace, tables: Mapping[str, Mapping[str, Any]], source: str | None
) -> dict[str, PartChoice]:
    """Each slot's kind and fields from the config ``tables`` (from
    :func:`microslip.io.config.parts_from_config`), then the flags (flags win)."""
    choices: dict[str, PartChoice] = {}
    for slot in SLOTS:
        choice = PartChoice(slot)
        table = tables.get(slot.name, {})
        if slot.selector in table:
            where = f"{slot.selector} in [{slot.name}] of {source}"
            choice.kind, choice.kind_origin = _kind(slot, table[slot.selector], where), where
        for name in slot.fields:
            if name in table:
                choice.values[name] = table[name]
                choice.origin[name] = f"{name} in [{slot.name}] of {source}"
        flag_kind = getattr(args, slot.name, None)
        if flag_kind is not None:
            kind = _kind(slot, flag_kind, slot.flag)
            if kind != choice.kind:  # another part than the file's: none of its fields
                choice.values.clear()
                choice.origin.clear()
            choice.kind, choice.kind_origin = kind, slot.flag
        for name in slot.fields:
            value = getattr(args, slot.dest(name), None)
            if value is not None:
                choice.values[name] = value
                choice.origin[name] = slot.field_flag(name)
        _check_fields(choice)
        choices[slot.name] = choice
    return choices


def _kind(slot: Slot, text: Any, where: str) -> str:
    if text not in slot.kinds:
        raise CliError(
            f"{where}: unknown {slot.name} {slot.selector} {text!r}; known: {', '.join(slot.kinds)}"
        )
    return str(text)


def _check_fields(choice: PartChoice) -> None:
    """Refuse a field without its part, or one the chosen kind does not have."""
    slot = choice.slot
    cls = _part_class(slot, choice.kind)
    for name, where in choice.origin.items():
        if not choice.given:
            kinds = ",".join(slot.kinds_with(name))
            raise CliError(
                f"{where} is a field of the {slot.name} part, which is not given: add "
                f"{slot.flag} {{{kinds}}} (or {slot.selector} in [{slot.name}])"
            )
        if cls is None:
            raise CliError(
                f"{where} has no effect with {slot.name} none ({choice.kind_origin}); remove it"
            )
        if name not in cls.field_names():
            has = ", ".join(cls.field_names()) or "none"
            raise CliError(
                f"{where} has no effect with {slot.name} {choice.kind} ({choice.kind_origin}); "
                f"its fields: {has}"
            )


def build_model(
    params: Parameters,
    parts: Mapping[str, PartChoice],
    provided: Mapping[str, tuple[float, str]] | None = None,
) -> Model:
    """The :class:`Model` of ``params`` and the chosen parts.

    ``provided`` maps dotted field names to (value, what sets it) for fields the command
    sets itself (a swept axis, the range of ``microslip response``): such a field needs no
    flag, and giving one as well is refused (both would set it).
    """
    provided = dict(provided or {})
    built: dict[str, Any] = {}
    origins: dict[str, str] = {}
    for slot_name, choice in parts.items():
        slot = choice.slot
        cls = _part_class(slot, choice.kind)
        origins.update(choice.origins())
        values = dict(choice.values)
        for dotted, (value, what) in provided.items():
            prefix, _, name = dotted.partition(".")
            if prefix != slot_name:
                continue
            if cls is None or not choice.given:
                raise CliError(
                    f"{what} sets {dotted}, but the model has no {slot_name} part: "
                    f"give one with {slot.flag}"
                )
            if name not in cls.field_names():
                raise CliError(f"{what}: {slot_name} {choice.kind} has no field {name!r}")
            if name in choice.origin:
                raise CliError(
                    f"{choice.origin[name]} cannot be combined with {what}: both set {dotted}"
                )
            values[name] = value
            origins[dotted] = what
        if cls is None or not choice.given:  # the paper's choice: None
            built[slot_name] = None
            continue
        for name in cls.field_names():
            if name not in values:
                unit = cls.field_unit(name)
                raise CliError(
                    f"{slot_name} {choice.kind} ({choice.kind_origin}) needs "
                    f"{slot.field_flag(name)} [{unit}] (or {name} in [{slot_name}] of --config)"
                )
        try:
            built[slot_name] = cls(**values)
        except ValueError as error:
            raise _located(error, origins) from None
    from microslip.model.composition import Model

    try:
        return Model(params, **built)
    except ValueError as error:
        raise _located(error, origins) from None


def _located(error: ValueError, origins: Mapping[str, str]) -> CliError:
    """``error`` prefixed with where the offending value came from."""
    text = str(error)
    for dotted, where in origins.items():
        if text.startswith(dotted) or f" {dotted}" in text:
            return CliError(f"{where}: {text}")
    return CliError(text)


def require_paper_tangential(
    model: Model,
    parts: Mapping[str, PartChoice],
    command: str,
    instead: str,
    allowed: Mapping[str, tuple] | None = None,
) -> None:
    """Refuse a model whose tangential side is not the paper's (rigid contact, Coulomb
    friction, the command's own constant force), but for the parts ``allowed`` by slot,
    for the commands that compute with the paper's constant force; one line naming where
    the part came from (:func:`microslip.model.capabilities.require`)."""
    from microslip.model.capabilities import TANGENTIAL_SLOTS, UnsupportedModelError, require

    allowed = dict(allowed or {})
    try:
        require(model, f"microslip {command}", allowed=allowed, instead=instead)
    except UnsupportedModelError as error:
        # The flag of the first refused part (one of the allowed ones may come first).
        refused = (
            s for s in TANGENTIAL_SLOTS
            if not model.paper_choice(s) and type(getattr(model, s)) not in allowed.get(s, ())
        )  # fmt: skip
        where = next((parts[s].kind_origin for s in refused), None)
        raise CliError(f"{where}: {error}" if where else str(error)) from None
