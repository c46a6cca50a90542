"""The rigid lanes' spans (integrators/rigid_pass.py): SPAN_ROWS rows of the normal tape
taken as one piece by the vector pass, the lanes it flags redone row by row.

Two checks: the span's integrals and extremes against numpy's integration of the
piecewise quartic (an independent computation), and the lanes through spans against the
same lanes row by row on a forced tape where they stick and slip every period.
"""

from __future__ import annotations

import numpy as np
import pytest

import microslip as ms
from microslip.integrators import normal_tape as nt
from microslip.integrators import rigid_pass
from microslip.integrators.kernel import as_tuple
from microslip.integrators.shared_lanes import pack_lanes, start_modes
from microslip.model.normal import normal_force

PARAMS = ms.Parameters()
T0 = PARAMS.natural_period


def _forced_tape(rows=2 * rigid_pass.SPAN_ROWS * 40):
    """(tape, coefficients) of a damped, harmonically forced normal motion near its
    resonance, from rest at y0: rows [0, rows) of its tape."""
    model = ms.Model(PARAMS, damping=ms.Viscous(0.05), excitation=ms.HarmonicForce(3.0, 1400.0))
    coeffs = nt.normal_coefficients(model.pack(0.0))
    carry, tape, work = nt.tape_buffers(PARAMS.static_deflection, 0.0)
    filled, status = nt.fill_tape(carry, coeffs, 1.0, T0 / 200, tape, work)
    assert status == 1 and filled == nt.TAPE_ROWS
    return tape[:rows].copy(), coeffs


def test_spans_divide_a_fill_of_the_tape():
    """A span never straddles two fills of a tape (nor two GPU blocks, rounded to
    whole spans): the lanes' bits then do not depend on where a fill ends."""
    assert nt.TAPE_ROWS % rigid_pass.SPAN_ROWS == 0


@pytest.mark.parametrize(("r0", "r1"), [(0, 1), (3, 11), (100, 108), (0, 37)])
def test_span_integrals_against_numpy_integration_of_the_pieces(r0, r1):
    """L, ∫ N dt, ∫ (t1 - t) N dt over the span, by numpy's polynomial integration of each
    piece (dt = h dτ; not the tape's I(1), K(1)), and the extremes on a dense grid."""
    tape, _ = _forced_tape()
    length, first, second, p_min, p_max = nt.span(tape, r0, r1)
    t_start = tape[r0, nt.T0]
    t_end = tape[r1 - 1, nt.T0] + tape[r1 - 1, nt.H]
    total, moment, values = 0.0, 0.0, []
    for r in range(r0, r1):
        h, t0 = tape[r, nt.H], tape[r, nt.T0]
        piece = np.polynomial.Polynomial(nt.coefficients(tape, r))  # P(τ), t = t0 + h τ
        total += h * piece.integ()(1.0)
        moment += h * (np.polynomial.Polynomial([t_end - t0, -h]) * piece).integ()(1.0)
        values.append(piece(np.linspace(0.0, 1.0, 2001)))
    assert length == pytest.approx(t_end - t_start, rel=1e-14)
    assert first == pytest.approx(total, rel=1e-12)
    assert second == pytest.approx(moment, rel=1e-10)
    values = np.concatenate(values)
    assert p_min == pytest.approx(values.min(), rel=1e-9)
    assert p_max == pytest.approx(values.max(), rel=1e-9)
    # One row: the row's own numbers, bit for bit (a span of one row is the old pass).
    h = tape[r0, nt.H]
    one = nt.span(tape, r0, r0 + 1)
    assert one == (h, h * tape[r0, nt.INT1], h * h * tape[r0, nt.KINT1], tape[r0, nt.PMIN],
                   tape[r0, nt.PMAX])  # fmt: skip


def test_lanes_through_spans_agree_with_lanes_row_by_row():
    """Lanes that stick and slip every period of a forced normal motion (static and
    kinetic friction, forces of both signs), through 640 rows: spans and rows give the
    same modes, switches and flagged rows, and x, ẋ to rounding. A span that misses a
    switch inside it (its integrals or extremes wrong, a flagged lane not redone or
    written back to another lane's column, a releasable lane left out) breaks it."""
    tape, coeffs = _forced_tape()
    forces = np.concatenate([np.linspace(0.05, 1.6, 48), -np.linspace(0.1, 1.4, 16)])
    groups = np.zeros(forces.size, dtype=np.int64)
    mu_s, mu_k = np.full(forces.size, 0.12), np.full(forces.size, 0.1)
    results = []
    for run in (rigid_pass.lanes_over_rows, rigid_pass.rows_one_by_one):
        lanes = pack_lanes(coeffs[None, :], groups, forces, mu_s, mu_k)[0]
        n = lanes.shape[1]
        start_modes(lanes, 0, n, normal_force(0.0, PARAMS.static_deflection, 0.0,
                                              as_tuple(coeffs)))  # fmt: skip
        switches = np.zeros(n, dtype=np.int64)
        flagged = np.zeros(n, dtype=np.int64)
        status, _ = run(tape, np.int64(0), np.int64(tape.shape[0]), lanes, n, n, switches,
                        flagged)  # fmt: skip
        assert status == rigid_pass.OK
        results.append((lanes.copy(), switches, flagged))
    (spans, switches, flagged), (rows, row_switches, row_flagged) = results
    assert switches.sum() > 3 * forces.size  # several switches per lane
    assert np.array_equal(switches, row_switches) and np.array_equal(flagged, row_flagged)
    assert np.array_equal(spans[rigid_pass.MODE], rows[rigid_pass.MODE])
    for row in (rigid_pass.X, rigid_pass.V):
        scale = np.abs(rows[row]).max()
        assert scale > 0.0
        np.testing.assert_allclose(spans[row], rows[row], rtol=0, atol=1e-12 * scale)
