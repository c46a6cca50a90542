"""io.output: atomic writes, no replacement without overwrite, foreign directories kept,
directories replaced without a moment with no complete copy, CF attributes added."""

import os
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from microslip.io import output
from microslip.io.output import (
    OutputError,
    OutputExistsError,
    is_microslip_output,
    write_atomically,
    write_dataset,
)
from microslip.metadata import cf_attributes, running


def dataset(value: float) -> xr.Dataset:
    return xr.Dataset(
        {"v": ("a", np.array([value, 2 * value]), {"units": "m s-1"})},
        coords={"a": ("a", [0.0, 1.0], {"units": "m"})},
        attrs={"title": "microslip test"},
    )


def test_foreign_zarr_and_plain_directories_are_not_ours(tmp_path):
    xr.Dataset({"v": ("a", [1.0])}).to_zarr(tmp_path / "theirs.zarr", consolidated=False)
    (tmp_path / "plain.zarr").mkdir()
    write_dataset(dataset(1.0), tmp_path / "ours.zarr")
    assert is_microslip_output(tmp_path / "ours.zarr")
    assert not is_microslip_output(tmp_path / "theirs.zarr")
    assert not is_microslip_output(tmp_path / "plain.zarr")
    for name in ("theirs.zarr", "plain.zarr"):
        with pytest.raises(OutputExistsError, match="did not write"):
            write_dataset(dataset(2.0), tmp_path / name, overwrite=True)
    assert (tmp_path / "theirs.zarr" / "v").is_dir()


def test_overwrite_false_refuses_and_true_replaces(tmp_path):
    path = tmp_path / "out.nc"
    path.write_bytes(b"mine")
    with pytest.raises(OutputExistsError, match="exists"):
        write_dataset(dataset(1.0), path, overwrite=False)
    assert path.read_bytes() == b"mine"
    write_dataset(dataset(3.0), path, overwrite=True)
    with xr.open_dataset(path) as ds:
        np.testing.assert_array_equal(ds["v"].values, [3.0, 6.0])
    assert sorted(os.listdir(tmp_path)) == ["out.nc"]


def test_file_appearing_while_computing_is_not_replaced(tmp_path, monkeypatch):
    path = tmp_path / "out.csv"

    def writer(tmp):
        tmp.write_text("new")
        path.write_text("someone else's")  # appears while we compute

    with pytest.raises(OutputExistsError, match="exists"):
        write_atomically(path, writer, overwrite=False)
    assert path.read_text() == "someone else's"
    path.unlink()
    real_link = os.link

    def racing_link(src, dst):  # appears between the last check and the rename
        Path(dst).write_text("someone else's")
        return real_link(src, dst)

    monkeypatch.setattr(output.os, "link", racing_link)
    with pytest.raises(OutputExistsError, match="appeared"):
        write_atomically(path, lambda tmp: tmp.write_text("new"), overwrite=False)
    assert path.read_text() == "someone else's"
    assert sorted(os.listdir(tmp_path)) == ["out.csv"]


def test_directory_replacement_keeps_the_old_copy_if_the_new_cannot_move_in(tmp_path, monkeypatch):
    path = tmp_path / "map.zarr"
    write_dataset(dataset(1.0), path)
    real_rename = os.rename
    calls = []

    def failing_second_rename(src, dst):
        calls.append((src, dst))
        if len(calls) == 2:  # old -> aside worked; new -> place fails
            raise OSError(28, "No space left on device")
        return real_rename(src, dst)

    monkeypatch.setattr(output.os, "rename", failing_second_rename)
    with pytest.raises(OutputError, match="No space left"):
        write_dataset(dataset(5.0), path)
    monkeypatch.undo()
    assert len(calls) == 3  # aside, failed move in, aside back
    with xr.open_zarr(path, consolidated=False) as ds:
        np.testing.assert_array_equal(ds["v"].values, [1.0, 2.0])
    assert sorted(os.listdir(tmp_path)) == ["map.zarr"]
    write_dataset(dataset(5.0), path)
    with xr.open_zarr(path, consolidated=False) as ds:
        np.testing.assert_array_equal(ds["v"].values, [5.0, 10.0])
    assert sorted(os.listdir(tmp_path)) == ["map.zarr"]


@pytest.mark.parametrize("error", [KeyboardInterrupt(), OSError(28, "No space left on device")])
def test_interrupted_or_failed_writer_leaves_the_old_file_and_no_temporary(tmp_path, error):
    path = tmp_path / "out.nc"
    path.write_bytes(b"old")

    def writer(tmp):
        tmp.write_bytes(b"half")
        raise error

    with pytest.raises(KeyboardInterrupt if isinstance(error, KeyboardInterrupt) else OutputError):
        write_atomically(path, writer)
    assert path.read_bytes() == b"old"
    assert sorted(os.listdir(tmp_path)) == ["out.nc"]


def test_cf_attributes_are_added_without_replacing_the_datasets_own(tmp_path):
    ds = dataset(1.0)
    ds.attrs["history"] = "made by hand"
    with running(["microslip", "map", "--force", "0.5"]):
        write_dataset(ds, tmp_path / "a.nc")
        write_dataset(dataset(1.0), tmp_path / "b.nc")
    assert "Conventions" not in ds.attrs  # the caller's Dataset is not modified
    with xr.open_dataset(tmp_path / "a.nc") as a, xr.open_dataset(tmp_path / "b.nc") as b:
        assert a.attrs["history"] == "made by hand"
        assert a.attrs["title"] == "microslip test"
        assert b.attrs["history"].endswith(": microslip map --force 0.5")
        for key in ("Conventions", "source", "references"):
            assert a.attrs[key] == b.attrs[key] == cf_attributes("x")[key]


@pytest.mark.parametrize("extra", ["precious.txt", "v/notes.txt", "sub/data.bin"])
def test_overwrite_keeps_a_store_holding_other_files(tmp_path, extra):
    path = tmp_path / "ours.zarr"
    write_dataset(dataset(1.0), path)
    write_dataset(dataset(2.0), path, overwrite=True)  # the store's own files only: replaced
    (path / extra).parent.mkdir(exist_ok=True)
    (path / extra).write_text("mine")
    with pytest.raises(OutputExistsError, match="not part of its Zarr store"):
        write_dataset(dataset(3.0), path, overwrite=True)
    assert (path / extra).read_text() == "mine"
    (path / extra).unlink()  # (zarr warns about a foreign file when opening)
    if extra.startswith("sub/"):
        (path / "sub").rmdir()
    with xr.open_zarr(path, consolidated=False) as ds:
        assert ds["v"].values[0] == 2.0


def test_fake_microslip_store_with_a_user_file_is_not_replaced(tmp_path):
    fake = tmp_path / "fake.zarr"
    fake.mkdir()
    (fake / "zarr.json").write_text('{"attributes": {"source": "microslip 0.0"}}')
    (fake / "precious.txt").write_text("mine")
    with pytest.raises(OutputExistsError):
        write_dataset(dataset(1.0), fake, overwrite=True)
    assert (fake / "precious.txt").read_text() == "mine"


@pytest.mark.parametrize("name", ["", "a\\b.nc", "dir\\x/run.nc"])
def test_empty_or_backslash_netcdf_paths_are_refused(tmp_path, name):
    with pytest.raises(OutputError, match=r"empty|backslash"):
        output.check_writable(str(tmp_path / name) if name else name)


def test_batch_moves_all_outputs_or_none(tmp_path):
    (tmp_path / "b.txt").write_text("old")
    with pytest.raises(KeyboardInterrupt), output.OutputBatch(overwrite=True) as batch:
        batch.temporary(tmp_path / "a.txt").write_text("new a")
        batch.temporary(tmp_path / "b.txt").write_text("new b")
        raise KeyboardInterrupt  # before commit: nothing moved, temporaries removed
    assert sorted(os.listdir(tmp_path)) == ["b.txt"] and (tmp_path / "b.txt").read_text() == "old"
    with output.OutputBatch(overwrite=True) as batch:
        batch.temporary(tmp_path / "a.txt").write_text("new a")
        batch.temporary(tmp_path / "b.txt").write_text("new b")
        assert batch.commit() == [tmp_path / "a.txt", tmp_path / "b.txt"]
    assert sorted(os.listdir(tmp_path)) == ["a.txt", "b.txt"]
    assert (tmp_path / "b.txt").read_text() == "new b"
