"""remove_store deletes microslip's working stores and nothing else."""

import numpy as np
import pytest

from microslip.sweeps import (
    StoreBusyError,
    StoreMismatchError,
    SweepSpec,
    exclusive_lock,
    remove_store,
)
from microslip.sweeps.store import SweepStore


def make_store(path):
    spec = SweepSpec.build(None, None, [0.2, 0.4], np.linspace(0, 2e-7, 4), amplitude_chunk=2)
    store = SweepStore(path, spec)
    store.write((0,), np.ones((2, 2)))
    return store


def test_foreign_directory_survives(tmp_path):
    foreign = tmp_path / "out.zarr"
    foreign.mkdir()
    (foreign / "data.txt").write_text("precious")
    with pytest.raises(StoreMismatchError, match="not a microslip sweep store"):
        remove_store(foreign)
    assert (foreign / "data.txt").read_text() == "precious"
    assert not (tmp_path / "out.zarr.lock").exists()


def test_store_holding_a_foreign_file_survives(tmp_path):
    store = make_store(tmp_path / "w.zarr")
    (store.path / "mean_velocity" / "notes.txt").write_text("mine")
    with pytest.raises(StoreMismatchError):
        remove_store(store.path)
    assert (store.path / "mean_velocity" / "notes.txt").exists()


def test_foreign_zarr_group_survives(tmp_path):
    import zarr

    group = zarr.open_group(str(tmp_path / "other.zarr"), mode="w")
    group.create_array("mean_velocity", shape=(2,), dtype="f8")
    with pytest.raises(StoreMismatchError):
        remove_store(tmp_path / "other.zarr")
    assert (tmp_path / "other.zarr" / "zarr.json").exists()


def test_symlink_to_a_store_is_not_followed(tmp_path):
    store = make_store(tmp_path / "w.zarr")
    link = tmp_path / "link.zarr"
    link.symlink_to(store.path)
    with pytest.raises(StoreMismatchError):
        remove_store(link)
    assert store.record_file((0,)).exists()


def test_working_store_is_removed(tmp_path):
    store = make_store(tmp_path / "w.zarr")
    assert store.record_file((0,)).exists()
    remove_store(store.path)
    assert sorted(tmp_path.iterdir()) == []  # neither the store nor its lock file
    remove_store(store.path)  # already gone: nothing to do


def test_store_in_use_is_not_removed(tmp_path):
    store = make_store(tmp_path / "w.zarr")
    with exclusive_lock(store.path), pytest.raises(StoreBusyError):
        remove_store(store.path)
    assert store.record_file((0,)).exists()


def test_plain_file_is_refused(tmp_path):
    path = tmp_path / "map.nc"
    path.write_bytes(b"CDF")
    with pytest.raises(StoreMismatchError):
        remove_store(path)
    assert path.read_bytes() == b"CDF"
