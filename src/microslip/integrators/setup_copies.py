"""Copies of a normal set-up, so that a few set-ups with many lanes keep every thread busy.

The lane kernels (:mod:`~microslip.integrators.shared_lanes`,
:mod:`~microslip.integrators.spring_lanes`, :mod:`~microslip.integrators.mindlin_lanes`)
run their normal set-ups in parallel, one set-up per range of
:func:`~microslip.integrators.threads.run_ranges`. A run of fewer set-ups than threads
left threads idle: a curve v(F) at one amplitude, or a wide force axis in a store's
chunks of 4096 lanes (one amplitude each), ran on one thread.

A lane's arithmetic depends only on its own parameters and its set-up's tape, and the
tape is the same bits wherever it is integrated. So a set-up can run as k copies, each
integrating the tape itself and taking every k-th of the set-up's lanes: every lane gets
the same bits, in about 1/k of the time on k threads, for k tapes' work in parallel. A
copy keeps at least :data:`MIN_LANES_PER_COPY` lanes, so that its own tape stays a small
part of its work.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from microslip.integrators import threads

__all__ = ["MIN_LANES_PER_COPY", "SetupCopies"]

# A copy's lanes, at least: a rigid lane costs ~2 ns per piece and a stepped tape ~170 ns
# per piece on the project's 2-core machine (2026-11-27), so a copy of 64 lanes still
# spends at least as long on its lanes as on its tape.
MIN_LANES_PER_COPY = 64


@dataclass(frozen=True)
class SetupCopies:
    """The copies of a run's G set-ups: ``copies`` of each (1: the set-ups themselves).

    Copy j of set-up g is copy g·copies + j; ``source`` (G·copies,) is the set-up of each
    copy, ``lane_copy`` (L,) the copy of each lane (a lane's rank among its set-up's lanes,
    modulo ``copies``, picks the copy, so each copy spans the set-up's forces), and
    ``order`` (L,) the lanes sorted by copy, stably (for kernels that take their lanes in
    set-up order)."""

    copies: int
    source: np.ndarray
    lane_copy: np.ndarray
    order: np.ndarray

    @classmethod
    def plan(cls, group_of_lane, n_groups: int, n_threads: int | None = None) -> SetupCopies:
        """The copies for lanes of set-ups ``group_of_lane`` (L,) among ``n_groups``, on
        ``n_threads`` threads (default :func:`threads.thread_count`): as many copies of
        every set-up as the threads hold (⌊threads/G⌋), each with at least
        MIN_LANES_PER_COPY lanes of the smallest set-up."""
        group_of_lane = np.asarray(group_of_lane, dtype=np.int64)
        n_threads = threads.thread_count() if n_threads is None else int(n_threads)
        counts = np.bincount(group_of_lane, minlength=n_groups)
        smallest = int(counts.min()) if n_groups > 0 else 0
        copies = cls.copies_for(n_groups, smallest, n_threads)
        source = np.repeat(np.arange(n_groups, dtype=np.int64), copies)
        if copies == 1:
            return cls(1, source, group_of_lane, np.argsort(group_of_lane, kind="stable"))
        # The rank of each lane among its set-up's lanes, in the caller's order.
        order = np.argsort(group_of_lane, kind="stable")
        starts = np.concatenate([[0], np.cumsum(counts)])
        rank = np.empty_like(group_of_lane)
        rank[order] = np.arange(group_of_lane.size) - starts[group_of_lane[order]]
        lane_copy = group_of_lane * copies + rank % copies
        return cls(copies, source, lane_copy, np.argsort(lane_copy, kind="stable"))

    @staticmethod
    def copies_for(n_groups: int, lanes: int, n_threads: int) -> int:
        """Copies of each of ``n_groups`` set-ups of at least ``lanes`` lanes each on
        ``n_threads`` threads: ⌊threads/G⌋, each copy with MIN_LANES_PER_COPY lanes or
        more, at least 1."""
        return max(1, min(n_threads // max(n_groups, 1), lanes // MIN_LANES_PER_COPY))

    @property
    def n_copies(self) -> int:
        return int(self.source.size)

    def spread(self, per_setup):
        """A per-set-up array (G, ...) as one row per copy; None stays None."""
        return None if per_setup is None else np.asarray(per_setup)[self.source]

    def unorder(self, in_order: np.ndarray) -> np.ndarray:
        """Per-lane values given in ``order`` (kernel order) back in the caller's order."""
        out = np.empty_like(in_order)
        out[self.order] = in_order
        return out

    def status(self, copy_status: np.ndarray) -> np.ndarray:
        """(G,) status of each set-up: that of its first copy that did not end OK (0)."""
        by_setup = np.asarray(copy_status).reshape(-1, self.copies)
        first = np.argmax(by_setup != 0, axis=1)
        return by_setup[np.arange(by_setup.shape[0]), first]

    def done(self, on_done: Callable[[float], None] | None):
        """``on_done`` told in set-ups: a copy that ends is 1/copies of one."""
        if on_done is None or self.copies == 1:
            return on_done
        return lambda count: on_done(count / self.copies)
