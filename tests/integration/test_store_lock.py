"""One store, one run: a second process is refused at once, and a killed holder frees it."""

import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import microslip.sweeps.runner as runner
from microslip.sweeps import StoreBusyError, SweepSpec, exclusive_lock, run_sweep

HOLDER = """
import sys, time
from microslip.sweeps import exclusive_lock
with exclusive_lock(sys.argv[1]):
    print("locked", flush=True)
    time.sleep(120)
"""


def spec():
    return SweepSpec.build(None, None, np.linspace(0.1, 0.9, 4), np.linspace(0, 3e-7, 6),
                           amplitude_chunk=2)  # fmt: skip


@pytest.fixture
def holder(tmp_path):
    """Another process holding the lock of ``tmp_path / "work.zarr"``."""
    store = tmp_path / "work.zarr"
    process = subprocess.Popen(
        [sys.executable, "-c", HOLDER, str(store)], stdout=subprocess.PIPE, text=True
    )
    assert process.stdout.readline().strip() == "locked"
    yield process, store
    if process.poll() is None:
        process.kill()
    process.wait()


def test_second_process_on_the_same_store_is_refused_at_once(holder):
    process, store = holder
    started = time.perf_counter()
    with pytest.raises(StoreBusyError, match=r"another microslip run is using .*work\.zarr"):
        run_sweep(spec(), store=store)
    assert time.perf_counter() - started < 5
    assert not store.exists()  # refused before anything was created
    assert store.with_name("work.zarr.lock").exists()  # the holder's lock is left alone
    process.send_signal(signal.SIGINT)  # Ctrl-C: the with block exits and removes the lock file
    process.wait()
    assert not store.with_name("work.zarr.lock").exists()
    assert run_sweep(spec(), store=store).identical(run_sweep(spec()))


def test_lock_of_a_killed_process_does_not_block(holder):
    process, store = holder
    process.send_signal(signal.SIGKILL)
    process.wait()
    assert store.with_name("work.zarr.lock").exists()  # stale file, but no lock on it
    with exclusive_lock(store) as lock_file:
        assert lock_file == store.with_name("work.zarr.lock")
    assert not lock_file.exists()


def test_run_sweep_holds_the_lock_while_it_runs(tmp_path, monkeypatch):
    store = tmp_path / "work.zarr"
    seen = []
    real = runner.compute_chunk

    def probing(spec_, key, progress=None):
        try:
            with exclusive_lock(store):
                seen.append("free")
        except StoreBusyError:
            seen.append("busy")
        return real(spec_, key, progress)

    monkeypatch.setattr(runner, "compute_chunk", probing)
    run_sweep(spec(), store=store)
    assert seen == ["busy"] * spec().n_chunks
    with exclusive_lock(store):  # released afterwards
        pass
