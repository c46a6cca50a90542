"""Small compiled functions in inner loops are compiled without NRT reference counting
(microslip/_refcount.py, docs/design.md "The compiled form").

The option is numba's private ``_nrt``; a release that renamed it, or a feature test
that looked in the wrong place, would leave ``NO_REFCOUNT`` empty and every function
silently reference counted again (a forced-response curve 1.26× slower). These tests
fail then, rather than a benchmark drifting."""

import numpy as np
import pytest
from numba import njit
from numba.core.errors import TypingError

from microslip._refcount import NO_REFCOUNT
from microslip.analysis import contact_point, normal_flow, normal_pieces
from microslip.analysis.orbit_table import orbit_state
from microslip.integrators import mindlin_lane_law, spring_lane_law

HOT = [
    normal_flow._step, normal_flow._first_switch, normal_flow._locate, normal_flow._value,
    contact_point._period, contact_point._root, contact_point._steady,
    normal_pieces.piece_integrals, normal_pieces._fill_piece, normal_pieces._interval_switches,
    spring_lane_law.lane_piece, mindlin_lane_law.lane_piece, mindlin_lane_law._first_exit,
]  # fmt: skip


def test_the_option_is_numbas_and_drops_the_reference_counting():
    """orbit_state (arrays in, several exits) compiled as a function of its own: numba's
    pruning leaves its reference counting in; the option takes it out."""
    assert NO_REFCOUNT == {"_nrt": False}
    plain, lean = njit(orbit_state.py_func), njit(**NO_REFCOUNT)(orbit_state.py_func)
    nodes = np.linspace(0.0, 1.0, 11)
    args = (0.37, nodes, nodes**2, 2.0 * nodes, np.full(10, 2.0), np.full(10, 2.0))
    assert plain(*args) == lean(*args)
    assert abs(lean(*args)[0] - 0.37**2) < 1e-15
    assert "NRT_incref" in next(iter(plain.inspect_llvm().values()))
    assert "NRT_incref" not in next(iter(lean.inspect_llvm().values()))


@pytest.mark.parametrize("function", HOT, ids=lambda f: f.py_func.__name__)
def test_the_inner_loop_functions_take_it(function):
    assert function.targetoptions.get("_nrt") is False


def test_a_function_that_allocates_is_refused():
    """The option cannot leak or free memory silently: numba will not compile it."""

    def allocates(n):
        return np.zeros(n).sum()

    with pytest.raises(TypingError):
        njit(**NO_REFCOUNT)(allocates)(3)
