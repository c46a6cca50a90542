"""A resumable, verified on-disk sweep: a Zarr group plus one completion record per chunk.

Layout of a working store ``PATH``::

    PATH/zarr.json             group; attrs: format marker, sweep definition, fingerprint
    PATH/mean_velocity/...     the result [m/s]; codecs bytes -> zstd -> crc32c
    PATH/complete/I.J.json     completion record of chunk (I, J) (one per finished chunk)
    PATH.lock                  sidecar lock file while a run uses the store

Why it cannot silently hand back wrong numbers:

* Every chunk of the result carries a crc32c checksum (Zarr v3 codec), so a flipped or
  missing byte fails to decode instead of decoding to -7e12 m/s.
* A chunk's completion record is written only after its data are durable: Zarr writes the
  chunk to a temporary file and renames it; we then fsync the file and its directories,
  hash the bytes read back from disk, and write the record (temporary file, fsync, rename,
  fsync of the directory). A run killed at any instant leaves, for each chunk, either no
  record (recomputed) or a record whose data are on disk.
* The record is one small JSON per chunk holding the chunk's key, its file name, size and
  SHA-256, plus a SHA-256 of those fields themselves. A damaged record therefore either
  fails to parse or fails its own check; a record copied to another chunk names the wrong
  key; a chunk file replaced by another valid chunk fails the size/hash check. One file per
  chunk also means a torn write can never damage the records of other chunks (a single
  shared "done" array could).
* On resume, every chunk with a record is verified: record check, file present, size and
  hash, decode through the crc32c codec, shape, dtype and no NaN. A chunk that fails is
  reported with a ``RuntimeWarning`` naming it, its record is removed and it is computed
  again. The store is created under a temporary name and renamed into place, so a store
  either exists whole or not at all.

``exclusive_lock`` (:mod:`microslip.sweeps.store_lock`) keeps two processes off one store
(``StoreBusyError`` at once), and ``remove_store`` deletes a directory only if it is such
a store and holds nothing else.
"""

from __future__ import annotations

import glob
import hashlib
import json
import os
import re
import shutil
import uuid
import warnings
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from microslip.sweeps.spec import ChunkKey, SweepSpec
from microslip.sweeps.store_lock import StoreBusyError as StoreBusyError
from microslip.sweeps.store_lock import exclusive_lock
from microslip.sweeps.store_lock import lock_path_of as lock_path_of

if TYPE_CHECKING:
    import zarr

# zarr is imported where a store is created or opened: a map computed in memory never
# needs it (0.1-0.2 s of the time to a first result).

RESULT = "mean_velocity"
RECORDS = "complete"
FORMAT_KEY = "microslip_sweep_store"
FORMAT = 2  # 1: the unchecked layout with a boolean "done" array (refused on resume)
_TOP_LEVEL = {"zarr.json", RESULT, RECORDS}
_TMP = re.compile(r".*\.[0-9a-f]{32}\.(partial|tmp)$")  # Zarr's and our temporary files


class StoreMismatchError(ValueError):
    """The store on disk belongs to a different sweep, or is not a microslip sweep store."""


# -- durability helpers ---------------------------------------------------------------------
def _fsync(path: Path) -> None:
    """Flush a file's data, or a directory's entries (a rename in it), to the disk."""
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _fsync_tree(root: Path) -> None:
    for directory, _, files in os.walk(root):
        for name in files:
            _fsync(Path(directory) / name)
        _fsync(Path(directory))


def _digest(fields: dict) -> str:
    return hashlib.sha256(json.dumps(fields, sort_keys=True).encode()).hexdigest()


# -- identification and removal -----------------------------------------------------------------
def is_sweep_store(path: str | Path) -> bool:
    """True if ``path`` is a directory holding a microslip sweep store and nothing else."""
    path = Path(path)
    if path.is_symlink() or not path.is_dir():
        return False
    try:
        attrs = json.loads((path / "zarr.json").read_text())["attributes"]
        if attrs.get(FORMAT_KEY) != FORMAT:
            return False
    except (OSError, ValueError, KeyError, TypeError):
        return False
    for directory, subdirs, files in os.walk(path):
        relative = Path(directory).relative_to(path).parts
        for name in files:
            if not _known_file((*relative, name)):
                return False
        if any((Path(directory) / d).is_symlink() for d in subdirs):
            return False
        if relative and relative[0] not in _TOP_LEVEL:
            return False
    return True


def _known_file(parts: tuple[str, ...]) -> bool:
    name = parts[-1]
    if _TMP.match(name):
        return True
    if len(parts) == 1:
        return name == "zarr.json"
    if parts[0] == RECORDS:
        return len(parts) == 2 and re.fullmatch(r"\d+(\.\d+)*\.json", name) is not None
    if parts[0] == RESULT:
        return parts[1:] == ("zarr.json",) or (
            parts[1] == "c" and all(p.isdigit() for p in parts[2:])
        )
    return False


def remove_store(path: str | Path) -> None:
    """Delete the working store at ``path`` (nothing if it does not exist).

    Refuses (``StoreMismatchError``) anything that is not a microslip sweep store holding
    only its own files, so a user's directory is never deleted; ``StoreBusyError`` if
    another run is using it.
    """
    path = Path(path)
    if not path.exists() and not path.is_symlink():
        return
    with exclusive_lock(path):  # checked under the lock: no run can be adding files
        if not is_sweep_store(path):
            raise StoreMismatchError(
                f"{str(path)!r} is not a microslip sweep store (or holds other files); "
                "not removing it"
            )
        shutil.rmtree(path)
    _fsync(path.parent)


# -- the store -----------------------------------------------------------------------------------
class SweepStore:
    """Open (or create) the verified working store at ``path`` for ``spec``.

    The caller should hold ``exclusive_lock(path)`` while using it (``run_sweep`` does).
    """

    def __init__(self, path: str | Path, spec: SweepSpec) -> None:
        self.path = Path(path)
        self.spec = spec
        if not self.path.exists():
            self._create()
        self.group = self._open()
        # Every chunk must have a file, even one equal to the fill value (not a Zarr default).
        self.array = self.group[RESULT].with_config({"write_empty_chunks": True})
        self.records = self.path / RECORDS
        self._synced_dirs: set[Path] = set()

    def _create(self) -> None:
        """Build the empty store under a temporary name, make it durable, rename it into place."""
        spec = self.spec
        # Leftovers of a run killed while creating the store (we hold the lock: none is live).
        for stale in self.path.parent.glob(f".{glob.escape(self.path.name)}.*.tmp"):
            if _TMP.match(stale.name) and not stale.is_symlink() and stale.is_dir():
                shutil.rmtree(stale, ignore_errors=True)
        import zarr
        from zarr.codecs import Crc32cCodec, ZstdCodec

        tmp = self.path.with_name(f".{self.path.name}.{uuid.uuid4().hex}.tmp")
        try:
            group = zarr.open_group(str(tmp), mode="w")
            group.create_array(
                RESULT, shape=spec.shape, chunks=self._chunk_shape(), dtype="f8",
                fill_value=np.nan, compressors=[ZstdCodec(level=0), Crc32cCodec()],
            )  # fmt: skip
            group.attrs.update(
                {
                    FORMAT_KEY: FORMAT,
                    "sweep_definition": json.dumps(spec.definition(), sort_keys=True),
                    "fingerprint": spec.fingerprint(),
                }
            )
            (tmp / RECORDS).mkdir()
            _fsync_tree(tmp)
            os.rename(tmp, self.path)
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise
        _fsync(self.path.parent)

    def _chunk_shape(self) -> tuple[int, ...]:
        spec = self.spec
        return (*(1 for _ in spec.param_axes), len(spec.forces), spec.amplitude_chunk)

    def _open(self) -> zarr.Group:
        import zarr

        try:
            group = zarr.open_group(str(self.path), mode="r+")
            attrs = group.attrs.asdict()
            stored = json.loads(attrs["sweep_definition"])
            array = group[RESULT]
        except Exception as error:  # any unreadable or foreign store
            raise StoreMismatchError(
                f"{str(self.path)!r} exists but is not a microslip sweep store ({error}); "
                "remove it or choose another output"
            ) from None
        if attrs.get(FORMAT_KEY) != FORMAT:
            raise StoreMismatchError(
                f"{str(self.path)!r} was written by an older microslip without chunk checksums; "
                "remove it or choose another output"
            )
        differing = self.spec.differences(stored)
        if differing:
            raise StoreMismatchError(
                f"{str(self.path)!r} holds a sweep with a different definition "
                f"(differs in: {', '.join(differing)}); refusing to resume into it. "
                "Remove it or choose another output"
            )
        codecs = [codec.get("name") for codec in array.metadata.to_dict()["codecs"]]
        layout = (array.shape, array.chunks, array.dtype, codecs[-1:])
        if layout != (self.spec.shape, self._chunk_shape(), np.dtype("f8"), ["crc32c"]):
            raise StoreMismatchError(
                f"{str(self.path)!r}: the result array has an unexpected layout {layout}; "
                "remove it or choose another output"
            )
        return group

    # -- paths ------------------------------------------------------------------------------
    def chunk_file(self, key: ChunkKey) -> Path:
        """The file holding chunk ``key`` of the result."""
        coords = (*key[:-1], 0, key[-1])
        return self.path / RESULT / self.array.metadata.encode_chunk_key(coords)

    def record_file(self, key: ChunkKey) -> Path:
        """The completion record of chunk ``key``."""
        return self.records / (".".join(str(i) for i in key) + ".json")

    # -- resume -----------------------------------------------------------------------------
    def verify(self, out: np.ndarray | None = None) -> list[ChunkKey]:
        """Check every recorded chunk; return the keys that must be computed.

        A chunk without a record is simply missing. A recorded chunk that fails any check
        gives a ``RuntimeWarning`` naming it and the reason, loses its record, and is
        returned with the missing ones. Verified blocks are copied into ``out`` (the full
        result array) when given.
        """
        todo = []
        for key in self.spec.chunks():
            if not self.record_file(key).exists():
                todo.append(key)
                continue
            block, problem = self._check(key)
            if problem is None:
                if out is not None:
                    out[self.spec.region(key)] = block
                continue
            warnings.warn(
                f"sweep store {self.path}: chunk {key} (amplitudes "
                f"{self.spec.amplitude_slice(key).start}..{self.spec.amplitude_slice(key).stop - 1}"
                f") {problem}; recomputing it",
                RuntimeWarning,
                stacklevel=3,
            )
            self.record_file(key).unlink()
            _fsync(self.records)
            todo.append(key)
        return todo

    def missing(self) -> list[ChunkKey]:
        """Keys of the chunks without a verified completion record (warns about damage)."""
        return self.verify()

    def _check(self, key: ChunkKey) -> tuple[np.ndarray | None, str | None]:
        try:
            record = json.loads(self.record_file(key).read_text())
            fields = {k: v for k, v in record.items() if k != "check"}
            valid = (
                record["check"] == _digest(fields)
                and set(fields) == {"chunk", "file", "bytes", "sha256"}
                and record["chunk"] == list(key)
            )
        except (OSError, ValueError, KeyError, TypeError, AttributeError):
            valid = False
        if not valid:
            return None, "has a damaged completion record"
        path = self.chunk_file(key)
        relative = path.relative_to(self.path)
        try:
            data = path.read_bytes()
        except FileNotFoundError:
            return None, f"is recorded complete but its data file {relative} is missing"
        if len(data) != record["bytes"] or hashlib.sha256(data).hexdigest() != record["sha256"]:
            return None, f"has a damaged data file {relative} (size or checksum mismatch)"
        try:
            block = np.asarray(self.array[self.spec.region(key)])
        except Exception as error:  # crc32c or zstd failure: any decode error means damage
            return None, f"cannot be decoded from {relative} ({type(error).__name__})"
        expected = (
            len(self.spec.forces),
            len(self.spec.amplitudes[self.spec.amplitude_slice(key)]),
        )
        if block.shape != expected or block.dtype != np.float64:
            return None, f"has shape {block.shape} / dtype {block.dtype}, expected {expected} f8"
        if np.isnan(block).any():
            return None, "holds NaN where values were computed"
        return block, None

    # -- writing ----------------------------------------------------------------------------
    def write(self, key: ChunkKey, block: np.ndarray) -> None:
        """Write chunk ``key`` durably, then record its completion durably."""
        self.array[self.spec.region(key)] = block
        path = self.chunk_file(key)
        _fsync(path)
        self._sync_parents(path.parent)
        data = path.read_bytes()
        fields = {
            "chunk": list(key),
            "file": path.relative_to(self.path).as_posix(),
            "bytes": len(data),
            "sha256": hashlib.sha256(data).hexdigest(),
        }
        record = self.record_file(key)
        tmp = record.with_name(f"{record.name}.{uuid.uuid4().hex}.tmp")
        with open(tmp, "w") as handle:
            json.dump({**fields, "check": _digest(fields)}, handle, sort_keys=True)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, record)
        _fsync(self.records)

    def _sync_parents(self, directory: Path) -> None:
        """fsync the chunk's directory (its rename) and, once, each new parent up to the array."""
        _fsync(directory)
        top = self.path / RESULT
        while directory != top and directory not in self._synced_dirs:
            self._synced_dirs.add(directory)
            directory = directory.parent
            _fsync(directory)

    def result(self) -> np.ndarray:
        """The whole result array, read through the checksums [m/s]."""
        return np.asarray(self.array[...])
