"""The on-disk cache of compiled kernels never serves machine code of an older source.

The kernel under test is ``integrators.steppers.rk4_step``, the paper's RK4 step: it
inlines the contact law (2.3) from ``model/contact.py``, a module of another subpackage,
which numba's own cache (keyed by the kernel's file only) does not notice.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from microslip import _jit_cache

SOURCE = Path(_jit_cache.__file__).resolve().parent
H = 1e-7  # RK4 step [s]; short enough that y barely moves from y0

# One RK4 step from rest at the static deflection y0: there ÿ = g - |R(y0)|/m = 0 (2.4),
# so ẏ stays ~0; with the reaction scaled by 2, ÿ = -g and ẏ = -g h after the step.
PROBE = f"""
import json, microslip, numpy as np
from microslip.integrators.steppers import WORK_ROWS, rk4_step
from microslip.model.coefficients import pack
from microslip.model.samples import state_array
from microslip.model.system import N_STATE
p = microslip.Parameters()
s, out = state_array(p.static_deflection, 0.0), np.empty(N_STATE)
rk4_step(s, 0.0, {H!r}, 0.0, pack(p, 0.0), out, np.empty((WORK_ROWS, N_STATE)))
print(json.dumps({{"ydot": out[1], "g": p.g, "file": microslip.__file__,
                  "hits": sum(rk4_step.stats.cache_hits.values()),
                  "misses": sum(rk4_step.stats.cache_misses.values())}}))
"""


def _copy_package(tmp_path: Path) -> Path:
    """A private copy of the package (sources only) under ``tmp_path/src``."""
    target = tmp_path / "src" / "microslip"
    shutil.copytree(SOURCE, target, ignore=shutil.ignore_patterns("__pycache__"))
    return target


def _probe(package: Path, cache: Path) -> dict:
    env = {**os.environ, "PYTHONPATH": str(package.parent), "MICROSLIP_CACHE_DIR": str(cache)}
    done = subprocess.run(
        [sys.executable, "-c", PROBE], capture_output=True, text=True, env=env, timeout=300
    )
    assert done.returncode == 0, done.stderr
    result = json.loads(done.stdout.splitlines()[-1])
    assert Path(result["file"]).resolve().parent == package.resolve()
    result["stderr"] = done.stderr
    return result


def _cache_files(cache: Path) -> set[Path]:
    return {p for p in cache.rglob("*") if p.suffix in (".nbi", ".nbc")}


def _scale_reaction(package: Path, factor: float) -> None:
    """Edit the compiled contact law (2.3) of the copy: |R| -> factor |R|."""
    contact = package / "model" / "contact.py"
    text = contact.read_text()
    old = "        return c[AREA_CN] * delta * delta\n"
    assert text.count(old) == 1, "the m2 = 2 branch of elastic_force() changed: update this test"
    contact.write_text(
        text.replace(old, f"        return {factor!r} * c[AREA_CN] * delta * delta\n")
    )


def _key_dirs(files: set[Path], cache: Path) -> set[str]:
    return {f.relative_to(cache).parts[0] for f in files}


def test_edit_of_inlined_contact_law_is_compiled_afresh(tmp_path):
    package = _copy_package(tmp_path)
    cache = tmp_path / "cache"

    first = _probe(package, cache)
    assert first["misses"] == 1 and first["hits"] == 0
    assert abs(first["ydot"]) < 1e-6 * first["g"] * H  # at rest in equilibrium
    files_first = _cache_files(cache)
    assert files_first, "the kernel was not written to MICROSLIP_CACHE_DIR"

    _scale_reaction(package, 2.0)
    second = _probe(package, cache)
    assert second["misses"] == 1 and second["hits"] == 0
    assert second["ydot"] == pytest.approx(-second["g"] * H, rel=1e-5)
    files_second = _cache_files(cache)
    assert len(_key_dirs(files_second, cache)) == 2  # a new key directory; the old one kept

    third = _probe(package, cache)  # unchanged sources: served from the cache
    assert third["hits"] == 1 and third["misses"] == 0
    assert third["ydot"] == second["ydot"]
    assert _cache_files(cache) == files_second


def test_unwritable_cache_root_still_computes_the_current_law(tmp_path):
    package = _copy_package(tmp_path)
    blocker = tmp_path / "a-file"
    blocker.write_text("not a directory")
    _scale_reaction(package, 2.0)

    result = _probe(package, blocker / "cache")
    assert "not writable" in result["stderr"]
    assert result["ydot"] == pytest.approx(-result["g"] * H, rel=1e-5)
    # Not handed back to numba's own locators, whose in-tree cache keys by file only.
    assert not _cache_files(package)


def test_key_covers_reachable_modules_only(tmp_path):
    package = _copy_package(tmp_path)
    key = _jit_cache.source_key(package)

    # The command line cannot reach compiled code: editing it keeps the compiled kernels.
    cli = package / "cli" / "main.py"
    cli.write_text(cli.read_text() + "\n# edited\n")
    assert _jit_cache.source_key(package) == key

    # Reached only through an import of a kernel module (analysis -> validation).
    validation = package / "validation.py"
    validation.write_text(validation.read_text() + "\n# edited\n")
    edited = _jit_cache.source_key(package)
    assert edited != key

    # A new module that compiles code is a root of its own, imported by nobody yet.
    (package / "extra_law.py").write_text("from numba import njit\n")
    assert _jit_cache.source_key(package) != edited


def _pruned(root: Path, ages: dict[str, float]) -> list[str]:
    """Names left in ``root`` after pruning key directories last used ``ages`` [s] ago."""
    now = time.time()
    for name, age in ages.items():
        stamp = root / name / _jit_cache._USED_STAMP
        stamp.parent.mkdir(parents=True)
        stamp.touch()
        os.utime(stamp, (now - age, now - age))
    (root / "user-data").mkdir()  # not one of ours: never touched
    (root / "jit-current").mkdir()
    _jit_cache._prune(root, root / "jit-current")
    return sorted(p.name for p in root.iterdir())


def test_prune_keeps_current_recent_and_foreign_directories(tmp_path):
    hour = 3600.0
    # All stale: the KEEP_OTHERS = 2 most recently used stay.
    stale = {"jit-a": 10 * hour, "jit-b": 5 * hour, "jit-c": 3 * hour, "jit-d": 2 * hour}
    kept = ["jit-c", "jit-current", "jit-d", "user-data"]
    assert _pruned(tmp_path / "stale", stale) == kept
    # Past that rank but used less than MIN_AGE_S ago (a process may still write there).
    young = {"jit-y1": 60.0, "jit-y2": 120.0, "jit-y3": 300.0, "jit-a": 10 * hour}
    kept = ["jit-current", "jit-y1", "jit-y2", "jit-y3", "user-data"]
    assert _pruned(tmp_path / "young", young) == kept
