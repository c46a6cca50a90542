"""Sweeps past one process: resumable stores and Dask clusters on loopback."""

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
import xarray as xr

import microslip.sweeps.runner as runner
from microslip.sweeps import StoreMismatchError, SweepSpec, run_sweep
from microslip.sweeps.store import SweepStore

FORCES = np.linspace(0.05, 0.95, 12)
AMPLITUDES = np.linspace(0.0, 3e-7, 20)


def spec(**changes):
    options = {"amplitude_chunk": 3, **changes}
    return SweepSpec.build(None, None, FORCES, AMPLITUDES, **options)


def test_interrupted_sweep_resumes_only_missing_chunks(tmp_path, monkeypatch):
    reference = run_sweep(spec())
    store = tmp_path / "work.zarr"
    calls = []
    interrupt_at = [4]  # the 4th chunk of the first run is "interrupted" (Ctrl-C)
    real = runner.compute_chunk

    def flaky(spec_, key, progress=None):
        calls.append(key)
        if len(calls) == interrupt_at[0]:
            interrupt_at[0] = -1
            raise KeyboardInterrupt
        return real(spec_, key, progress)

    monkeypatch.setattr(runner, "compute_chunk", flaky)
    with pytest.raises(KeyboardInterrupt):
        run_sweep(spec(), store=store)
    assert not store.with_name("work.zarr.lock").exists()  # released on the way out
    assert len(SweepStore(store, spec()).missing()) == spec().n_chunks - 3
    calls.clear()
    resumed = run_sweep(spec(), store=store)
    assert len(calls) == spec().n_chunks - 3  # only the missing chunks
    assert resumed.identical(reference)


def test_store_of_another_sweep_is_refused(tmp_path):
    store = tmp_path / "work.zarr"
    run_sweep(spec(), store=store)
    with pytest.raises(StoreMismatchError, match="amplitudes"):
        run_sweep(
            SweepSpec.build(None, None, FORCES, AMPLITUDES[:-1], amplitude_chunk=3), store=store
        )
    junk = tmp_path / "junk.zarr"
    junk.mkdir()
    (junk / "file").write_text("x")
    with pytest.raises(StoreMismatchError, match="not a microslip sweep store"):
        run_sweep(spec(), store=junk)


def _without_history(path):
    """The file's Dataset minus ``history`` (it holds the time and command of each run)."""
    with xr.open_dataset(path) as ds:
        ds = ds.load()
    ds.attrs.pop("history", None)
    return ds


def test_killed_cli_sweep_resumes_to_identical_file(cli, tmp_path):
    args = ["map", "--force", "0.05:0.95:40", "--amplitude", "0:3e-7:150", "--chunk", "1",
            "--method", "time", "--duration", "0.004", "--quiet"]  # fmt: skip
    n_chunks = 150
    whole = tmp_path / "whole.nc"
    assert cli(*args, "--out", str(whole)).returncode == 0
    out = tmp_path / "map.nc"
    work = tmp_path / "map.nc.partial.zarr"
    exe = [str(sys.executable.replace("python", "microslip"))]
    if not os.path.exists(exe[0]):
        exe = [sys.executable, "-m", "microslip.cli.main"]
    process = subprocess.Popen([*exe, *args, "--out", str(out)])

    def n_complete():
        records = work / "complete"
        return len(list(records.glob("*.json"))) if records.exists() else 0

    deadline = time.time() + 240
    while time.time() < deadline and process.poll() is None and n_complete() < 3:
        time.sleep(0.01)
    assert process.poll() is None, "the run ended before it could be killed mid-way"
    process.send_signal(signal.SIGKILL)
    process.wait()
    # Killed mid-way: a partial store with some, but not all, chunks complete, no output.
    assert 3 <= n_complete() < n_chunks
    assert not out.exists()
    # Damage one finished chunk as well: the resumed run names it and computes it again.
    record = sorted((work / "complete").glob("*.json"))[0]
    damaged = work / json.loads(record.read_text())["file"]
    raw = bytearray(damaged.read_bytes())
    raw[len(raw) // 2] ^= 0xFF
    damaged.write_bytes(bytes(raw))
    result = cli(*args, "--out", str(out))
    assert result.returncode == 0, result.stderr
    key = tuple(int(i) for i in record.name.removesuffix(".json").split("."))
    assert f"chunk {key} " in result.stderr and "recomputing it" in result.stderr
    resumed, reference = _without_history(out), _without_history(whole)
    assert resumed.identical(reference)
    values = resumed["mean_velocity"].values
    assert not np.isnan(values).any()
    assert np.array_equal(values, reference["mean_velocity"].values)
    assert not work.exists()


def test_local_dask_cluster_matches_embedded_run_bit_for_bit():
    embedded = run_sweep(spec())
    distributed = run_sweep(spec(), workers=2)
    np.testing.assert_array_equal(
        distributed["mean_velocity"].values, embedded["mean_velocity"].values
    )
    assert distributed.identical(embedded)


def test_local_workers_share_out_the_kernel_threads(monkeypatch):
    """Each of N local workers runs its kernels on the threads / N of this process (at
    least 1), not on every CPU each."""
    from microslip.integrators import threads
    from microslip.sweeps.runner import dask_client

    monkeypatch.setattr(threads, "thread_count", lambda: 4)

    def probe():
        from microslip.integrators.threads import thread_count

        return thread_count()

    with dask_client(None, 2) as client:
        assert sorted(client.run(probe).values()) == [2, 2]
    monkeypatch.setattr(threads, "thread_count", lambda: 1)
    with dask_client(None, 2) as client:
        assert sorted(client.run(probe).values()) == [1, 1]


def test_existing_scheduler_address(tmp_path):
    from distributed import LocalCluster

    with LocalCluster(
        n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None,
        host="127.0.0.1",
    ) as cluster:  # fmt: skip
        via_scheduler = run_sweep(
            spec(method="time", duration=0.002), scheduler=cluster.scheduler_address,
            store=tmp_path / "s.zarr",
        )  # fmt: skip
    embedded = run_sweep(spec(method="time", duration=0.002))
    assert via_scheduler.identical(embedded)


def test_unreachable_scheduler_fails_fast():
    started = time.perf_counter()
    with pytest.raises(ConnectionError, match="cannot reach Dask scheduler"):
        run_sweep(spec(), scheduler="tcp://127.0.0.1:9")
    assert time.perf_counter() - started < 30


def test_unreachable_scheduler_cli(cli, tmp_path):
    result = cli(
        "map", "--force", "0.5", "--amplitude", "1e-7", "--out", str(tmp_path / "m.nc"),
        "--scheduler", "tcp://127.0.0.1:9", "--quiet",
    )  # fmt: skip
    assert result.returncode == 2
    assert "cannot reach Dask scheduler" in result.stderr
    assert sorted(tmp_path.iterdir()) == []  # neither the output nor a working store
