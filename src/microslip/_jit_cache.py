"""On-disk cache of microslip's compiled kernels that cannot serve stale machine code.

Numba's ``cache=True`` keys a compiled function by the contents of its own source file.
microslip's kernels inline jitted functions of other modules (the integrators inline the
contact law of ``model/contact.py``), so after an edit of the contact law numba's own
cache would keep serving the old machine code without a word.

This module registers a cache locator, ahead of numba's own, that serves only functions
defined inside this package. It stores them under ``<root>/jit-<key>/<subpackage>/``,
where ``key`` hashes the Python, NumPy, numba and llvmlite versions and the source of
every module compiled code can reach: each module of the package that imports numba,
and every module of the package those import, transitively. An edit of any of
them changes the key and so selects a fresh, empty directory; directories of other keys
are pruned, keeping the most recently used few (several checkouts may share the root).

The root is ``$MICROSLIP_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/microslip``, else
``~/.cache/microslip``. If it is not writable the kernels are cached in a private
temporary directory removed at exit: every process compiles afresh, still correct.

It must be imported before any jitted function is decorated: every module that imports
numba imports this one at its top (a test checks it), so the locator is in place whichever
module is loaded first; Dask workers import microslip too and get the same cache.
Setting ``NUMBA_CACHE_LOCATOR_CLASSES`` replaces every locator, this one included, and
so brings back numba's per-file keys.
"""

from __future__ import annotations

import ast
import atexit
import functools
import hashlib
import os
import re
import shutil
import sys
import tempfile
import time
import warnings
from pathlib import Path

import llvmlite
import numba
import numpy as np
from numba.core import caching

__all__ = ["PACKAGE_DIR", "cache_dir", "cache_root", "source_key", "source_modules"]

PACKAGE_DIR = Path(__file__).resolve().parent
PACKAGE = PACKAGE_DIR.name
PREFIX = "jit-"  # names of the key directories: `make clean` and pruning touch only these
KEEP_OTHERS = 2  # key directories kept besides the current one (other checkouts, branches)
# A key directory younger than this is never pruned: a process that started from another
# source state may still be writing to it (numba would fail on a directory removed under it).
MIN_AGE_S = 900.0
_USED_STAMP = ".last-used"  # its mtime orders key directories for pruning


def cache_root() -> Path:
    """The directory that holds one ``jit-<key>`` directory per source state."""
    explicit = os.environ.get("MICROSLIP_CACHE_DIR")
    if explicit:
        return Path(explicit).expanduser()
    xdg = os.environ.get("XDG_CACHE_HOME")
    base = Path(xdg).expanduser() if xdg else Path.home() / ".cache"
    return base / "microslip"


def _module_index(files: list[Path], package_dir: Path) -> dict[str, Path]:
    """Dotted module name -> source file of every module of the package (``a/b.py`` is
    ``microslip.a.b``, ``a/__init__.py`` is ``microslip.a``; a module file wins over a
    package of the same name, as the import system's order of candidates here did). One
    dictionary instead of a path construction and a stat per imported name: those were
    ~30 ms of every start."""
    index: dict[str, Path] = {}
    for path in files:
        parts = path.relative_to(package_dir).with_suffix("").parts
        if parts[-1] == "__init__":
            index.setdefault(".".join((PACKAGE, *parts[:-1])), path)
        else:
            index[".".join((PACKAGE, *parts))] = path
    return index


# Import statements, matched on the text so that only they are parsed (a whole-module parse
# costs tens of ms at every start); anything the match cuts short parses the module. A
# parenthesised list may hold comments, whose own parentheses do not close it (a
# re-export's "(re-exported)": two modules were parsed whole for one, ~8 ms a start).
_IMPORT = re.compile(
    r"^[ \t]*(from[ \t]+[.\w]+[ \t]+import[ \t]+(?:\((?:[^)#]|#[^\n]*)*\)|[^\n]*)"
    r"|import[ \t]+[^\n]*)",
    re.M,
)


_NUMBA_IMPORT = re.compile(r"^[ \t]*(?:from|import)[ \t]+numba\b", re.M)


def _import_nodes(text: str) -> list[ast.AST]:
    """The import statements of a module's source ``text`` (more nodes where they cannot
    be told apart: never fewer). The matched statements are parsed together, one parse a
    module rather than one a statement."""
    try:
        return ast.parse("\n".join(m.group(1) for m in _IMPORT.finditer(text))).body
    except SyntaxError:  # a continued line, or prose in a docstring
        return list(ast.walk(ast.parse(text)))


def _imported_files(path: Path, package_dir: Path, index: dict[str, Path]) -> set[Path]:
    """Package modules that ``path`` imports (``import a.b``, ``from a import b``, relative)."""
    rel = path.relative_to(package_dir).with_suffix("")
    parts = [PACKAGE, *rel.parts]
    package = parts if parts[-1] == "__init__" else parts[:-1]
    if package[-1] == "__init__":
        package = package[:-1]
    found: set[Path] = set()
    for node in _import_nodes(path.read_text(encoding="utf-8")):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                anchor = package[: len(package) - node.level + 1]
                module = ".".join([*anchor, *([node.module] if node.module else [])])
            else:
                module = node.module or ""
            # `from pkg import name` reaches the submodule pkg.name if there is one, else
            # the attribute `name` of pkg (its __init__.py).
            names = []
            for alias in node.names:
                sub = f"{module}.{alias.name}"
                names.append(sub if sub in index else module)
        else:
            continue
        for name in names:
            target = index.get(name)
            if target is not None:
                found.add(target)
    return found


def source_modules(package_dir: Path = PACKAGE_DIR) -> list[Path]:
    """Files whose source compiled code can reach, sorted.

    Seeds are the modules that import numba; the set is closed under the
    package-internal imports. A module that cannot be parsed makes every ``.py`` file of
    the package count, so a syntax error never hides a dependency.
    """
    files = sorted(package_dir.rglob("*.py"))
    index = _module_index(files, package_dir)
    try:
        todo = [f for f in files if _NUMBA_IMPORT.search(f.read_text(encoding="utf-8"))]
        reached: set[Path] = set()
        while todo:
            path = todo.pop()
            if path not in reached:
                reached.add(path)
                todo.extend(_imported_files(path, package_dir, index) - reached)
    except (SyntaxError, ValueError, OSError):
        return files
    return sorted(reached)


def source_key(package_dir: Path = PACKAGE_DIR) -> str:
    """Hex key of the reachable sources and of the versions that shape the machine code."""
    digest = hashlib.sha256()
    versions = (sys.version, np.__version__, numba.__version__, llvmlite.__version__)
    digest.update(repr(versions).encode())
    for path in source_modules(package_dir):
        digest.update(path.relative_to(package_dir).as_posix().encode() + b"\0")
        digest.update(hashlib.sha256(path.read_bytes()).digest())
    return digest.hexdigest()[:24]


def _writable(directory: Path) -> bool:
    try:
        directory.mkdir(parents=True, exist_ok=True)
        tempfile.TemporaryFile(dir=directory).close()
    except OSError:
        return False
    return True


def _prune(root: Path, current: Path) -> None:
    """Remove the key directories other than ``current`` and the most recently used few."""

    def last_used(path: Path) -> float:
        try:
            return (path / _USED_STAMP).stat().st_mtime
        except OSError:
            return 0.0

    others = [p for p in root.glob(PREFIX + "*") if p.is_dir() and p != current]
    others.sort(key=last_used, reverse=True)
    now = time.time()
    for old in others[KEEP_OTHERS:]:
        if now - last_used(old) > MIN_AGE_S:
            shutil.rmtree(old, ignore_errors=True)


@functools.cache
def _private_dir(reason: str) -> Path:
    """A temporary directory of this process, removed at exit: caching without persistence."""
    private = Path(tempfile.mkdtemp(prefix="microslip-jit-"))
    atexit.register(shutil.rmtree, private, ignore_errors=True)
    warnings.warn(
        f"microslip: {reason}; compiled kernels are not kept between runs "
        "(set MICROSLIP_CACHE_DIR to a writable directory)",
        RuntimeWarning,
        stacklevel=1,
    )
    return private


@functools.cache
def cache_dir() -> Path:
    """This process's cache directory for the current sources (created and pruned once)."""
    try:
        root = cache_root()
    except (RuntimeError, KeyError):  # Path.home() without HOME or a passwd entry
        return _private_dir("no home directory for the cache")
    current = root / (PREFIX + source_key())
    if not _writable(current):
        return _private_dir(f"cache directory {str(root)!r} is not writable")
    (current / _USED_STAMP).touch()
    _prune(root, current)
    return current


class SourceTreeLocator(caching._CacheLocator):
    """Numba cache locator for the functions of this package, keyed on all reachable source.

    Functions defined elsewhere are left to numba's own locators (``from_function``
    returns None for them), so other numba users in the same process are unaffected.
    """

    def __init__(self, py_func, py_file: str) -> None:
        self._py_file = py_file
        self._lineno = py_func.__code__.co_firstlineno
        self._cache_path = str(cache_dir() / _package_subdir(py_file))

    def get_cache_path(self) -> str:
        return self._cache_path

    def get_source_stamp(self) -> str:
        # The directory is already keyed on the sources; the stamp adds the function's own
        # file, for a module that compiles code without importing numba itself.
        return self._cache_path + ":" + _file_digest(self._py_file)

    def get_disambiguator(self) -> str:
        return str(self._lineno)

    @classmethod
    def from_function(cls, py_func, py_file: str) -> SourceTreeLocator | None:
        if _package_subdir(py_file) is None:
            return None
        locator = cls(py_func, py_file)
        if locator._cache_path in _usable_paths:
            return locator
        try:
            locator.ensure_cache_path()
        except OSError:
            # Never give the function back to numba's locators: they would serve stale code.
            subdir = Path(locator._cache_path).relative_to(cache_dir())
            locator._cache_path = str(_private_dir("cache directory not writable") / subdir)
            locator.ensure_cache_path()
        _usable_paths.add(locator._cache_path)
        return locator


# Per process, once per source file or cache directory rather than once per compiled
# function (~180 at import): resolving paths, hashing a file and probing a directory with
# a temporary file were ~0.07 s of every start.
_usable_paths: set[str] = set()  # cache directories created and found writable


@functools.cache
def _package_subdir(py_file: str) -> Path | None:
    """The directory of ``py_file`` relative to the package, None outside it."""
    try:
        return Path(py_file).resolve().parent.relative_to(PACKAGE_DIR)
    except (OSError, ValueError):
        return None


@functools.cache
def _file_digest(py_file: str) -> str:
    """SHA-256 of the file's bytes (read once per process)."""
    return hashlib.sha256(Path(py_file).read_bytes()).hexdigest()


def _register() -> None:
    impl = getattr(caching, "CacheImpl", None) or caching._CacheImpl
    if SourceTreeLocator not in impl._locator_classes:
        impl._locator_classes.insert(0, SourceTreeLocator)


_register()
