"""Running a sweep's chunks: in-process (all cores) or on a Dask cluster, with progress."""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from microslip.sweeps.compute import compute_chunk
from microslip.sweeps.dataset import sweep_dataset
from microslip.sweeps.spec import SweepSpec
from microslip.sweeps.store import SweepStore

CONNECT_TIMEOUT_S = 5.0


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
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        Client(cluster) as client,
    ):
        yield client


def _progress(total: int, initial: int, show: bool):
    from tqdm import tqdm

    return tqdm(
        total=total, initial=initial, unit="chunk", desc="sweep", disable=not show,
        file=sys.stderr, dynamic_ncols=True,
    )  # fmt: skip


def run_sweep(
    spec: SweepSpec,
    *,
    store: str | Path | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool = False,
):
    """Compute every missing chunk of ``spec`` and return the result as a Dataset.

    With ``store``, chunks are written to that Zarr store as they finish; a rerun with
    the same spec computes only the chunks not yet there. ``progress`` shows a bar
    with ETA on standard error.
    """
    if workers is not None and (isinstance(workers, bool) or int(workers) < 1):
        raise ValueError(f"workers must be an integer >= 1, got {workers!r}")
    # Connect first: a scheduler that cannot be reached leaves no store behind.
    with dask_client(scheduler, workers) as client:
        sweep_store = SweepStore(store, spec) if store is not None else None
        todo = sweep_store.missing() if sweep_store is not None else list(spec.chunks())
        result = None if sweep_store is not None else np.full(spec.shape, np.nan)

        def save(key, block):
            if sweep_store is not None:
                sweep_store.write(key, block)
            else:
                result[spec.region(key)] = block

        with _progress(spec.n_chunks, spec.n_chunks - len(todo), progress) as bar:
            if client is None:
                for key in todo:
                    save(key, compute_chunk(spec, key))
                    bar.update()
            elif todo:
                from distributed import as_completed

                futures = client.map(compute_chunk, [spec] * len(todo), todo, pure=False)
                key_of = {future.key: key for future, key in zip(futures, todo, strict=True)}
                for future in as_completed(futures):
                    save(key_of[future.key], future.result())
                    bar.update()
    values = sweep_store.result() if sweep_store is not None else result
    return sweep_dataset(spec, values)
