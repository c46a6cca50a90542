"""``microslip friction``: μ_eff curves and maps under normal vibration, on the command line.

The flat punch (m2 = 1, N = K_n δ) under a prescribed penetration δ = δ_m (1 + β cos ωt),
with a tangential spring k_t and Coulomb friction μ, driven at v, has the closed form
(docs/theory/friction_reduction.md)

    μ_eff/μ = 1 - β D(ṽ),  ṽ = k_t v / (μ N0 β ω),  N0 = K_n δ_m   (β <= 1),

with D(ṽ) = (1/2π) ∫_{τ1}^{τ2} [cos τ - cos τ1 - ṽ (τ - τ1)] dτ over the stick phase:
it starts where the slope of n = 1 + β cos τ reaches that of the spring line
(sin τ1 = -ṽ, n rising: τ1 = π + asin ṽ) and ends where n falls back to the line
(τ2 > τ1); D = 0 for ṽ >= 1 (the contact point never sticks). D is computed here by
root finding and quadrature, independently of microslip.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import xarray as xr
from cli_inprocess import one_line_failure, run
from scipy.integrate import quad
from scipy.optimize import brentq

MU = 0.1
C_N = 1e8  # N/m: K_n of the flat punch (S = 1 m², m2 = 1)
Y0 = 1.0 * 9.81 / C_N  # δ_m = y0 [m]: N0 = m g
N0 = 9.81
K_T = 1e8  # k_t [N/m]
FREQ = 1000.0  # f [Hz]
OMEGA = 2 * math.pi * FREQ
SPRING = ["--tangential", "spring", "--tangential-stiffness", str(K_T)]
PUNCH = [
    "--m2", "1", "--area", "1", "--c-n", str(C_N), "--mu", str(MU),
    "--excitation", "prescribed-penetration", "--excitation-mean", repr(Y0),
    "--excitation-frequency", str(FREQ),
]  # fmt: skip
FLAT_PUNCH = [*PUNCH, *SPRING]


BETA = ["--excitation-amplitude", repr(0.5 * Y0)]


def reduction(v_tilde: float) -> float:
    """D(ṽ) of the module docstring."""
    if v_tilde >= 1.0:
        return 0.0
    t1 = math.pi + math.asin(v_tilde)

    def gap(t: float) -> float:  # n - line, in units of β
        return math.cos(t) - math.cos(t1) - v_tilde * (t - t1)

    # gap(τ1) = gap'(τ1) = 0, gap''(τ1) = cos(asin ṽ) > 0: gap > 0 just after τ1 (the
    # stick phase lasts ~ 3 sqrt(1 - ṽ²) >> 1e-3 for ṽ <= 0.99); gap(τ1 + 2π) = -2π ṽ < 0
    t2 = brentq(gap, t1 + 1e-3, t1 + 2 * math.pi, xtol=1e-15, rtol=1e-15)
    return quad(gap, t1, t2, epsabs=1e-14, epsrel=1e-13)[0] / (2 * math.pi)


def velocity_of(v_tilde: float, beta: float) -> float:
    return v_tilde * MU * N0 * beta * OMEGA / K_T


def test_reduction_of_the_test_itself():
    """D(0+) = (1/2π) ∫_π^{3π} (cos τ + 1) dτ = 1 (full stick: f = μ min N), D(1-) -> 0,
    decreasing in between."""
    assert reduction(1e-7) == pytest.approx(1.0, abs=1e-5)
    assert reduction(0.99) < 1e-3
    values = [reduction(v) for v in np.linspace(0.05, 0.95, 10)]
    assert all(a > b for a, b in itertools.pairwise(values))


def test_curve_matches_the_flat_punch_closed_form(capsys, tmp_path):
    beta = 0.5
    v_tilde = np.array([0.1, 0.3, 0.6, 0.9, 1.5])
    velocities = ",".join(repr(velocity_of(float(v), beta)) for v in v_tilde)
    out, plot = tmp_path / "mu.nc", tmp_path / "mu.png"
    status, stdout, err = run(
        capsys, "friction", *FLAT_PUNCH, "--excitation-amplitude", repr(beta * Y0),
        "--velocities", velocities, "--out", out, "--plot", plot,
    )  # fmt: skip
    assert status == 0, err
    assert "min mu_eff/mu_k = 0.62" in stdout and "m s-1" in stdout
    assert "critical v_tilde = 1 at v = " in stdout
    assert f"wrote {out}" in stdout and f"wrote {plot}" in stdout
    assert plot.stat().st_size > 1000
    with xr.open_dataset(out) as ds:
        assert ds["velocity"].attrs["units"] == "m s-1"
        for name in ("mu_eff", "ratio", "v_tilde", "stick_fraction"):
            assert ds[name].dims == ("velocity",)
            assert ds[name].attrs["units"] == "1"
        assert ds.attrs["tangential"] == "TangentialSpring"
        assert ds.attrs["drive"] == "PrescribedVelocity"  # added by the command
        # the event method at rtol 1e-11: mu_eff to ~1e-10 relative
        expected = np.array([1.0 - beta * reduction(v) for v in v_tilde])
        np.testing.assert_allclose(ds["ratio"].values, expected, rtol=0, atol=1e-8)
        np.testing.assert_allclose(ds["mu_eff"].values, MU * expected, rtol=0, atol=1e-9)
        stick = ds["stick_fraction"].values
        assert stick[-1] == pytest.approx(0.0, abs=1e-9)  # ṽ > 1: never sticks
        assert np.all(np.diff(stick) < 0.0)


def test_v_tilde_is_the_flat_punch_value(capsys, tmp_path):
    """ṽ = k_t v / (μ max|dN/dt|), max|dN/dt| = N0 β ω exactly for the flat punch (to the
    ~1e-7 of a max|dN/dt| sampled 4096 times per period)."""
    beta, v_tilde = 0.5, np.array([0.3, 1.5])
    out = tmp_path / "mu.nc"
    velocities = ",".join(repr(velocity_of(float(v), beta)) for v in v_tilde)
    status, _, err = run(capsys, "friction", *FLAT_PUNCH, "--excitation-amplitude",
                         repr(beta * Y0), "--velocities", velocities, "--out", out)  # fmt: skip
    assert status == 0, err
    with xr.open_dataset(out) as ds:
        np.testing.assert_allclose(ds["v_tilde"].values, v_tilde, rtol=1e-6)


def test_past_the_critical_speed_friction_is_not_reduced(capsys, tmp_path):
    """ṽ > 1 everywhere (the contact point never sticks): μ_eff = μ."""
    out = tmp_path / "mu.nc"
    v = [velocity_of(2.0, 0.25), velocity_of(4.0, 0.25)]
    status, _, err = run(
        capsys, "friction", *FLAT_PUNCH, "--excitation-amplitude", repr(0.25 * Y0),
        "--velocities", f"{v[0]!r},{v[1]!r}", "--out", out,
    )  # fmt: skip
    assert status == 0, err
    with xr.open_dataset(out) as ds:
        np.testing.assert_allclose(ds["ratio"].values, 1.0, rtol=0, atol=1e-8)
        np.testing.assert_allclose(ds["stick_fraction"].values, 0.0, atol=1e-9)


def test_map_over_the_penetration_amplitude(capsys, tmp_path):
    betas = np.array([0.25, 0.75])
    out, plot = tmp_path / "map.nc", tmp_path / "map.png"
    v = [velocity_of(0.1, 1.0), velocity_of(0.2, 1.0)]  # ṽ < 1 at both amplitudes
    status, stdout, err = run(
        capsys, "friction", *FLAT_PUNCH, "--velocities", f"{v[0]!r},{v[1]!r}",
        "--axis", f"excitation.amplitude={0.25 * Y0!r},{0.75 * Y0!r}", "--out", out,
        "--plot", plot,
    )  # fmt: skip
    assert status == 0, err
    assert plot.stat().st_size > 1000
    with xr.open_dataset(out) as ds:
        ratio = ds["ratio"]
        assert ratio.dims == ("excitation.amplitude", "velocity")
        assert ds["excitation.amplitude"].attrs["units"] == "m"
        for i, beta in enumerate(betas):
            for j, vel in enumerate(v):
                v_tilde = K_T * vel / (MU * N0 * beta * OMEGA)
                expected = 1.0 - beta * reduction(v_tilde)
                assert ratio.values[i, j] == pytest.approx(expected, abs=1e-8), (beta, vel)
    assert "excitation.amplitude = 7.3575e-08 m" in stdout  # the smallest ratio: largest β
    assert "v_tilde < 1 (friction reduced) at 4 of 4 points" in stdout


def test_rigid_contact_has_mu_eff_mu_under_free_vibration(capsys, tmp_path):
    """A rigid contact never sticks at v > 0: μ_eff = μ for any normal motion (here the
    paper's free vibration of amplitude A)."""
    out = tmp_path / "mu.nc"
    status, stdout, err = run(capsys, "friction", "--velocities", "1e-4,1e-3",
                              "--axis", "amplitude=5e-8,1.5e-7", "--out", out)  # fmt: skip
    assert status == 0, err
    with xr.open_dataset(out) as ds:
        assert ds["mu_eff"].dims == ("amplitude", "velocity")
        assert ds["amplitude"].attrs["units"] == "m"
        np.testing.assert_allclose(ds["mu_eff"].values, 0.1, rtol=1e-12)
    assert "min mu_eff/mu_k = 1" in stdout


def test_log_range_and_toml_options(capsys, tmp_path):
    """--velocities start:stop:count:log; the options from [effective-friction]."""
    config = tmp_path / "run.toml"
    config.write_text(
        '[tangential]\nkind = "spring"\nstiffness = 1e8\n'
        "[effective-friction]\nvelocities = '1e-4:1e-2:3:log'\n"
    )
    out = tmp_path / "mu.nc"
    status, _, err = run(capsys, "friction", *PUNCH, "--excitation-amplitude", repr(0.5 * Y0),
                         "--config", config, "--out", out)  # fmt: skip
    assert status == 0, err
    with xr.open_dataset(out) as ds:
        np.testing.assert_allclose(ds["velocity"].values, [1e-4, 1e-3, 1e-2], rtol=1e-15)


def test_an_existing_output_needs_overwrite(capsys, tmp_path):
    out = tmp_path / "mu.nc"
    out.write_text("keep")
    args = ["friction", *FLAT_PUNCH, "--excitation-amplitude", repr(0.5 * Y0),
            "--velocities", "1e-3", "--out", out]  # fmt: skip
    status, _, err = run(capsys, *args)
    one_line_failure(status, err, "exists", "--overwrite")
    assert out.read_text() == "keep"
    status, _, err = run(capsys, *args, "--overwrite")
    assert status == 0, err
    with xr.open_dataset(out) as ds:
        assert ds.sizes["velocity"] == 1


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        ([], ["--velocities [m s-1] is required", "[effective-friction]"]),
        (["--velocities", "0:1e-2:4:log"], ["--velocities", "0 < start"]),
        (["--velocities", "1e-3", "--drive", "spring", "--drive-stiffness", "1e5",
          "--drive-velocity", "1e-4"], ["--drive:", "not with drive spring",
                                        "--drive prescribed-velocity"]),
        (["--velocities", "1e-3", "--drive", "prescribed-velocity", "--drive-velocity",
          "1e-3", *BETA], ["--drive-velocity cannot be combined with --velocities"]),
        (["--velocities", "1e-3", "--axis", "drive.velocity=1e-3,2e-3"],
         ["--axis", "the velocity is the --velocities axis"]),
        (["--velocities", "1e-3", "--axis", "excitation.amplitude"], ["expected NAME=RANGE"]),
        (["--velocities", "1e-3", "--axis", "excitation.amplitude=0:1:3"],
         ["--axis excitation.amplitude=...", "excitation.amplitude=1.0", "outside"]),
        (["--velocities", "1e-3", "--axis", "excitation.amplitude=1e-8,2e-8",
          "--excitation-amplitude", "1e-8"],
         ["--axis excitation.amplitude=... cannot be combined with --excitation-amplitude"]),
        (["--velocities", "1e-3", "--axis", "tangential.nothing=1,2", *BETA],
         ["tangential spring has no field 'nothing'"]),
        (["--velocities", "1e-3", "--axis", "damping.ratio=0.1,0.2"], ["no damping part"]),
        (["--velocities", "1e-3", "--axis", "mu=0.1,0.2", *BETA],
         ["--axis mu=... cannot be combined with --mu"]),
        (["--velocities", "1e-3", "--axis", "amplitude=1e-8,2e-8", "--amplitude", "1e-8",
          *BETA],
         ["--axis amplitude=... cannot be combined with --amplitude"]),
        (["--velocities", "1e-3", *BETA, "--out", "mu.csv"],
         ["suffix must be one of .nc"]),
        (["--velocities", "1e-3", *BETA, "--out", "a.nc", "--plot", "a.nc"], ["suffix"]),
        (["--velocities", "1e-3", *BETA, "--plot", "a.txt"],
         ["'a.txt'", "suffix must be one of .png"]),
    ],
)  # fmt: skip
def test_refusals_before_computing(capsys, tmp_path, monkeypatch, extra, words):
    monkeypatch.chdir(tmp_path)
    status, out, err = run(capsys, "friction", *FLAT_PUNCH, *extra)
    one_line_failure(status, err, *words)
    assert out == ""
    assert list(tmp_path.iterdir()) == []
