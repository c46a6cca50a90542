"""Atomic output: a file appears complete or not at all."""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

DATASET_SUFFIXES = (".nc", ".csv", ".zarr")


def check_writable(path: str | Path, suffixes: tuple[str, ...] | None = None) -> Path:
    """Fail early (``ValueError``) if ``path`` cannot be written or has a bad suffix."""
    path = Path(path)
    if suffixes is not None and path.suffix.lower() not in suffixes:
        raise ValueError(f"output {str(path)!r}: suffix must be one of {', '.join(suffixes)}")
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise ValueError(f"output {str(path)!r}: directory {str(parent)!r} does not exist")
    try:  # os.access is not enough (read-only mounts, /proc, root); try a real file
        handle, probe = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".probe", dir=parent)
        os.close(handle)
        os.unlink(probe)
    except OSError as error:
        raise ValueError(
            f"output {str(path)!r}: directory {str(parent)!r} is not writable ({error.strerror})"
        ) from None
    if path.is_dir() and path.suffix.lower() != ".zarr":
        raise ValueError(f"output {str(path)!r} is a directory")
    return path


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; move it into place only on success."""
    path = Path(path)
    handle, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent or ".")
    os.close(handle)
    os.unlink(tmp)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        if path.is_dir():
            shutil.rmtree(path)
        os.replace(tmp_path, path)
    finally:
        if tmp_path.is_dir():
            shutil.rmtree(tmp_path, ignore_errors=True)
        elif tmp_path.exists():
            tmp_path.unlink()


def write_atomically(path: str | Path, writer: Callable[[Path], None]) -> Path:
    """Call ``writer(tmp)`` and move ``tmp`` to ``path``."""
    with atomic_path(path) as tmp:
        writer(tmp)
    return Path(path)


def write_dataset(ds, path: str | Path) -> Path:
    """Write an ``xarray.Dataset`` to .nc (NetCDF-4), .zarr or .csv, atomically.

    CSV columns carry their units in the header, e.g. ``x [m]``.
    """
    path = check_writable(path, DATASET_SUFFIXES)
    suffix = path.suffix.lower()
    if suffix == ".nc":
        return write_atomically(path, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4"))
    if suffix == ".zarr":
        return write_atomically(path, lambda tmp: ds.to_zarr(tmp, mode="w", consolidated=False))

    def write_csv(tmp: Path) -> None:
        dims = {d for name in ds.data_vars for d in ds[name].dims}
        if "time" in dims:
            dim = "time"  # a trajectory: the time series; switching instants stay in .nc
        elif len(dims) == 1:
            (dim,) = dims
        else:
            raise ValueError(f"CSV output needs one dimension, got {sorted(dims)}; use .nc")
        columns = [v for v in ds.data_vars if ds[v].dims == (dim,)]
        frame = ds[columns].to_dataframe()
        frame.index.name = f"{dim} [{ds[dim].attrs.get('units', '')}]"
        frame.columns = [f"{name} [{ds[name].attrs.get('units', '')}]" for name in columns]
        frame.to_csv(tmp)

    return write_atomically(path, write_csv)
