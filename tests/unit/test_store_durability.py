"""A chunk's completion record is written only after its data are on the disk."""

import os
from pathlib import Path

import numpy as np

from microslip.sweeps import SweepSpec
from microslip.sweeps.store import SweepStore


def test_record_follows_durable_data(tmp_path, monkeypatch):
    spec = SweepSpec.build(None, {"mu": [0.1, 0.2]}, [0.2, 0.4], np.linspace(0, 2e-7, 4),
                           amplitude_chunk=2)  # fmt: skip
    store = SweepStore(tmp_path / "w.zarr", spec)
    key = (1, 1)
    chunk, record = store.chunk_file(key), store.record_file(key)
    events = []
    real_fsync, real_replace = os.fsync, os.replace

    def fsync(fd):
        path = Path(os.readlink(f"/proc/self/fd/{fd}"))
        events.append(("fsync", path, record.exists()))
        real_fsync(fd)

    def replace(src, dst):
        events.append(("replace", Path(dst), record.exists()))
        real_replace(src, dst)

    monkeypatch.setattr(os, "fsync", fsync)
    monkeypatch.setattr(os, "replace", replace)
    store.write(key, np.full((2, 2), 0.25))
    monkeypatch.undo()

    def first(kind, path):
        return next(i for i, (k, p, _) in enumerate(events) if k == kind and p == path)

    data, data_dir = first("fsync", chunk), first("fsync", chunk.parent)
    new_dirs = [first("fsync", d) for d in (chunk.parent.parent, chunk.parent.parent.parent)]
    record_tmp = next(
        i for i, (k, p, _) in enumerate(events) if k == "fsync" and p.name.startswith(record.name)
    )
    renamed, records_dir = first("replace", record), first("fsync", record.parent)
    assert data < data_dir < record_tmp < renamed < records_dir
    assert max(new_dirs) < renamed  # directories created for the chunk are durable too
    assert not any(exists for _, _, exists in events[: renamed + 1])  # no record before
    assert record.exists()
    assert store.verify() == [k for k in spec.chunks() if k != key]
