"""A command run on an empty kernel cache counts the compile apart from the run in its
summary line; the next run, served from the cache, names the load of the kernels
instead. Off a terminal (here: captured) stderr gets no note of the compile
(tests/unit/test_compile_clock.py checks it at a terminal)."""

from __future__ import annotations

import re

MAP = ("map", "--force", "0.1:0.9:4", "--amplitude", "1e-7,2e-7")
SUMMARY = re.compile(
    r"^1 chunks, 8 points in (\d+\.\d+) s"
    r"( \+ (\d+\.\d+) s (compiling kernels|loading compiled kernels))?; max v"
)


def _summary(stdout: str) -> re.Match:
    match = SUMMARY.match(stdout.splitlines()[0])
    assert match, stdout
    return match


def test_first_run_counts_its_compile_and_the_next_its_load(cli, tmp_path, monkeypatch):
    cache = tmp_path / "kernels"
    monkeypatch.setenv("MICROSLIP_CACHE_DIR", str(cache))

    first = cli(*MAP, "--out", str(tmp_path / "first.nc"))
    assert first.returncode == 0, first.stderr
    assert first.stderr == ""  # not a terminal: no note
    assert any(cache.rglob("*.nbi"))  # the kernels were compiled into the cache
    compiled = _summary(first.stdout)
    # The steady map's kernels take seconds to compile, far longer than the run.
    assert compiled.group(4) == "compiling kernels"
    assert float(compiled.group(3)) > float(compiled.group(1))

    second = cli(*MAP, "--out", str(tmp_path / "second.nc"))
    assert second.returncode == 0, second.stderr
    assert second.stderr == ""
    loaded = _summary(second.stdout)
    # numba's start-up on its first load from the cache alone is well above 0.05 s.
    assert loaded.group(4) == "loading compiled kernels"
    assert float(loaded.group(3)) < float(compiled.group(3))
