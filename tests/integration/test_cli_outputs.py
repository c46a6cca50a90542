"""No data lost: existing outputs, foreign directories, full disks, Ctrl-C, concurrent runs.

Each failure must be one line on stderr, exit status 2 (130 for Ctrl-C), no traceback,
and no partial or temporary file left behind.
"""

import errno
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import xarray as xr
from cli_inprocess import MAP, SIM, run

import microslip as ms


def assert_one_line_failure(status, err, *words, code=2):
    assert status == code, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    for word in words:
        assert word in err, (word, err)


def test_foreign_directory_is_never_deleted(capsys, tmp_path):
    # Reproduces issue 8 defect 1: `map --out EXISTING.zarr` deleted a user's directory.
    keep = tmp_path / "keep.zarr"
    keep.mkdir()
    (keep / "data.txt").write_text("precious")
    status, _, err = run(capsys, *MAP, "--out", keep)
    assert_one_line_failure(status, err, "exists", "--overwrite")
    status, _, err = run(capsys, *MAP, "--out", keep, "--overwrite")
    assert_one_line_failure(status, err, "did not write")
    assert (keep / "data.txt").read_text() == "precious"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.zarr"]  # no store, no lock
    assert sorted(p.name for p in keep.iterdir()) == ["data.txt"]


@pytest.mark.parametrize(
    ("args", "name"),
    [(SIM, "run.nc"), (SIM, "run.csv"), (SIM, "run.png"), (MAP, "map.nc"), (MAP, "map.png")],
)
def test_existing_file_is_refused_then_replaced_with_overwrite(capsys, tmp_path, args, name):
    target = tmp_path / name
    target.write_bytes(b"the user's own file")
    flag = "--plot" if name.endswith(".png") else "--out"
    extra = ["--out", tmp_path / "data.nc"] if flag == "--plot" else []
    status, _, err = run(capsys, *args, flag, target, *extra)
    assert_one_line_failure(status, err, name, "exists", "--overwrite")
    assert target.read_bytes() == b"the user's own file"
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]  # refused before computing
    status, _, err = run(capsys, *args, flag, target, *extra, "--overwrite")
    assert status == 0, err
    content = target.read_bytes()
    if name.endswith(".png"):
        assert content[:8] == b"\x89PNG\r\n\x1a\n"
    elif name.endswith(".csv"):
        assert content.startswith(b"time [s],y [m]")
    else:
        with xr.open_dataset(target) as ds:
            assert ds.attrs["Conventions"] == "CF-1.10"
    leftovers = [p.name for p in tmp_path.iterdir() if p.name.startswith(".")]
    assert leftovers == []


def test_own_zarr_output_is_replaced_whole_with_overwrite(capsys, tmp_path):
    out = tmp_path / "map.zarr"
    assert run(capsys, *MAP, "--out", out)[0] == 0
    args = ["map", "--force", "0.2,0.4", "--amplitude", "1e-7", "--quiet", "--out", out]
    status, _, err = run(capsys, *args)
    assert_one_line_failure(status, err, "exists")
    assert run(capsys, *args, "--overwrite")[0] == 0
    with xr.open_zarr(out, consolidated=False) as ds:
        assert ds["mean_velocity"].shape == (2, 1)
        expected = ms.mean_velocity(force=0.4, amplitude=1e-7)
        assert float(ds["mean_velocity"].sel(force=0.4, amplitude=1e-7)) == expected
    assert sorted(p.name for p in tmp_path.iterdir()) == ["map.zarr"]  # old copy deleted


def test_figures_checks_every_target_before_computing(capsys, tmp_path):
    (tmp_path / "fig7.nc").write_bytes(b"old")
    started = time.perf_counter()
    status, _, err = run(capsys, "figures", "--only", "fig2,fig7", "--out", tmp_path)
    assert_one_line_failure(status, err, "fig7.nc", "--overwrite")
    assert time.perf_counter() - started < 5.0  # nothing was computed
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fig7.nc"]  # fig2 not drawn


def _failing_writer(code):
    """A writer that starts the file, then fails as a full or read-only disk does."""

    def write(self, path, *args, **kwargs):
        Path(path).write_bytes(b"partial")
        raise OSError(code, os.strerror(code))

    return write


@pytest.mark.parametrize("code", [errno.ENOSPC, errno.EROFS])
@pytest.mark.parametrize(
    ("args", "name", "target"),
    [
        (SIM, "run.nc", (xr.Dataset, "to_netcdf")),
        (MAP, "map.nc", (xr.Dataset, "to_netcdf")),
        (MAP, "map.zarr", (xr.Dataset, "to_zarr")),
    ],
)
def test_write_failure_leaves_no_file(capsys, monkeypatch, tmp_path, code, args, name, target):
    monkeypatch.setattr(*target, _failing_writer(code))
    out = tmp_path / name
    status, _, err = run(capsys, *args, "--out", out)
    assert_one_line_failure(status, err, name, os.strerror(code))
    assert not out.exists()
    names = sorted(p.name for p in tmp_path.iterdir())
    # A map keeps its finished chunks for a rerun; no output, temporary or lock remains.
    assert names == ([f"{name}.partial.zarr"] if args is MAP else [])


def test_write_failure_of_csv_and_plot(capsys, monkeypatch, tmp_path):
    import pandas as pd
    from matplotlib.figure import Figure

    monkeypatch.setattr(pd.DataFrame, "to_csv", _failing_writer(errno.ENOSPC))
    status, _, err = run(capsys, *SIM, "--out", tmp_path / "run.csv")
    assert_one_line_failure(status, err, "run.csv", "No space left")
    monkeypatch.setattr(Figure, "savefig", _failing_writer(errno.ENOSPC))
    status, _, err = run(capsys, *SIM, "--plot", tmp_path / "run.png")
    assert_one_line_failure(status, err, "run.png", "No space left")
    assert list(tmp_path.iterdir()) == []


def _microslip() -> list[str]:
    exe = Path(sys.executable).with_name("microslip")
    return [str(exe)] if exe.exists() else [sys.executable, "-m", "microslip"]


def test_ctrl_c_in_simulate_is_one_line_exit_130_and_no_file(tmp_path):
    ms.simulate(force=0.5, amplitude=1.5e-7, duration=1e-3)  # the kernels are compiled
    out = tmp_path / "run.nc"
    command = [*_microslip(), "simulate", "--force", "0.5", "--amplitude", "1.5e-7"]
    # ~1e9 steps: minutes of kernel time; the interrupt must not wait for the end.
    command += ["--duration", "3000", "--allow-large", "--out", str(out)]
    # Python prints a traceback for Ctrl-C while `import microslip` runs (before any code
    # of the CLI can catch it): wait well past the import time, measured now on this load.
    started = time.perf_counter()
    imports = "import microslip.cli.commands, microslip.budget, netCDF4"
    subprocess.run([sys.executable, "-c", imports], check=True)
    import_time = time.perf_counter() - started
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(2.0 * import_time + 2.0)  # imported and inside the compiled loop by now
    assert process.poll() is None, process.communicate()
    process.send_signal(signal.SIGINT)
    started = time.perf_counter()
    _, err = process.communicate(timeout=60)
    assert time.perf_counter() - started < 10.0
    assert process.returncode == 130
    assert_one_line_failure(130, err, "interrupted", code=130)
    assert list(tmp_path.iterdir()) == []


def _interrupt_and_wait(process: subprocess.Popen) -> str:
    """SIGINT to ``process``; its stderr once it has ended (fails after 60 s)."""
    process.send_signal(signal.SIGINT)
    try:
        return process.communicate(timeout=60)[1]
    except subprocess.TimeoutExpired:
        process.kill()
        err = process.communicate()[1]
        pytest.fail(f"the run went on for 60 s after its SIGINT: {err!r}")


def test_ctrl_c_in_a_long_map_chunk_stops_at_once_and_keeps_the_store(tmp_path):
    """One chunk of hours in compiled code (a lane above μ m g never repeats a period):
    the Ctrl-C is raised while the chunk runs, not when it ends (threads.run_ranges)."""
    ms.velocity_map(forces=[1.5], amplitudes=[1e-7], method="time", duration=1e-3)
    out = tmp_path / "map.nc"
    command = [*_microslip(), "map", "--force", "1.5", "--amplitude", "1e-7", "--method"]
    command += ["time", "--duration", "1e5", "--allow-large", "--quiet", "--out", str(out)]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    store = tmp_path / "map.nc.partial.zarr"
    deadline = time.time() + 120
    while time.time() < deadline and process.poll() is None and not store.exists():
        time.sleep(0.02)
    time.sleep(2.0)  # inside the compiled chunk by now
    assert process.poll() is None, process.communicate()
    err = _interrupt_and_wait(process)
    assert_one_line_failure(process.returncode, err, "interrupted", "resume", code=130)
    assert store.exists() and not out.exists()


def test_second_map_on_the_same_output_stops_at_once(tmp_path):
    out = tmp_path / "map.nc"
    long_map = ["map", "--force", "1.0:1.9:40", "--amplitude", "0:3e-7:150", "--chunk", "1"]
    # Long enough (minutes) that the first run is still computing when the second has
    # started and stopped: forces above μ m g = 0.981 N slide for ever, so no lane repeats
    # a period and every period is stepped. (Below it the lanes park and a set-up skips
    # the periods left: the map then ends in seconds, before its SIGINT, exit 0.)
    long_map += ["--method", "time", "--duration", "10.0", "--quiet", "--out", str(out)]
    first = subprocess.Popen(
        [*_microslip(), *long_map], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    lock = tmp_path / "map.nc.lock"
    deadline = time.time() + 120
    while time.time() < deadline and first.poll() is None and not lock.exists():
        time.sleep(0.02)
    try:
        assert first.poll() is None and lock.exists(), "the first run never took its lock"
        started = time.perf_counter()
        second = subprocess.run(
            [*_microslip(), *long_map], capture_output=True, text=True, timeout=120
        )
        assert first.poll() is None, "the first run ended before the second one started"
        assert time.perf_counter() - started < 30.0  # stops at once (import time only)
        assert_one_line_failure(second.returncode, second.stderr, "another microslip run")
        # Interrupt once the first run has its chunk store: before that, "no output
        # written" is the right message (a loaded machine got there once).
        store = tmp_path / "map.nc.partial.zarr"
        deadline = time.time() + 120
        while time.time() < deadline and first.poll() is None and not store.exists():
            time.sleep(0.02)
    finally:
        first_err = _interrupt_and_wait(first)
    assert first.returncode == 130
    assert_one_line_failure(130, first_err, "interrupted", "resume", code=130)
    assert not out.exists() and not lock.exists()


def test_a_long_map_says_what_to_expect_before_it_starts(capsys, monkeypatch, tmp_path):
    """A run estimated at LONG_RUN_S or more notes its chunks, its estimate and where a
    Ctrl-C leaves its work, on stderr before it starts (a log gets no progress bar); a
    short run and a quiet one say nothing of it."""
    from microslip.cli import sweep_command

    grid = ["map", "--force", "0.1:0.9:3", "--amplitude", "0:3e-7:3", "--out"]
    status, _, err = run(capsys, *grid, tmp_path / "short.nc")
    assert status == 0 and "estimated" not in err
    monkeypatch.setattr(sweep_command, "LONG_RUN_S", 0.0)
    status, _, err = run(capsys, *grid, tmp_path / "quiet.nc", "--quiet")
    assert status == 0 and err == ""
    status, _, err = run(capsys, *grid, tmp_path / "long.nc")
    assert status == 0
    note = [line for line in err.splitlines() if "estimated to take about" in line]
    assert len(note) == 1 and note[0].startswith("microslip: note: 1 chunks, ")
    assert str(tmp_path / "long.nc.partial.zarr") in note[0]
