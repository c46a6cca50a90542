"""The kernel cache's key finds a module's imports without parsing the whole module.

``_jit_cache._import_nodes`` matches the import statements on the text and parses only
them; where the match cannot be parsed it falls back to a parse of the whole module
(correct, but tens of ms a start, at every start). Checked against a whole-module parse
of every module of the package: no import is lost, and none needs the fallback.
"""

from __future__ import annotations

import ast

import pytest

from microslip import _jit_cache

MODULES = sorted(_jit_cache.PACKAGE_DIR.rglob("*.py"))


def _imports(nodes) -> set[tuple]:
    found = set()
    for node in nodes:
        if isinstance(node, ast.Import):
            found.update(("import", alias.name) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            found.update((node.level, node.module, alias.name) for alias in node.names)
    return found


@pytest.mark.parametrize(
    "path", MODULES, ids=lambda p: p.relative_to(_jit_cache.PACKAGE_DIR).as_posix()
)
def test_matched_imports_cover_a_whole_parse_without_falling_back(path):
    text = path.read_text(encoding="utf-8")
    nodes = _jit_cache._import_nodes(text)
    # The fallback walks the whole tree (the Module node, expressions, ...).
    assert all(isinstance(n, (ast.Import, ast.ImportFrom)) for n in nodes), "fell back"
    assert _imports(ast.walk(ast.parse(text))) <= _imports(nodes)


def test_parenthesised_import_with_a_comment_holding_parentheses():
    text = (
        '"""Doc."""\n'
        "from microslip.integrators.tape_row import (  # noqa: F401  (re-exported)\n"
        "    flight_piece,  # a comment (with a ) in it)\n"
        "    span,\n"
        ")\n"
        "x = (1)\n"
    )
    nodes = _jit_cache._import_nodes(text)
    assert all(isinstance(n, ast.ImportFrom) for n in nodes)
    assert _imports(nodes) == {
        (0, "microslip.integrators.tape_row", "flight_piece"),
        (0, "microslip.integrators.tape_row", "span"),
    }


def test_prose_that_looks_like_an_import_parses_the_whole_module():
    text = '"""\nimport the table from the paper (2.3)\n"""\nfrom microslip import results\n'
    assert ("import", "the") not in _imports(_jit_cache._import_nodes(text))
    assert (0, "microslip", "results") in _imports(_jit_cache._import_nodes(text))
