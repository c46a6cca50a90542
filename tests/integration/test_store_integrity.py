"""The working store on disk: damaged chunks are found and recomputed, never baked in."""

import errno
import json
import os
import shutil
import warnings

import numpy as np
import pytest
import zarr

import microslip.sweeps.runner as runner
from microslip.sweeps import StoreMismatchError, SweepSpec, run_sweep
from microslip.sweeps.store import SweepStore, _digest

FORCES = np.linspace(0.05, 0.95, 12)
AMPLITUDES = np.linspace(0.0, 3e-7, 20)
# A 2-parameter sweep, so chunk keys have two indices and chunk files sit in several dirs.
AXES = {"mu": [0.1, 0.12]}


def spec():
    return SweepSpec.build(None, AXES, FORCES, AMPLITUDES, amplitude_chunk=3)


def partial_store(path, monkeypatch, n_done):
    """A store left by a run interrupted after ``n_done`` chunks; returns the compute spy."""
    calls = []
    real = runner.compute_chunk

    def counting(spec_, key, progress=None):
        calls.append(key)
        if len(calls) == n_done + 1 and stop[0]:
            raise KeyboardInterrupt
        return real(spec_, key, progress)

    stop = [True]
    monkeypatch.setattr(runner, "compute_chunk", counting)
    with pytest.raises(KeyboardInterrupt):
        run_sweep(spec(), store=path)
    stop[0] = False
    calls.clear()
    return calls


def test_damaged_store_is_repaired_to_the_uninterrupted_result(tmp_path, monkeypatch):
    reference = run_sweep(spec())
    store = tmp_path / "work.zarr"
    calls = partial_store(store, monkeypatch, n_done=9)
    s = SweepStore(store, spec())
    keys = list(spec().chunks())
    done, never = keys[:9], keys[9:]
    assert len(keys) == 14 and all(s.record_file(k).exists() for k in done)
    assert not any(s.record_file(k).exists() for k in never)

    flipped, truncated, deleted, forged, bad_record = done[1], done[3], done[5], never[2], done[7]
    raw = bytearray(s.chunk_file(flipped).read_bytes())
    raw[len(raw) // 2] ^= 0xFF
    raw[len(raw) // 2 + 1] ^= 0x55
    s.chunk_file(flipped).write_bytes(bytes(raw))
    data = s.chunk_file(truncated).read_bytes()
    s.chunk_file(truncated).write_bytes(data[: len(data) // 2])
    s.chunk_file(deleted).unlink()
    # A well-formed, self-consistent record for a chunk that was never computed.
    fields = {**json.loads(s.record_file(done[0]).read_text()), "chunk": list(forged)}
    fields.pop("check")
    s.record_file(forged).write_text(json.dumps({**fields, "check": _digest(fields)}))
    text = s.record_file(bad_record).read_text()
    s.record_file(bad_record).write_text(text.replace('"bytes": ', '"bytes": 1'))

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        resumed = run_sweep(spec(), store=store)
    messages = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    assert len(messages) == 5, messages
    for key, reason in [
        (flipped, "damaged data file"), (truncated, "damaged data file"),
        (deleted, "is missing"), (forged, "is missing"), (bad_record, "damaged completion record"),
    ]:  # fmt: skip
        assert any(f"chunk {key} " in m and reason in m for m in messages), (key, messages)
    # Only the damaged and the never-computed chunks were computed again.
    assert sorted(calls) == sorted([flipped, truncated, deleted, bad_record, *never])
    values = resumed["mean_velocity"].values
    assert not np.isnan(values).any()
    assert np.array_equal(values, reference["mean_velocity"].values)
    assert resumed.identical(reference)
    # The repaired store now verifies cleanly and needs nothing.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert SweepStore(store, spec()).verify() == []


def test_chunks_carry_a_crc32c_checksum(tmp_path):
    """Flipped bytes fail to decode through Zarr itself, record or not."""
    store = tmp_path / "work.zarr"
    run_sweep(spec(), store=store)
    s = SweepStore(store, spec())
    path = s.chunk_file((1, 2))
    raw = bytearray(path.read_bytes())
    raw[len(raw) // 2] ^= 0x01  # one bit
    path.write_bytes(bytes(raw))
    array = zarr.open_group(str(store), mode="r")["mean_velocity"]
    with pytest.raises(ValueError, match="checksum"):
        array[1, :, 6:9]


def test_record_moved_to_another_chunk_is_rejected(tmp_path):
    store = tmp_path / "work.zarr"
    reference = run_sweep(spec(), store=store)
    s = SweepStore(store, spec())
    # Chunk (0, 0)'s valid data and record copied over chunk (1, 0): every file is
    # individually intact, but the record names the wrong chunk.
    shutil.copy(s.chunk_file((0, 0)), s.chunk_file((1, 0)))
    shutil.copy(s.record_file((0, 0)), s.record_file((1, 0)))
    with pytest.warns(RuntimeWarning, match=r"chunk \(1, 0\) .*damaged completion record"):
        resumed = run_sweep(spec(), store=store)
    assert resumed.identical(reference)


def test_chunk_that_decodes_to_nan_is_recomputed(tmp_path):
    """A chunk whose record and checksum agree but holds NaN is not trusted."""
    store = tmp_path / "work.zarr"
    reference = run_sweep(spec(), store=store)
    s = SweepStore(store, spec())
    key = (0, 4)
    s.array[spec().region(key)] = np.full((12, 3), np.nan)
    s.record_file(key).unlink()
    s.write(key, np.asarray(s.array[spec().region(key)]))  # a record vouching for NaN
    with pytest.warns(RuntimeWarning, match=r"chunk \(0, 4\) .*NaN"):
        resumed = run_sweep(spec(), store=store)
    assert not np.isnan(resumed["mean_velocity"].values).any()
    assert resumed.identical(reference)


def test_chunk_computed_as_nan_is_an_error_not_a_result(tmp_path, monkeypatch):
    real = runner.compute_chunk

    def broken(spec_, key, progress=None):
        block = real(spec_, key, progress)
        if key == (1, 3):
            block[2, 1] = np.nan
        return block

    monkeypatch.setattr(runner, "compute_chunk", broken)
    with pytest.raises(RuntimeError, match=r"chunk \(1, 3\) holds 1 NaN"):
        run_sweep(spec(), store=tmp_path / "work.zarr")
    s = SweepStore(tmp_path / "work.zarr", spec())
    assert not s.record_file((1, 3)).exists()


def test_store_without_checksums_is_not_resumed(tmp_path):
    """A store of the earlier layout (no checksums, one "done" array) is refused, not trusted."""
    store = tmp_path / "work.zarr"
    group = zarr.open_group(str(store), mode="w")
    group.create_array("mean_velocity", shape=spec().shape, chunks=(1, 12, 3), dtype="f8")
    group.create_array("done", shape=spec().chunk_grid, dtype="bool")
    group.attrs["sweep_definition"] = json.dumps(spec().definition(), sort_keys=True)
    with pytest.raises(StoreMismatchError, match="older microslip without chunk checksums"):
        run_sweep(spec(), store=store)


def test_failed_chunk_write_stops_the_run_and_a_rerun_completes(tmp_path, monkeypatch):
    """A full disk while writing a chunk is an error (not swallowed by the writer thread)."""
    store = tmp_path / "work.zarr"
    real = SweepStore.write

    def full_disk(self, key, block):
        if key == (0, 5):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        real(self, key, block)

    monkeypatch.setattr(SweepStore, "write", full_disk)
    with pytest.raises(OSError, match="No space left"):
        run_sweep(spec(), store=store)
    monkeypatch.undo()
    assert not SweepStore(store, spec()).record_file((0, 5)).exists()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing damaged: (0, 5) was never recorded
        assert run_sweep(spec(), store=store).identical(run_sweep(spec()))


def test_finished_chunks_waiting_for_a_slow_disk_are_bounded(tmp_path, monkeypatch):
    """Where the store's writes are slower than the chunks come, the computation waits:
    at most MAX_PENDING_WRITE_BYTES of finished chunks wait for the writer (without the
    bound all of them would, a fraction of the map held twice), and the result is the
    same as without a store."""
    reference = run_sweep(spec())
    block_bytes = FORCES.size * 3 * 8  # a chunk: one value of mu, forces x 3 amplitudes
    monkeypatch.setattr(runner, "MAX_PENDING_WRITE_BYTES", 2 * block_bytes)
    computed, written, waiting = [], [], []
    real_compute, real_write = runner.compute_chunk, SweepStore.write

    def compute(spec_, key, progress=None):
        computed.append(key)
        waiting.append(len(computed) - len(written))
        return real_compute(spec_, key, progress)

    def slow_write(self, key, block):
        import time

        time.sleep(0.05)
        real_write(self, key, block)
        written.append(key)

    monkeypatch.setattr(runner, "compute_chunk", compute)
    monkeypatch.setattr(SweepStore, "write", slow_write)
    result = run_sweep(spec(), store=tmp_path / "slow.zarr")
    assert len(computed) == 14 and len(written) == 14
    # The chunk being computed, one being written and at most two queued (three behind a
    # chunk of two amplitudes, the last of each mu). Unbounded, all 14 would queue.
    assert max(waiting) <= 5, waiting
    assert np.array_equal(result.mean_velocity.values, reference.mean_velocity.values)


def test_points_left_uncomputed_are_counted_across_slabs():
    values = np.zeros(3 * 2**20 + 8)
    values[[0, 2**20 - 1, 2**20, 3 * 2**20 + 7]] = np.nan  # both sides of a slab edge, the tail
    values[7] = np.inf  # an infinite mean velocity is a result, not a gap
    assert runner._count_nan(values.reshape(-1, 4)) == 4
