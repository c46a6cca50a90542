"""A command run on an empty kernel cache says it compiles, and counts the compile apart
from the run in its summary line; the next run, served from the cache, says neither."""

from __future__ import annotations

import re

MAP = ("map", "--force", "0.1:0.9:4", "--amplitude", "1e-7,2e-7")
NOTE = "microslip map: note: compiling kernels for these sources"
SUMMARY = re.compile(
    r"^1 chunks, 8 points in (\d+\.\d+) s( \+ (\d+\.\d) s compiling kernels)?; max v"
)


def _summary(stdout: str) -> re.Match:
    match = SUMMARY.match(stdout.splitlines()[0])
    assert match, stdout
    return match


def test_first_run_says_it_compiles_and_the_next_does_not(cli, tmp_path, monkeypatch):
    cache = tmp_path / "kernels"
    monkeypatch.setenv("MICROSLIP_CACHE_DIR", str(cache))

    first = cli(*MAP, "--out", str(tmp_path / "first.nc"))
    assert first.returncode == 0, first.stderr
    notes = [line for line in first.stderr.splitlines() if line.startswith(NOTE)]
    assert len(notes) == 1, first.stderr
    assert str(cache) in notes[0]  # where later runs load them from
    compiled = _summary(first.stdout)
    # The steady map's kernels take seconds to compile, far longer than the run.
    assert compiled.group(2) and float(compiled.group(3)) > float(compiled.group(1))

    second = cli(*MAP, "--out", str(tmp_path / "second.nc"))
    assert second.returncode == 0, second.stderr
    assert NOTE not in second.stderr
    assert _summary(second.stdout).group(2) is None
