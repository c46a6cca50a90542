"""The sidecar lock that keeps two processes off one sweep store.

``exclusive_lock(PATH)`` holds a non-blocking exclusive ``flock`` on ``PATH.lock`` (next
to the store directory ``PATH``, see :mod:`microslip.sweeps.store`) for a ``with`` block
and raises ``StoreBusyError`` at once when another run holds it.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
from collections.abc import Iterator
from pathlib import Path


class StoreBusyError(ValueError):
    """Another process is using the store (its lock is held)."""


def lock_path_of(path: str | Path) -> Path:
    """The sidecar lock file of ``path``: ``<path>.lock``."""
    path = Path(path)
    return path.with_name(path.name + ".lock")


@contextlib.contextmanager
def exclusive_lock(path: str | Path) -> Iterator[Path]:
    """Hold a non-blocking exclusive ``flock`` on ``<path>.lock`` for the ``with`` block.

    The lock file is created if needed and removed on exit. Raises ``StoreBusyError``
    at once if another process (or another ``exclusive_lock`` on the same path in this
    process: the lock is not re-entrant) holds it. The kernel drops the lock when its
    holder dies, so a killed run never leaves a store locked.
    """
    lock_path = lock_path_of(path)
    while True:
        try:
            fd = os.open(lock_path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as error:
            raise ValueError(f"cannot create lock file {lock_path}: {error.strerror}") from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise StoreBusyError(
                f"another microslip run is using {path} (lock {lock_path} is held); "
                "wait for it to finish or choose another output"
            ) from None
        except OSError as error:
            os.close(fd)
            raise ValueError(f"cannot lock {lock_path}: {error.strerror}") from None
        # The previous holder may have removed the file between our open and our flock:
        # we would then hold a lock on an orphan while a third process locks the new file.
        try:
            on_disk = os.stat(lock_path)
            mine = os.fstat(fd)
            if (on_disk.st_dev, on_disk.st_ino) == (mine.st_dev, mine.st_ino):
                break
        except FileNotFoundError:
            pass
        os.close(fd)
    try:
        yield lock_path
    finally:
        # Removed while still held, so nobody can lock this file after we let it go.
        with contextlib.suppress(FileNotFoundError):
            lock_path.unlink()
        os.close(fd)
