"""Safe output: a file appears complete or not at all, and nothing is lost on the way.

- Every output is written to a temporary name in its target directory, then renamed
  into place, so a crash, Ctrl-C or a full disk never leaves a partial file under the
  final name (the temporary is removed).
- An existing output is replaced only with ``overwrite=True``; a directory is replaced
  only if microslip wrote it (a Zarr group whose attributes say so), never a foreign one.
- An existing directory is replaced by renaming it aside, renaming the new one in, and
  only then deleting the old one: at every instant one complete copy exists.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import tempfile
import uuid
from collections.abc import Callable, Iterator
from pathlib import Path

from microslip.metadata import cf_attributes

DATASET_SUFFIXES = (".nc", ".csv", ".zarr")
PLOT_SUFFIXES = (".png", ".pdf", ".svg")

__all__ = [
    "DATASET_SUFFIXES",
    "PLOT_SUFFIXES",
    "OutputError",
    "OutputExistsError",
    "atomic_path",
    "check_writable",
    "is_microslip_output",
    "write_atomically",
    "write_dataset",
]


class OutputError(ValueError):
    """An output cannot be written (one line naming the path and the reason)."""


class OutputExistsError(OutputError):
    """The output exists and may not be replaced."""


def is_microslip_output(path: str | Path) -> bool:
    """True if ``path`` is a directory holding a Zarr group written by microslip.

    Recognised by the group attributes (``source`` = "microslip ..." or the older
    ``microslip_version``) in ``zarr.json`` (Zarr v3) or ``.zattrs`` (Zarr v2).
    """
    path = Path(path)
    if not path.is_dir() or path.is_symlink():
        return False
    for meta_name, v3 in (("zarr.json", True), (".zattrs", False)):
        meta = path / meta_name
        if not meta.is_file():
            continue
        try:
            data = json.loads(meta.read_text())
        except (OSError, ValueError):
            return False
        attrs = data.get("attributes", {}) if v3 else data
        if not isinstance(attrs, dict):
            return False
        source = attrs.get("source")
        return (isinstance(source, str) and source.startswith("microslip")) or (
            "microslip_version" in attrs
        )
    return False


def _refuse_existing(path: Path, overwrite: bool) -> None:
    if not os.path.lexists(path):
        return
    if not overwrite:
        raise OutputExistsError(
            f"output {str(path)!r} exists; pass --overwrite (Python: overwrite=True) to replace it"
        )
    if path.is_dir() and not is_microslip_output(path):
        raise OutputExistsError(
            f"output {str(path)!r} is a directory that microslip did not write; "
            "refusing to replace it (even with --overwrite); remove it yourself or choose another"
        )


def check_writable(
    path: str | Path, suffixes: tuple[str, ...] | None = None, *, overwrite: bool = True
) -> Path:
    """Fail early (``OutputError``) if ``path`` cannot be written or may not be replaced.

    Checks the suffix, that the directory exists and accepts a new file, and (unless
    ``overwrite``) that ``path`` does not exist yet. A directory at ``path`` is replaceable
    only if it is a microslip Zarr output and ``overwrite`` is true.
    """
    path = Path(path)
    if suffixes is not None and path.suffix.lower() not in suffixes:
        raise OutputError(f"output {str(path)!r}: suffix must be one of {', '.join(suffixes)}")
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise OutputError(f"output {str(path)!r}: directory {str(parent)!r} does not exist")
    try:  # os.access is not enough (read-only mounts, /proc, root); try a real file
        handle, probe = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".probe", dir=parent)
        os.close(handle)
        os.unlink(probe)
    except OSError as error:
        raise OutputError(
            f"output {str(path)!r}: directory {str(parent)!r} is not writable ({error.strerror})"
        ) from None
    if path.is_dir() and path.suffix.lower() != ".zarr":
        raise OutputError(f"output {str(path)!r} is a directory")
    _refuse_existing(path, overwrite)
    return path


def _install(tmp: Path, path: Path, overwrite: bool) -> None:
    """Move the finished ``tmp`` to ``path``, checking again what is there now."""
    _refuse_existing(path, overwrite)  # something may have appeared while we computed
    if not os.path.lexists(path):
        if tmp.is_dir():
            os.rename(tmp, path)
            return
        try:  # link() never replaces: no race with a file created meanwhile
            os.link(tmp, path)
        except FileExistsError:
            raise OutputExistsError(
                f"output {str(path)!r} appeared while computing; not replaced"
            ) from None
        except OSError:  # no hard links on this file system
            os.replace(tmp, path)
            return
        os.unlink(tmp)
        return
    if not tmp.is_dir() and not path.is_dir():
        os.replace(tmp, path)  # atomic: the old file stays complete until this instant
        return
    # A directory is involved: rename the old one aside, the new one in, then delete.
    aside = path.with_name(f".{path.name}.old-{uuid.uuid4().hex[:8]}")
    os.rename(path, aside)
    try:
        os.rename(tmp, path)
    except BaseException:
        os.rename(aside, path)
        raise
    if aside.is_dir() and not aside.is_symlink():
        shutil.rmtree(aside, ignore_errors=True)
    else:
        aside.unlink()


def _low_space(directory: Path) -> str:
    """A hint when the disk is (nearly) full: HDF5 says only "HDF error"."""
    try:
        free = shutil.disk_usage(directory).free
    except OSError:
        return ""
    return f" ({free} bytes free in {str(directory)!r}: disk full?)" if free < 1 << 20 else ""


@contextlib.contextmanager
def atomic_path(path: str | Path, *, overwrite: bool = True) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; move it into place only on success.

    On any exception (also ``KeyboardInterrupt``) the temporary is removed and ``path``
    is left as it was. ``OSError`` while writing becomes ``OutputError`` (one line).
    """
    path = Path(path)
    parent = path.parent if str(path.parent) else Path(".")
    tmp_path = parent / f".{path.name}.{uuid.uuid4().hex[:8]}.tmp"
    try:
        try:
            yield tmp_path
            _install(tmp_path, path, overwrite)
        except OSError as error:  # full disk, read-only or vanished directory, ...
            reason = error.strerror or str(error) or type(error).__name__
            raise OutputError(f"cannot write {str(path)!r}: {reason}{_low_space(parent)}") from None
        except RuntimeError as error:  # netCDF4/HDF5 report a full disk as "HDF error"
            raise OutputError(f"cannot write {str(path)!r}: {error}{_low_space(parent)}") from None
    finally:
        if tmp_path.is_dir() and not tmp_path.is_symlink():
            shutil.rmtree(tmp_path, ignore_errors=True)
        elif os.path.lexists(tmp_path):
            with contextlib.suppress(OSError):
                tmp_path.unlink()


def write_atomically(
    path: str | Path, writer: Callable[[Path], None], *, overwrite: bool = True
) -> Path:
    """Call ``writer(tmp)`` and move ``tmp`` to ``path`` (see :func:`atomic_path`)."""
    with atomic_path(path, overwrite=overwrite) as tmp:
        writer(tmp)
    return Path(path)


def with_cf_attributes(ds):
    """A shallow copy of ``ds`` with the CF global attributes it lacks (Conventions, ...)."""
    out = ds.copy(deep=False)
    out.attrs = dict(ds.attrs)
    for key, value in cf_attributes(ds.attrs.get("title", "microslip output")).items():
        out.attrs.setdefault(key, value)
    return out


def write_dataset(ds, path: str | Path, *, overwrite: bool = True) -> Path:
    """Write an ``xarray.Dataset`` to .nc (NetCDF-4), .zarr or .csv, atomically.

    NetCDF and Zarr files get the CF global attributes the dataset lacks
    (``Conventions``, ``title``, ``source``, ``references``, ``history``). CSV columns
    carry their units in the header, e.g. ``x [m]``. ``overwrite=False`` refuses an
    existing ``path``; a directory microslip did not write is never replaced.
    """
    path = check_writable(path, DATASET_SUFFIXES, overwrite=overwrite)
    suffix = path.suffix.lower()
    if suffix == ".nc":
        ds = with_cf_attributes(ds)
        return write_atomically(
            path, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4"), overwrite=overwrite
        )
    if suffix == ".zarr":
        ds = with_cf_attributes(ds)
        return write_atomically(
            path,
            lambda tmp: ds.to_zarr(tmp, mode="w", consolidated=False),
            overwrite=overwrite,
        )

    def write_csv(tmp: Path) -> None:
        dims = {d for name in ds.data_vars for d in ds[name].dims}
        if "time" in dims:
            dim = "time"  # a trajectory: the time series; switching instants stay in .nc
        elif len(dims) == 1:
            (dim,) = dims
        else:
            raise OutputError(f"CSV output needs one dimension, got {sorted(dims)}; use .nc")
        columns = [v for v in ds.data_vars if ds[v].dims == (dim,)]
        frame = ds[columns].to_dataframe()
        frame.index.name = f"{dim} [{ds[dim].attrs.get('units', '')}]"
        frame.columns = [f"{name} [{ds[name].attrs.get('units', '')}]" for name in columns]
        frame.to_csv(tmp)

    return write_atomically(path, write_csv, overwrite=overwrite)
