"""Validation tests: make the independent scipy reference importable, cache its solutions."""

import functools
import sys
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))

from scipy_reference import reference_solution  # noqa: E402


@functools.lru_cache(maxsize=64)
def _cached(params, force, amplitude, t_eval, rtol, atol):
    return reference_solution(
        params, force=force, amplitude=amplitude, t_eval=np.array(t_eval), rtol=rtol, atol=atol
    )


@pytest.fixture(scope="session")
def reference():
    """``reference(params, force=, amplitude=, t_eval=, rtol=, atol=)``, cached per session.

    The result is shared between tests: treat it as read-only.
    """

    def solve(params, *, force, amplitude, t_eval, rtol=1e-12, atol=1e-14):
        key = tuple(float(t) for t in np.asarray(t_eval, dtype=float))
        return _cached(params, float(force), float(amplitude), key, rtol, atol)

    return solve
