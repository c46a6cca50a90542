"""Friction figures (plotting/friction.py): the plotted data against independent values.

The flat punch (m2 = 1) under δ = δ_m (1 + β cos ωt), k_t, prescribed velocity v: for
β <= 1, μ_eff/μ = 1 − β D(ṽ), ṽ = k_t v/(μ max|dN/dt|), max|dN/dt| = S c_n Δ ω. D is
computed here from its definition (docs/theory/friction_reduction.md): with θ = ωt the
contact point slides (f = μN) while −sin θ <= ṽ, sticks from θ1 = π + asin ṽ (f grows at
k_t v, slope β ṽ in units of μ N0) until f meets μN again at θ2, and
D = (1/2π) ∫_{θ1}^{θ2} (cos θ − cos θ1 − ṽ (θ − θ1)) dθ.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

import microslip as ms
from microslip.plotting import friction
from microslip.plotting import stick_slip as stick_slip_plots

P = ms.Parameters()
BETAS = friction.MASTER_BETAS
_PREFIX = {"": 1.0, "k": 1e-3, "m": 1e3, "µ": 1e6, "n": 1e9, "p": 1e12}


def reduction(v_tilde: float) -> float:
    """D(ṽ) by quadrature of the stick-phase deficit (see the module docstring)."""
    if v_tilde >= 1.0:
        return 0.0
    t1 = math.pi + math.asin(v_tilde)

    def gap(theta: float) -> float:
        return math.cos(theta) - math.cos(t1) - v_tilde * (theta - t1)

    t2 = 3.0 * math.pi if v_tilde == 0.0 else brentq(gap, 1.5 * math.pi, 3.0 * math.pi, xtol=1e-15)
    return quad(gap, t1, t2, epsabs=1e-13, epsrel=1e-13)[0] / (2.0 * math.pi)


def test_reduction_reference():
    assert reduction(0.0) == pytest.approx(1.0, abs=1e-12)  # stuck at the minimum of μN
    assert reduction(1.0) == 0.0
    values = [reduction(v) for v in np.linspace(0.0, 0.999, 30)]
    assert np.all(np.diff(values) < 0)


def _labels_have_units(fig):
    for ax in fig.axes:
        for label in (ax.get_xlabel(), ax.get_ylabel()):
            if label:
                assert re.search(r"\[[^\]]+\]$", label), label


def _factor(label: str, base: str) -> float:
    """SI -> plotted factor from an axis label ``"... [<prefix><base>]"``."""
    symbol = re.search(r"\[([^\]]+)\]$", label).group(1)
    assert symbol.endswith(base), (label, base)
    return _PREFIX[symbol[: -len(base)]]


def _line(ax, label: str):
    return next(line for line in ax.get_lines() if line.get_label() == label)


# -- master curve ----------------------------------------------------------------------
@pytest.fixture(scope="module")
def master():
    return friction.master_curve_figure(P)


def _independent_v_tilde(ds) -> np.ndarray:
    """ṽ = k_t v / (μ S c_n Δ ω) from the recorded model, per (β, point)."""
    a = ds.attrs
    omega = 2.0 * math.pi * a["excitation_frequency"]
    slope = a["param_area"] * a["param_c_n"] * ds["beta"].values[:, None] * a["excitation_mean"]
    return a["tangential_stiffness"] * ds["velocity"].values / (a["param_mu"] * slope * omega)


def test_master_curve_is_a_flat_punch(master):
    _, ds = master
    a = ds.attrs
    assert a["param_m2"] == 1.0
    assert a["excitation"] == "PrescribedPenetration" and a["drive"] == "PrescribedVelocity"
    assert a["tangential"] == "TangentialSpring" and a["friction"] == "none"
    # the mean penetration carries the weight: N0 = S c_n δ_m = m g
    n0 = a["param_area"] * a["param_c_n"] * a["excitation_mean"]
    assert n0 == pytest.approx(P.mass * P.g, rel=1e-12)
    np.testing.assert_allclose(_independent_v_tilde(ds), np.broadcast_to(ds["v_tilde"], ds[
        "velocity"].shape), rtol=1e-12)  # fmt: skip


def test_master_curve_collapses_onto_closed_form(master):
    fig, ds = master
    _labels_have_units(fig)
    sub = ds.sel(beta=list(BETAS))
    red = (1.0 - sub["ratio"].values) / sub["beta"].values[:, None]
    np.testing.assert_allclose(sub["reduction"].values, red, rtol=0, atol=1e-15)
    assert np.ptp(red, axis=0).max() < 1e-6  # equal across β
    closed = np.array([reduction(v) for v in ds["v_tilde"].values])
    np.testing.assert_allclose(red, np.broadcast_to(closed, red.shape), rtol=0, atol=1e-6)
    np.testing.assert_allclose(ds["closed_form"].values, closed, rtol=0, atol=1e-9)
    # the drawn closed-form line is D at its abscissae
    line = _line(fig.axes[0], "closed form D(ṽ)")
    x, y = line.get_data()
    picks = np.linspace(0, x.size - 1, 25).astype(int)
    np.testing.assert_allclose(y[picks], [reduction(v) for v in x[picks]], rtol=0, atol=1e-9)
    # the plotted markers are the data
    for beta in BETAS:
        _, y = _line(fig.axes[0], f"β = {beta:g}").get_data()
        np.testing.assert_array_equal(y, ds["reduction"].sel(beta=beta).values)


def test_master_curve_loss_of_contact_does_not_collapse(master):
    _, ds = master
    lost = ds.sel(beta=[b for b in ds["beta"].values if b > 1.0])
    assert lost.sizes["beta"] >= 1
    slow = lost.sel(v_tilde=0.5)
    assert np.all(np.abs(slow["reduction"].values - reduction(0.5)) > 1e-2)
    # friction never negative, never above μ
    assert np.all(ds["ratio"].values >= -1e-12) and np.all(ds["ratio"].values <= 1 + 1e-9)


# -- μ_eff map -------------------------------------------------------------------------
@pytest.fixture(scope="module")
def mu_map():
    return friction.mu_eff_map_figure(P)


def test_mu_eff_map_critical_line(mu_map):
    fig, ds = mu_map
    _labels_have_units(fig)
    a = ds.attrs
    amplitude = ds["excitation.amplitude"].values
    omega = 2.0 * math.pi * a["excitation_frequency"]
    # v_c = μ max|dN/dt| / k_t with max|dN/dt| = S c_n Δ ω (also for Δ > δ_m: at the
    # steepest point δ = δ_m > 0)
    v_c = a["param_mu"] * a["param_area"] * a["param_c_n"] * amplitude * omega / a[
        "tangential_stiffness"]  # fmt: skip
    np.testing.assert_allclose(ds["critical_velocity"].values, v_c, rtol=1e-9)
    ax = fig.axes[0]
    x, y = _line(ax, "ṽ = 1 (critical speed)").get_data()
    x, y = x / _factor(ax.get_xlabel(), "m/s"), y / _factor(ax.get_ylabel(), "m")
    k_t = a["tangential_stiffness"]
    slope = a["param_mu"] * a["param_area"] * a["param_c_n"] * omega / k_t  # v_c / Δ
    np.testing.assert_allclose(x, slope * y, rtol=1e-9)
    assert y.min() == pytest.approx(amplitude.min()) and y.max() == pytest.approx(amplitude.max())
    assert ax.get_xscale() == "log"
    # loss of contact at Δ = δ_m = m g/(S c_n)
    loss = _line(ax, "Δ = δ_m (loss of contact above)").get_ydata()[0]
    delta_m = P.mass * P.g / (a["param_area"] * a["param_c_n"])
    assert loss / _factor(ax.get_ylabel(), "m") == pytest.approx(delta_m, rel=1e-12)


def test_mu_eff_map_values(mu_map):
    _, ds = mu_map
    ratio = ds["ratio"].transpose("excitation.amplitude", "velocity").values
    beta = ds["excitation.amplitude"].values / ds.attrs["excitation_mean"]
    v_c = ds["critical_velocity"].values
    for i in np.flatnonzero(beta <= 1.0):
        v_tilde = ds["velocity"].values / v_c[i]
        expect = [1.0 - beta[i] * reduction(v) for v in v_tilde]
        np.testing.assert_allclose(ratio[i], expect, rtol=0, atol=1e-6)


# -- μ_eff curve of any dataset ---------------------------------------------------------
def test_friction_curve_figure_marks_critical_speed():
    from microslip.analysis.effective_friction import effective_friction_curve

    beta = 0.5
    model = friction.flat_punch_model(P, beta)
    v_c = P.mu * P.mass * P.g * beta * 2 * math.pi * P.natural_frequency / P.contact_stiffness
    velocities = np.array([0.1, 0.5, 2.0]) * v_c
    ds = effective_friction_curve(model, velocities)
    fig = friction.friction_curve_figure(ds)
    _labels_have_units(fig)
    top, low = fig.axes[:2]
    assert top.get_xscale() == "log"
    factor = _factor(low.get_xlabel(), "m/s")
    critical = [line for line in top.get_lines() if line.get_label().startswith("ṽ = 1")]
    assert len(critical) == 1
    assert critical[0].get_xdata()[0] / factor == pytest.approx(v_c, rel=1e-9)
    x, y = _line(top, "μ_eff / μ_k").get_data()
    np.testing.assert_allclose(x / factor, velocities, rtol=1e-12)
    np.testing.assert_allclose(y, [1.0 - beta * reduction(v) for v in (0.1, 0.5, 2.0)], atol=1e-6)


# -- spring-driven stick–slip ----------------------------------------------------------
@pytest.fixture(scope="module")
def stick_slip():
    return stick_slip_plots.spring_stick_slip_figure(P)


def test_spring_stick_slip_without_vibration(stick_slip):
    fig, ds = stick_slip
    _labels_have_units(fig)
    a = ds.attrs
    mu_s, mu_k = a["friction_mu_static"], a["friction_mu_kinetic"]
    k_d, v_d = a["drive_stiffness"], a["drive_velocity"]
    assert a["tangential"] == "none" and a["friction"] == "StaticKinetic" and mu_s > mu_k
    still = ds.isel(case=int(np.flatnonzero(ds["amplitude"].values == 0.0)[0]))
    mg = P.mass * P.g
    # undamped slider from rest at F = μ_s m g: m ẍ = k_d (v_d t − x) − μ_k m g; in
    # z = x − v_d t + μ_k m g/k_d, z = −Δ0 cos Ωt − (v_d/Ω) sin Ωt, Δ0 = (μ_s − μ_k) m g/k_d;
    # ẋ = 0 again at Ωt = π + 2 atan(v_d/(Δ0 Ω)), and the drop k_d (z(t) − z(0)) is exactly
    # 2 (μ_s − μ_k) m g for any v_d; the stick that follows lasts 2 Δ0 / v_d
    omega = math.sqrt(k_d / P.mass)
    half = (mu_s - mu_k) * mg / k_d
    slip = (math.pi + 2 * math.atan(v_d / (half * omega))) / omega
    drop = 2 * (mu_s - mu_k) * mg
    assert float(still["force_drop"]) == pytest.approx(drop, rel=1e-8)
    assert float(still["force_drop_std"]) < 1e-8 * drop
    assert float(still["period"]) == pytest.approx(slip + 2 * half / v_d, rel=1e-8)
    assert float(still["stick_start_time"] - still["slip_start_time"]) == pytest.approx(
        slip, rel=1e-8)  # fmt: skip
    # in the drawn history: F at each slip start is μ_s m g, at each stick start μ_s m g − drop
    keep = np.isfinite(still["time"].values)
    moving = np.r_[False, still["direction"].values[keep] != 0]
    force = still["drive_force"].values[keep]
    starts = np.flatnonzero(np.diff(moving.astype(int)) == 1)
    stops = np.flatnonzero(np.diff(moving.astype(int)) == -1)
    assert starts.size >= 2 and stops.size >= 2
    np.testing.assert_allclose(force[starts], mu_s * mg, rtol=1e-9)
    np.testing.assert_allclose(force[stops], mu_s * mg - drop, rtol=1e-8)
    # the drawn arrow spans the drop at the end of the first slip, its label says it
    ax = fig.axes[0]
    factor = _factor(ax.get_ylabel(), "N")
    arrows = [t for t in ax.texts if getattr(t, "arrow_patch", None) is not None]
    assert len(arrows) == 1
    (x, low), (_, high) = arrows[0].xy, arrows[0].xyann
    assert (high - low) / factor == pytest.approx(drop, rel=1e-8)
    assert high / factor == pytest.approx(mu_s * mg, rel=1e-9)
    below = fig.axes[ds.sizes["case"]]  # the velocity panel under it
    assert x / _factor(below.get_xlabel(), "s") == pytest.approx(
        float(still["time"][stops[0]]), rel=1e-12)  # fmt: skip
    labels = [t.get_text() for t in ax.texts if t.get_text()]
    assert labels == [f"ΔF = {drop * factor:.3g} N"]


def test_spring_stick_slip_with_vibration(stick_slip):
    fig, ds = stick_slip
    assert len(fig.axes) == 2 * ds.sizes["case"]
    amplitudes = ds["amplitude"].values
    assert amplitudes[0] == 0.0 and np.all(np.diff(amplitudes) > 0)
    assert np.all(np.diff(ds["force_drop"].values) < 0)  # vibration shrinks the drop
    for k in range(ds.sizes["case"]):
        run = ds.isel(case=k)
        keep = np.isfinite(run["time"].values)
        moving = run["direction"].values[keep] != 0
        starts = np.flatnonzero(np.diff(moving.astype(int)) == 1) + 1
        assert starts.size >= 1
        # a slip starts from stick exactly where the spring force reaches μ_s N(t)
        force, limit = run["drive_force"].values[keep], run["friction_limit"].values[keep]
        np.testing.assert_allclose(force[starts], limit[starts], rtol=1e-9)
        # while stuck the body does not move
        np.testing.assert_array_equal(run["xdot"].values[keep][~moving], 0.0)
