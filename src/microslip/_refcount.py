"""Compile options for small compiled functions that take arrays and allocate nothing.

numba's runtime (NRT) takes a reference to every array a compiled function receives
when it starts and releases it at each exit, with atomic operations on the array's
shared count; its pruning pass removes such pairs only in simple control flow. A root
finder, an integrator step or a table lookup called in an inner loop, with several
exits, then spends more on these operations than on its work: a forced-response curve
(the normal flow's steps) 1.26×, the exact μ_eff walk 1.5× (docs/design.md).

A function that creates no array, returns none and keeps none needs no reference
counting: its caller holds every array it is given for the whole call. ``NO_REFCOUNT``
compiles it without (numba's ``_nrt`` option). numba refuses to compile such a function
if it allocates after all, so the option cannot silently leak or free memory. Where a
numba release no longer has the option, it is empty: the same code, reference counted.

Usage: ``@njit(cache=True, **NO_REFCOUNT)``.
"""

from __future__ import annotations

from numba.core.cpu import CPUTargetOptions

from microslip import _jit_cache  # noqa: F401  (registers the cache before any @njit)

__all__ = ["NO_REFCOUNT"]

NO_REFCOUNT: dict[str, bool] = {"_nrt": False} if hasattr(CPUTargetOptions, "_nrt") else {}
