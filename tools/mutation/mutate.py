"""Mutation testing of microslip's numerics that works with numba (``make mutate``).

mutmut 3 replaces functions by trampolines that numba cannot compile, so this script
rewrites the source file on disk instead, one mutant at a time, in a scratch copy of
the repository (the working tree is never touched):

1. copy ``src/``, ``tests/`` and ``pyproject.toml`` to the scratch directory (no
   ``__pycache__``, so no compiled kernel is reused) and check that ``import microslip``
   there resolves to the copy (``PYTHONPATH`` goes before the editable install);
2. run each module's test selection (``targets.toml``) once unmutated: it must pass;
3. for every mutant of every target module: write the mutated file, run the selection
   with ``pytest -x`` under a wall-clock timeout, restore the file. A failing test
   kills the mutant; a timeout counts separately.

Two modes:

* ``--jit`` (default): numba compiles every mutant afresh (``NUMBA_CACHE_DIR`` and
  ``MICROSLIP_CACHE_DIR`` point to an empty directory per mutant): faithful, ~1 min a
  mutant on a 2-core machine.
* ``--no-jit``: ``NUMBA_DISABLE_JIT=1``, the kernels run as Python: ~5 s a mutant. Use
  it to screen, then re-run its survivors with ``--jit --only FILE:LINE ...``.

Mutations (Python AST, written back by replacing the node's source segment):
arithmetic operator swaps (+ −, * /, ** → *), unary minus removed, comparison
boundaries and negations (< <= > >= == !=), and/or swapped, ``not`` removed,
min/max swapped, True/False swapped, numeric constants c → c + 1, augmented
assignments (+= −=). Docstrings, annotations and decorator arguments are not mutated.
"""

from __future__ import annotations

import argparse
import ast
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import asdict, dataclass
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve().parent

_BINOP_SWAP = {
    ast.Add: ast.Sub,
    ast.Sub: ast.Add,
    ast.Mult: ast.Div,
    ast.Div: ast.Mult,
    ast.Pow: ast.Mult,
    ast.FloorDiv: ast.Div,
}
_CMP_SWAP = {
    ast.Lt: (ast.LtE, ast.GtE),
    ast.LtE: (ast.Lt, ast.Gt),
    ast.Gt: (ast.GtE, ast.LtE),
    ast.GtE: (ast.Gt, ast.Lt),
    ast.Eq: (ast.NotEq,),
    ast.NotEq: (ast.Eq,),
}


@dataclass(frozen=True)
class Mutant:
    """One mutation: replace source lines [line, end_line] columns [col, end_col)."""

    path: str  # relative to the repository root
    line: int
    col: int
    end_line: int
    end_col: int
    original: str
    replacement: str

    @property
    def where(self) -> str:
        return f"{self.path}:{self.line}"

    def describe(self) -> str:
        return f"{self.where}: {self.original!s} -> {self.replacement!s}"


def _skip_ranges(tree: ast.AST) -> list[tuple[int, int]]:
    """Line ranges that are never mutated: docstrings, decorators, annotations, __all__."""
    ranges = []
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr):
            value = body[0].value
            if isinstance(value, ast.Constant) and isinstance(value.value, str):
                ranges.append((body[0].lineno, body[0].end_lineno))
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            for deco in node.decorator_list:
                ranges.append((deco.lineno, deco.end_lineno))
        if isinstance(node, ast.FunctionDef) and node.returns is not None:
            ranges.append((node.returns.lineno, node.returns.end_lineno))
        if isinstance(node, ast.arg) and node.annotation is not None:
            ranges.append((node.annotation.lineno, node.annotation.end_lineno))
        if isinstance(node, ast.AnnAssign):
            ranges.append((node.annotation.lineno, node.annotation.end_lineno))
        if isinstance(node, ast.Assign) and any(
            isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets
        ):
            ranges.append((node.lineno, node.end_lineno))
    return ranges


def _variants(node: ast.AST) -> list[ast.AST]:
    """Mutated copies of ``node`` (each differs from it in one place)."""
    out: list[ast.AST] = []
    if isinstance(node, ast.BinOp) and type(node.op) in _BINOP_SWAP:
        out.append(ast.BinOp(node.left, _BINOP_SWAP[type(node.op)](), node.right))
    elif isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        out.append(node.operand)
    elif isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Not):
        out.append(node.operand)
    elif isinstance(node, ast.Compare) and len(node.ops) == 1 and type(node.ops[0]) in _CMP_SWAP:
        for op in _CMP_SWAP[type(node.ops[0])]:
            out.append(ast.Compare(node.left, [op()], node.comparators))
    elif isinstance(node, ast.BoolOp):
        other = ast.Or() if isinstance(node.op, ast.And) else ast.And()
        out.append(ast.BoolOp(other, node.values))
    elif isinstance(node, ast.Constant):
        if isinstance(node.value, bool):
            out.append(ast.Constant(not node.value))
        elif isinstance(node.value, (int, float)):
            out.append(ast.Constant(node.value + 1))
    elif (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Name)
        and node.func.id in ("min", "max")
    ):
        name = "max" if node.func.id == "min" else "min"
        out.append(ast.Call(ast.Name(name, ast.Load()), node.args, node.keywords))
    elif isinstance(node, ast.AugAssign) and type(node.op) in (ast.Add, ast.Sub):
        op = ast.Sub() if isinstance(node.op, ast.Add) else ast.Add()
        out.append(ast.AugAssign(node.target, op, node.value))
    return out


def generate(path: Path) -> list[Mutant]:
    """All mutants of one source file, in source order."""
    source = path.read_text()
    tree = ast.parse(source)
    skip = _skip_ranges(tree)
    rel = str(path.relative_to(ROOT))
    mutants = []
    in_fstring = {
        id(inner) for node in ast.walk(tree) if isinstance(node, ast.JoinedStr)
        for inner in ast.walk(node)
    }  # fmt: skip
    for node in ast.walk(tree):
        if id(node) in in_fstring or not hasattr(node, "lineno") or node.end_lineno is None:
            continue
        if any(lo <= node.lineno and node.end_lineno <= hi for lo, hi in skip):
            continue
        original = ast.get_source_segment(source, node)
        if original is None:
            continue
        for variant in _variants(node):
            text = ast.unparse(variant)
            # A negative constant's "- 1" is a USub of a Constant: c + 1 on the operand
            # is enough; parenthesise every expression so precedence cannot change.
            if not isinstance(node, ast.stmt):
                text = f"({text})"
            if text.strip("()") == original.strip("()"):
                continue
            mutants.append(
                Mutant(
                    rel,
                    node.lineno,
                    node.col_offset,
                    node.end_lineno,
                    node.end_col_offset,
                    original,
                    text,
                )
            )
    mutants.sort(key=lambda m: (m.line, m.col, m.replacement))
    return mutants


def apply(source: str, m: Mutant) -> str:
    lines = source.splitlines(keepends=True)
    offsets = [0]
    for line in lines:
        offsets.append(offsets[-1] + len(line.encode()))
    data = source.encode()
    start = offsets[m.line - 1] + m.col
    end = offsets[m.end_line - 1] + m.end_col
    return (data[:start] + m.replacement.encode() + data[end:]).decode()


def make_scratch(scratch: Path) -> None:
    ignore = shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc", "*.egg-info")
    for name in ("src", "tests"):
        shutil.copytree(ROOT / name, scratch / name, ignore=ignore, dirs_exist_ok=True)
    shutil.copy2(ROOT / "pyproject.toml", scratch / "pyproject.toml")


def environment(scratch: Path, jit: bool, cache: Path) -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(scratch / "src")
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    env["NUMBA_CACHE_DIR"] = str(cache)
    env["MICROSLIP_CACHE_DIR"] = str(cache)
    env["MPLBACKEND"] = "Agg"
    if jit:
        env.pop("NUMBA_DISABLE_JIT", None)
    else:
        env["NUMBA_DISABLE_JIT"] = "1"
    return env


def run_tests(scratch: Path, tests: list[str], env: dict, timeout: float) -> tuple[str, float]:
    """'passed', 'failed' or 'timeout', and the wall time [s]."""
    cmd = [sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider",
           "-p", "no:randomly", "--timeout", str(int(timeout)), *tests]  # fmt: skip
    start = time.monotonic()
    try:
        proc = subprocess.run(
            cmd, cwd=scratch, env=env, timeout=timeout, capture_output=True, text=True
        )
    except subprocess.TimeoutExpired:
        return "timeout", time.monotonic() - start
    elapsed = time.monotonic() - start
    if proc.returncode == 0:
        return "passed", elapsed
    if proc.returncode == 5:  # no tests collected: the selection is wrong
        raise SystemExit(f"no tests collected for {tests}:\n{proc.stdout[-2000:]}")
    if "+ Timeout +" in proc.stdout:  # pytest-timeout stopped a test: a hang, not a failure
        return "timeout", elapsed
    return "failed", elapsed


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0], allow_abbrev=False)
    parser.add_argument("--config", type=Path, default=HERE / "targets.toml")
    parser.add_argument("--module", action="append", default=[],
                        help="mutate only these modules (paths as in the config)")  # fmt: skip
    parser.add_argument("--only", action="append", default=[],
                        help="only mutants at FILE:LINE (as printed)")  # fmt: skip
    parser.add_argument("--jit", action=argparse.BooleanOptionalAction, default=True)
    parser.add_argument(
        "--timeout", type=float, default=None, help="per-mutant limit [s] (3x baseline + 30)"
    )
    parser.add_argument("--scratch", type=Path, default=None)
    parser.add_argument("--report", type=Path, default=None, help="write results as JSON")
    parser.add_argument("--list", action="store_true", help="list the mutants and stop")
    args = parser.parse_args(argv)

    config = tomllib.loads(args.config.read_text())
    targets: dict[str, list[str]] = {k: v["tests"] for k, v in config["targets"].items()}
    modules = args.module or list(targets)
    for module in modules:
        if module not in targets:
            parser.error(f"--module {module!r} is not in {args.config}")
    plan = {module: generate(ROOT / module) for module in modules}
    if args.only:
        plan = {mod: [m for m in ms if m.where in args.only] for mod, ms in plan.items()}
    total = sum(len(v) for v in plan.values())
    print(f"{total} mutants in {len(plan)} modules (jit={'on' if args.jit else 'off'})")
    if args.list:
        for mutants in plan.values():
            for m in mutants:
                print("  " + m.describe())
        return 0

    scratch = args.scratch or Path(tempfile.mkdtemp(prefix="microslip-mutation-"))
    scratch.mkdir(parents=True, exist_ok=True)
    make_scratch(scratch)
    cache_root = scratch / ".numba-cache"
    probe = subprocess.run(
        [sys.executable, "-c", "import microslip; print(microslip.__file__)"],
        env=environment(scratch, args.jit, cache_root / "probe"),
        capture_output=True, text=True, cwd=scratch, check=True,
    )  # fmt: skip
    if not probe.stdout.strip().startswith(str(scratch)):
        raise SystemExit(f"microslip imports from {probe.stdout.strip()}, not the scratch copy")
    print(f"scratch copy: {scratch}")

    results = []
    counts = {"killed": 0, "survived": 0, "timeout": 0}
    for module, mutants in plan.items():
        if not mutants:
            continue
        tests = targets[module]
        cache = cache_root / "baseline"
        shutil.rmtree(cache, ignore_errors=True)
        status, base = run_tests(scratch, tests, environment(scratch, args.jit, cache), 1800)
        if status != "passed":
            raise SystemExit(f"the unmutated tests for {module} do not pass ({status})")
        limit = args.timeout or 3.0 * base + 30.0
        print(f"{module}: {len(mutants)} mutants, baseline {base:.1f} s, timeout {limit:.0f} s")
        target = scratch / module
        original = target.read_text()
        try:
            for k, m in enumerate(mutants, 1):
                target.write_text(apply(original, m))
                cache = cache_root / "mutant"
                shutil.rmtree(cache, ignore_errors=True)
                status, elapsed = run_tests(
                    scratch, tests, environment(scratch, args.jit, cache), limit
                )
                outcome = {"passed": "survived", "failed": "killed"}.get(status, status)
                counts[outcome] += 1
                results.append({**asdict(m), "outcome": outcome, "seconds": round(elapsed, 1)})
                print(f"  [{k}/{len(mutants)}] {outcome:8s} {elapsed:5.1f}s {m.describe()}",
                      flush=True)  # fmt: skip
        finally:
            target.write_text(original)
    print()
    print(f"killed {counts['killed']}, survived {counts['survived']}, timeout {counts['timeout']}")
    survivors = [r for r in results if r["outcome"] == "survived"]
    if survivors:
        print("survivors:")
        for r in survivors:
            print(f"  {r['path']}:{r['line']}: {r['original']} -> {r['replacement']}")
    if args.report:
        args.report.write_text(json.dumps({"counts": counts, "results": results}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
