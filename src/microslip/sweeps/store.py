"""A resumable on-disk sweep: a Zarr group with the result and one "done" flag per chunk.

Zarr writes every chunk file atomically (temporary file, then rename), and a chunk's
flag is set only after its data are written, so a sweep killed at any instant loses at
most the chunks in flight. The group remembers the sweep definition; resuming with a
different definition is refused.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import zarr

from microslip.sweeps.spec import ChunkKey, SweepSpec

RESULT = "mean_velocity"
DONE = "done"


class StoreMismatchError(ValueError):
    """The store on disk belongs to a different sweep."""


class SweepStore:
    """Open (or create) the working store at ``path`` for ``spec``."""

    def __init__(self, path: str | Path, spec: SweepSpec) -> None:
        self.path = Path(path)
        self.spec = spec
        if self.path.exists():
            self.group = self._open_existing()
        else:
            self.group = self._create()

    def _create(self) -> zarr.Group:
        group = zarr.open_group(str(self.path), mode="w")
        spec = self.spec
        chunk_shape = (*(1 for _ in spec.param_axes), len(spec.forces), spec.amplitude_chunk)
        group.create_array(
            RESULT, shape=spec.shape, chunks=chunk_shape, dtype="f8", fill_value=np.nan
        )
        group.create_array(
            DONE, shape=spec.chunk_grid, chunks=(1,) * len(spec.chunk_grid), dtype="bool",
            fill_value=False,
        )  # fmt: skip
        group.attrs["sweep_definition"] = json.dumps(spec.definition(), sort_keys=True)
        group.attrs["fingerprint"] = spec.fingerprint()
        return group

    def _open_existing(self) -> zarr.Group:
        try:
            group = zarr.open_group(str(self.path), mode="r+")
            stored = json.loads(group.attrs["sweep_definition"])
            group[RESULT], group[DONE]
        except Exception as error:  # any unreadable or foreign store
            raise StoreMismatchError(
                f"{str(self.path)!r} exists but is not a microslip sweep store ({error}); "
                "remove it or choose another output"
            ) from None
        differing = self.spec.differences(stored)
        if differing:
            raise StoreMismatchError(
                f"{str(self.path)!r} holds a sweep with a different definition "
                f"(differs in: {', '.join(differing)}); refusing to resume into it. "
                "Remove it or choose another output"
            )
        return group

    def missing(self) -> list[ChunkKey]:
        done = np.asarray(self.group[DONE][...])
        return [key for key in self.spec.chunks() if not done[key]]

    def write(self, key: ChunkKey, block: np.ndarray) -> None:
        self.group[RESULT][self.spec.region(key)] = block
        self.group[DONE][key] = True

    def result(self) -> np.ndarray:
        return np.asarray(self.group[RESULT][...])
