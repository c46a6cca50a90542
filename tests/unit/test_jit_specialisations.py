"""The switching core is compiled once per argument type, never once per constant.

numba types a module-level int (and a literal True/False) passed to a jitted function as
a literal, and compiles the callee once per value. Each compile of a switching function
takes a large share of the cold start (docs/design.md, "The compiled form"): calls such
as ``switching_rate(SEPARATION, ...)`` once tripled the compile of the shared-normal time
kernel. Two checks: no call site in the package passes such a constant to the switching
core (static, always effective), and no compiled signature of the core holds a literal
type (effective when this process compiled the kernels rather than loading callers from
the disk cache, as on a fresh machine).
"""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import numpy as np
from numba.core import types

import microslip as ms
from microslip.integrators import (
    bracket,
    kernel,
    lane_parking,
    methods,
    mindlin_rows,
    mindlin_spans,
    normal_step,
    rigid_pass,
    spring_lanes,
    switching,
)
from microslip.integrators.batched import simulate_batch
from microslip.model import (
    switches,
    switching_functions,
    system,
)
from microslip.model.coefficients import pack

PACKAGE = Path(ms.__file__).resolve().parent

DISPATCHERS = {
    "switching_value": switching_functions.switching_value,
    "switching_rate": switching_functions.switching_rate,
    "apply_switch": switches.apply_switch,
    "_screen": switching._screen,
    "_resolve": switching._resolve,
    "locate": switching.locate,
    "bracket_step": bracket.bracket_step,
    "contact_switch": normal_step.contact_switch,
    "normal_step._locate": normal_step._locate,
    "contact_event": switches.contact_event,
    "may_switch": switching.may_switch,
    "first_switch": switching.first_switch,
    "piece_end": kernel.piece_end,
    "advance": methods.advance,
    "normal_force_call": system.normal_force_call,
    "normal_force_rate_call": system.normal_force_rate_call,
    # Not the switching core, but as large: the rigid lanes over a range of tape rows,
    # the spring lanes by spans and row by row, the Mindlin lanes by spans and row by row,
    # the moves of parked lanes, the output.
    "lanes_over_rows": rigid_pass.lanes_over_rows,
    "rows_one_by_one": rigid_pass.rows_one_by_one,
    "spring_lanes._spans": spring_lanes._spans,
    "spring_lanes._rows": spring_lanes._rows,
    "run_rows": mindlin_rows.run_rows,
    "run_spans": mindlin_spans.run_spans,
    "_copy_lane": lane_parking._copy_lane,
    "_write": kernel._write,
}


def _module_name(path: Path) -> str:
    relative = path.relative_to(PACKAGE.parent).with_suffix("")
    return ".".join(relative.parts)


def _constant_arguments(source: str, module_globals: dict):
    """(line, callee, argument) of each call in ``source`` to a core function with an
    int or bool literal, or a module-level Python int, as an argument."""
    tree = ast.parse(source)
    local_names = {name: name for name in DISPATCHERS}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            for alias in node.names:
                if alias.name in DISPATCHERS:
                    local_names[alias.asname or alias.name] = alias.name
    for node in ast.walk(tree):
        if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)):
            continue
        callee = local_names.get(node.func.id)
        if callee is None:
            continue
        for argument in node.args:
            if isinstance(argument, ast.Constant) and isinstance(argument.value, int):
                yield node.lineno, callee, ast.unparse(argument)
            if isinstance(argument, ast.Name):
                if type(module_globals.get(argument.id)) in (int, bool):
                    yield node.lineno, callee, argument.id


def test_no_call_site_passes_a_literal_to_the_switching_core():
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        source = path.read_text(encoding="utf-8")
        if "njit" not in source:
            continue
        module = vars(importlib.import_module(_module_name(path)))
        for line, callee, argument in _constant_arguments(source, module):
            found.append(f"{path.relative_to(PACKAGE)}:{line}: {callee}(... {argument} ...)")
    assert found == [], "pass np.int64 / np.bool_ constants instead:\n" + "\n".join(found)


def test_the_static_check_finds_each_kind_of_constant():
    source = """
from microslip.integrators.switching import _screen as screen
def f(t, s, c):
    switching_rate(SEPARATION, t, s, 1.0, c)
    screen(_WRAPPED, t, s, 1.0, c)
    locate(which, True, 0, s)
    other(SEPARATION)
"""
    module = {"SEPARATION": 1, "_WRAPPED": np.int64(1)}
    found = sorted(_constant_arguments(source, module))
    assert found == [(4, "switching_rate", "SEPARATION"), (6, "locate", "0"), (6, "locate", "True")]


def _literal_signatures(dispatcher):
    return [
        signature
        for signature in dispatcher.signatures
        if any(isinstance(argument, types.Literal) for argument in signature)
    ]


def test_no_literal_specialisations_of_the_switching_core():
    params = ms.Parameters()
    forced = ms.Model(params, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(2.0, 1400.0))
    # Every path that reaches the switching core: the time kernel's normal tape (free
    # and forced), the event and rk4 integrations, the coupled batched kernel.
    ms.velocity_map(params, forces=[0.2, 0.6], amplitudes=[1e-7], method="time", duration=1e-3)
    ms.sweep(forced, {"excitation.amplitude": [1.0]}, force=[0.3], method="time", duration=1e-3)
    ms.simulate(params, force=0.5, amplitude=1e-7, duration=1e-3)
    ms.simulate(forced, force=0.5, duration=1e-3, method="rk4")
    states0 = np.array([[params.static_deflection - 1e-7, 0.0, 0.0, 0.0]])
    simulate_batch(pack(params, 0.5)[None, :], states0, 1e-3, params.natural_period / 200)
    _run_the_lane_kernels(params)
    for name, dispatcher in DISPATCHERS.items():
        assert _literal_signatures(dispatcher) == [], (
            f"{name} is specialised on a constant: {_literal_signatures(dispatcher)}"
        )


def _run_the_lane_kernels(params):
    # The steady map, the paper's time map on a repeated tape (parking), the spring and
    # Mindlin lanes on a stepped and on a repeated tape.
    ms.velocity_map(params, forces=[0.2, 0.6], amplitudes=[0.0, 1e-7])
    ms.velocity_map(params, forces=[0.2, 0.6], amplitudes=[1e-7], method="time", duration=4e-3)
    for tangential in (ms.TangentialSpring(params.contact_stiffness), ms.MindlinSpring(0.8235)):
        model = ms.Model(params, tangential=tangential)
        # Two forces: on a span one lane sticks throughout and the other goes row by row.
        ms.sweep(model, None, force=[0.3, 0.95], amplitude=[0.0, 1e-7], method="time",
                 duration=4e-3)  # fmt: skip
