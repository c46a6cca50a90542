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
    "OutputBatch",
    "OutputError",
    "OutputExistsError",
    "atomic_path",
    "check_output_name",
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


# The files a Zarr store writes itself (v3 and v2 metadata); a chunk lives in an array's
# directory (v3: under ``c/``; v2: a name of digits and separators).
_ZARR_METADATA = {"zarr.json", ".zattrs", ".zgroup", ".zarray", ".zmetadata"}


def _is_chunk_name(name: str) -> bool:
    return bool(name) and all(part.isdigit() for part in name.split("."))


def _is_array(node: Path) -> bool:
    if (node / ".zarray").is_file():
        return True
    try:
        return json.loads((node / "zarr.json").read_text()).get("node_type") == "array"
    except (OSError, ValueError, AttributeError):
        return False


def _holds_only_chunks(directory: Path) -> bool:
    for entry in os.scandir(directory):
        if entry.is_symlink() or not _is_chunk_name(entry.name):
            return False
        if entry.is_dir() and not _holds_only_chunks(Path(entry.path)):
            return False
    return True


def _holds_only_store_files(node: Path) -> bool:
    """True if every entry under the group or array ``node`` is Zarr metadata or a chunk.

    ``--overwrite`` deletes the old store: a file the user put there (notes, other
    results) must not go with it.
    """
    array = _is_array(node)
    for entry in os.scandir(node):
        path = Path(entry.path)
        if entry.is_symlink():
            return False
        if entry.is_file():
            if entry.name in _ZARR_METADATA or (array and _is_chunk_name(entry.name)):
                continue
            return False
        if not entry.is_dir():
            return False
        if array and (entry.name == "c" or _is_chunk_name(entry.name)):
            if not _holds_only_chunks(path):  # v3 <array>/c/i/j, v2 <array>/i/j
                return False
        elif not any((path / meta).is_file() for meta in _ZARR_METADATA):
            return False
        elif not _holds_only_store_files(path):
            return False
    return True


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
    if path.is_dir() and not _holds_only_store_files(path):
        raise OutputExistsError(
            f"output {str(path)!r} holds files that are not part of its Zarr store; "
            "refusing to replace it (even with --overwrite); move them out or choose another"
        )


def check_output_name(path: str | Path) -> Path:
    """``OutputError`` for an empty path, or a NetCDF path netCDF4/HDF5 cannot create.

    HDF5 refuses a backslash anywhere in the path of a file it creates (it fails with
    "Permission denied" only when writing, after the computation).
    """
    if not str(path).strip():
        raise OutputError("output path is empty")
    path = Path(path)
    if path.suffix.lower() == ".nc" and "\\" in str(path.absolute()):
        raise OutputError(
            f"output {str(path)!r}: NetCDF files cannot be created under a path with a "
            "backslash; choose another name"
        )
    return path


def check_writable(
    path: str | Path, suffixes: tuple[str, ...] | None = None, *, overwrite: bool = True
) -> Path:
    """Fail early (``OutputError``) if ``path`` cannot be written or may not be replaced.

    Checks the suffix, that the directory exists and accepts a new file, and (unless
    ``overwrite``) that ``path`` does not exist yet. A directory at ``path`` is replaceable
    only if it is a microslip Zarr output and ``overwrite`` is true.
    """
    path = check_output_name(path)
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


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    elif os.path.lexists(path):
        with contextlib.suppress(OSError):
            path.unlink()


class OutputBatch:
    """The outputs of one run: written to temporaries, moved into place together.

    :meth:`temporary` gives a hidden name beside a target (same suffix, so writers that
    pick the format from it still work); :meth:`commit` moves every finished temporary
    to its target (:attr:`written` lists them). Leaving the ``with`` block by an
    exception (also ``KeyboardInterrupt``) removes every temporary not yet moved, so an
    interrupted run leaves none of its outputs, and the old files stay as they were.
    """

    def __init__(self, *, overwrite: bool = False) -> None:
        self.overwrite = overwrite
        self.written: list[Path] = []
        self._staged: list[tuple[Path, Path]] = []

    def temporary(self, target: str | Path) -> Path:
        """A fresh temporary path for ``target`` (moved there by :meth:`commit`)."""
        target = Path(target)
        tmp = target.with_name(f".{target.stem}.{uuid.uuid4().hex[:8]}.partial{target.suffix}")
        return self.stage(tmp, target)

    def write(self, target: str | Path, writer: Callable[[Path], object]) -> Path:
        """Call ``writer(tmp)`` for a fresh temporary of ``target``; errors name ``target``."""
        tmp = self.temporary(target)
        try:
            writer(tmp)
        except OutputError as error:  # written to tmp, but the user knows only the target
            raise type(error)(str(error).replace(str(tmp), str(target))) from None
        except OSError as error:
            reason = error.strerror or str(error) or type(error).__name__
            raise OutputError(f"cannot write {str(target)!r}: {reason}") from None
        return Path(target)

    def stage(self, tmp: str | Path, target: str | Path) -> Path:
        """Register a finished (or to be finished) ``tmp`` to move to ``target``."""
        self._staged.append((Path(tmp), Path(target)))
        return Path(tmp)

    def commit(self) -> list[Path]:
        """Move every temporary to its target; returns the targets written."""
        while self._staged:
            tmp, target = self._staged[0]
            try:
                _install(tmp, target, self.overwrite)
            except OSError as error:
                reason = error.strerror or str(error) or type(error).__name__
                raise OutputError(f"cannot write {str(target)!r}: {reason}") from None
            self._staged.pop(0)
            self.written.append(target)
        return list(self.written)

    def discard(self) -> None:
        """Remove every temporary not moved yet."""
        for tmp, _ in self._staged:
            _remove(tmp)
        self._staged.clear()

    def __enter__(self) -> OutputBatch:
        return self

    def __exit__(self, *exc_info) -> None:
        self.discard()
