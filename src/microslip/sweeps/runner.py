"""Running a sweep's chunks: in-process (all cores) or on a Dask cluster, with progress."""

from __future__ import annotations

import contextlib
import os
import sys
import threading
from collections import deque
from collections.abc import Iterator
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from microslip.sweeps.compute import compute_chunk, compute_chunks, shares_runs, tape_order
from microslip.sweeps.cost import LOCAL_BATCH
from microslip.sweeps.dataset import sweep_dataset
from microslip.sweeps.spec import SweepSpec
from microslip.sweeps.store import SweepStore, exclusive_lock

if TYPE_CHECKING:
    import xarray as xr

CONNECT_TIMEOUT_S = 5.0


def max_workers() -> int:
    """Most local Dask workers accepted: 4 per CPU. The chunks are CPU-bound, so more
    workers than CPUs gain nothing, and each worker process costs ~100 MB; a million
    of them hung the machine."""
    return 4 * (os.cpu_count() or 1)


def check_workers(workers: object) -> int | None:
    """``workers`` as an int in [1, :func:`max_workers`], or None (``ValueError``)."""
    if workers is None:
        return None
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise ValueError(f"workers must be an integer >= 1, got {workers!r}")
    if workers > max_workers():
        raise ValueError(
            f"workers={workers!r} is more than {max_workers()} (4 per CPU of this machine)"
        )
    return int(workers)


def check_store_path(store: str | Path) -> Path:
    """The store's path; ``ValueError`` if its parent directory does not exist (a typo in
    the path should not silently create directories)."""
    path = Path(store)
    if not str(store) or not path.parent.is_dir():
        raise ValueError(f"store {str(store)!r}: directory {str(path.parent)!r} does not exist")
    return path


@contextlib.contextmanager
def dask_client(scheduler: str | None, workers: int | None) -> Iterator[object | None]:
    """A ``distributed.Client``: to ``scheduler`` if given, else a local cluster of
    ``workers`` processes, else None (run in-process)."""
    if scheduler is None and workers is None:
        yield None
        return
    from distributed import Client, LocalCluster

    if scheduler is not None:
        try:
            client = Client(scheduler, timeout=f"{CONNECT_TIMEOUT_S}s")
        except (OSError, TimeoutError, ValueError) as error:
            raise ConnectionError(
                f"cannot reach Dask scheduler {scheduler!r} within {CONNECT_TIMEOUT_S:g} s: {error}"
            ) from None
        with client:
            yield client
        return
    with (
        LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
            env={"NUMBA_NUM_THREADS": str(worker_threads(workers))},
        ) as cluster,
        Client(cluster) as client,
    ):  # fmt: skip
        yield client


def worker_threads(workers: int) -> int:
    """Kernel threads of each of ``workers`` local Dask worker processes: this process's
    (:func:`~microslip.integrators.threads.thread_count`) shared out, at least 1. Each
    worker's kernels would otherwise start a thread per CPU, ``workers`` times too many."""
    from microslip.integrators.threads import thread_count

    return max(1, thread_count() // max(1, int(workers)))


def _progress(total: int, initial: int, show: bool):
    from tqdm import tqdm

    return tqdm(
        total=total, initial=initial, unit="chunk", desc="sweep", disable=not show,
        file=sys.stderr, dynamic_ncols=True,
    )  # fmt: skip


def _advance(bar, chunks: int):
    """A compute call's ``progress`` (:data:`~microslip.sweeps.compute.Progress`) for a
    batch of ``chunks`` chunks on ``bar``: the fraction done moves the bar by that many
    chunks. Called from the kernels' threads, so under a lock; None for a hidden bar."""
    if bar.disable:
        return None
    lock = threading.Lock()

    def progress(fraction: float) -> None:
        with lock:
            bar.update(fraction * chunks)

    return progress


def _checked(spec: SweepSpec, key, block) -> np.ndarray:
    """``block`` as the chunk's float64 array; RuntimeError if it has the wrong shape or NaN."""
    block = np.asarray(block)
    expected = (len(spec.forces), len(spec.amplitudes[spec.amplitude_slice(key)]))
    if block.shape != expected or block.dtype != np.float64:
        raise RuntimeError(
            f"chunk {key} came back with shape {block.shape} / dtype {block.dtype}, "
            f"expected {expected} float64"
        )
    if np.isnan(block).any():  # a computed mean velocity is a number or inf, never NaN
        raise RuntimeError(f"chunk {key} holds {int(np.isnan(block).sum())} NaN values")
    return block


# In-process, time chunks are computed in batches of up to LOCAL_BATCH chunks (why: at
# its definition in cost.py) and of at most this many lanes in all (~190 B each: the
# in-memory chunk cap), so that batching never holds more than one large chunk's buffers.
BATCH_LANES = 2**18

# At most this many bytes of finished chunks wait for the store's writer thread: where the
# chunks come faster than the disk takes them (fsyncs), the computation waits instead of
# the queue growing with the map (an 8192 x 8192 steady map queued ~0.3 of its result).
MAX_PENDING_WRITE_BYTES = 32 * 2**20


def _local_batches(spec: SweepSpec, keys: list) -> Iterator[list]:
    """``keys`` in the batches the in-process loop computes together: single keys, except
    time chunks, up to LOCAL_BATCH of them and BATCH_LANES lanes (a chunk of more is a
    batch of its own)."""
    if not shares_runs(spec):
        yield from ([key] for key in keys)
        return
    batch: list = []
    lanes = 0
    for key in sorted(keys, key=tape_order(spec)):
        block = spec.amplitude_slice(key)
        size = len(spec.forces) * (block.stop - block.start)
        if batch and (len(batch) == LOCAL_BATCH or lanes + size > BATCH_LANES):
            yield batch
            batch, lanes = [], 0
        batch.append(key)
        lanes += size
    if batch:
        yield batch


def run_sweep(
    spec: SweepSpec,
    *,
    store: str | Path | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool = False,
) -> xr.Dataset:
    """Compute every missing chunk of ``spec`` and return the result as a Dataset.

    With ``store``, chunks are written to that Zarr store as they finish, each with a
    checksum and a completion record written once its data are durable; the store is
    locked (``exclusive_lock``) for the whole run, so a second run on it fails at once
    with ``StoreBusyError``. A rerun with the same spec verifies every finished chunk,
    recomputes damaged ones (``RuntimeWarning`` naming each) and computes the rest; the
    result equals an uninterrupted run bit for bit. ``progress`` shows a bar with ETA on
    standard error. Before returning, every point is checked to have been computed (no
    NaN): a chunk that comes back with NaN raises ``RuntimeError``. ``workers`` must
    be in [1, :func:`max_workers`] and the store's parent directory must exist
    (``ValueError`` before anything starts).
    """
    workers = check_workers(workers)
    if store is not None:
        store = check_store_path(store)
    with contextlib.ExitStack() as stack:
        sweep_store = None
        if store is not None:
            stack.enter_context(exclusive_lock(store))  # before connecting: busy fails at once
        # Connect first: a scheduler that cannot be reached leaves no store behind.
        client = stack.enter_context(dask_client(scheduler, workers))
        result = np.full(spec.shape, np.nan)
        if store is not None:
            sweep_store = SweepStore(store, spec)
            todo = sweep_store.verify(out=result)
        else:
            todo = list(spec.chunks())
        done = set(spec.chunks()) - set(todo)
        # One writer thread: the fsyncs of chunk k (milliseconds each on some disks) overlap
        # the computation of chunk k+1. On the way out (Ctrl-C included) pending writes finish.
        writer = stack.enter_context(ThreadPoolExecutor(max_workers=1))
        written: deque[Future] = deque()

        def durable(key, block):
            sweep_store.write(key, block)
            return key

        def collect(wait: bool) -> None:  # a failed write (full disk) surfaces here
            while written and (wait or written[0].done()):
                done.add(written.popleft().result())

        def save(key, block):
            block = _checked(spec, key, block)
            result[spec.region(key)] = block
            if sweep_store is None:
                done.add(key)
            else:
                written.append(writer.submit(durable, key, block))
                collect(wait=False)
                while len(written) > max(1, MAX_PENDING_WRITE_BYTES // max(1, block.nbytes)):
                    done.add(written.popleft().result())  # the oldest write, waited for

        with _progress(spec.n_chunks, spec.n_chunks - len(todo), progress) as bar:
            if client is None:
                for batch in _local_batches(spec, todo):
                    # The bar moves as the batch's set-ups end (a long chunk's too), and
                    # stands on the chunks saved once the batch is done.
                    before = bar.n
                    progress = _advance(bar, len(batch))
                    if len(batch) > 1:
                        blocks = compute_chunks(spec, batch, progress)
                    else:
                        blocks = [compute_chunk(spec, batch[0], progress)]
                    for key, block in zip(batch, blocks, strict=True):
                        save(key, block)
                    bar.n = before + len(batch)
                    bar.refresh()
            elif todo:
                from distributed import as_completed

                futures = client.map(compute_chunk, [spec] * len(todo), todo, pure=False)
                key_of = {future.key: key for future, key in zip(futures, todo, strict=True)}
                for future in as_completed(futures):
                    save(key_of[future.key], future.result())
                    bar.update()
            collect(wait=True)
    not_done = spec.n_chunks - len(done)
    missing = _count_nan(result)
    if not_done or missing:
        raise RuntimeError(
            f"sweep incomplete: {not_done} chunks and {missing} points were not computed"
        )
    return sweep_dataset(spec, result)


def _count_nan(values: np.ndarray) -> int:
    """The NaN values in ``values``, counted a slab at a time: a boolean mask of the whole
    result would add an eighth of it to the run's peak memory."""
    flat = values.reshape(-1)
    slab = 2**20
    return sum(int(np.isnan(flat[i : i + slab]).sum()) for i in range(0, flat.size, slab))
