"""``microslip response``: the forced-response curve as files, its summary, and every
refused input as one line (exit 2) before anything is computed or written."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from cli_inprocess import one_line_failure, run

import microslip as ms
from microslip.cli.main import main
from microslip.plotting.response import response_figure

P = ms.Parameters()
F0 = P.natural_frequency
DAMPED_FORCE = [
    "--damping", "viscous", "--damping-ratio", "0.03",
    "--excitation", "harmonic-force", "--excitation-amplitude", "1.0",
]  # fmt: skip
# P0 = 1 N, ζ = 0.03: the curve leans over between 0.85 f0 and 0.95 f0 (two folds), with
# contact lost near the top of the upper branch.
FOLDED = ["--frequencies", "1200:1600"]


def fold_markers(fig) -> int:
    """The number of fold marks (open circles) drawn on the curve."""
    ax = fig.axes[0]
    return sum(len(line.get_xdata()) for line in ax.lines if line.get_marker() == "o")


@pytest.fixture(scope="module")
def folded(tmp_path_factory):
    """One folded branch written once (a module fixture: main() directly, no capsys)."""
    directory = tmp_path_factory.mktemp("response")
    status = main(
        ["response", *DAMPED_FORCE, *FOLDED, "--out", str(directory / "r.nc"),
         "--plot", str(directory / "r.png")]
    )  # fmt: skip
    assert status == 0
    with xr.open_dataset(directory / "r.nc") as ds:
        return directory, ds.load()


def test_response_writes_the_branch_and_the_plot(folded):
    directory, ds = folded
    assert (directory / "r.png").stat().st_size > 10_000
    for name in ("frequency", "excitation_amplitude", "amplitude", "y_min", "y_max",
                 "N_min", "N_max", "stable", "max_multiplier", "contact_lost"):  # fmt: skip
        assert name in ds, name
        assert "units" in ds[name].attrs, name
    assert ds["frequency"].attrs["units"] == "Hz"
    assert ds["amplitude"].attrs["units"] == "m"
    assert ds["N_min"].attrs["units"] == "N"
    # the branch runs from F1 to exactly F2, at the forcing the flags gave
    assert float(ds["frequency"][0]) == pytest.approx(1200.0, rel=1e-12)
    assert float(ds["frequency"][-1]) == pytest.approx(1600.0, rel=1e-9)
    np.testing.assert_array_equal(ds["excitation_amplitude"].values, 1.0)
    assert ds.attrs["damping"] == "Viscous" and ds.attrs["damping_ratio"] == 0.03
    assert ds.attrs["excitation"] == "HarmonicForce"


def test_the_curve_marks_each_fold_of_the_dataset(folded):
    _, ds = folded
    folds = np.atleast_1d(ds.attrs["folds"])
    assert folds.size == 2  # the leaning resonance peak: two folds in this window
    assert fold_markers(response_figure(ds)) == folds.size
    # stability changes at each fold (a saddle-node), and only there on this branch
    stable = ds["stable"].values
    changes = np.flatnonzero(stable[1:] != stable[:-1]) + 1
    assert all(min(abs(changes - f)) <= 1 for f in folds), (changes, folds)


def test_the_summary_names_folds_and_contact_loss(capsys, tmp_path):
    status, out, err = run(capsys, "response", *DAMPED_FORCE, *FOLDED, "--max-points", "2000")
    assert status == 0, err
    assert "2 folds at frequency =" in out
    assert "contact lost at" in out
    assert list(tmp_path.iterdir()) == []  # no --out, no --plot: nothing written


def test_response_in_amplitude_from_a_config_file(capsys, tmp_path):
    config = tmp_path / "run.toml"
    config.write_text(
        '[damping]\nlaw = "viscous"\nratio = 0.03\n'
        '[excitation]\nkind = "harmonic-force"\nfrequency = 1400.0\n'
        "[response]\namplitudes = [0.05, 0.5]\n"
    )
    out = tmp_path / "a.nc"
    status, _, err = run(capsys, "response", "--config", config, "--out", out,
                         "--plot", tmp_path / "a.svg")  # fmt: skip
    assert status == 0, err
    with xr.open_dataset(out) as ds:
        np.testing.assert_array_equal(ds["frequency"].values, 1400.0)
        assert float(ds["excitation_amplitude"][0]) == pytest.approx(0.05, rel=1e-12)
        assert float(ds["excitation_amplitude"][-1]) == pytest.approx(0.5, rel=1e-9)
        assert ds["excitation_amplitude"].attrs["units"] == "N"
        # the forcing of the file reached the model: at P0 = 0.05 N the orbit is the
        # linear oscillator's, P0/sqrt((K_n - m w^2)^2 + (c w)^2) (departs as P0^2)
        k = P.m2 * P.mass * P.g / P.static_deflection
        c = 2.0 * 0.03 * math.sqrt(k * P.mass)
        w = 2.0 * math.pi * 1400.0
        linear = 0.05 / math.hypot(k - P.mass * w * w, c * w)
        assert float(ds["amplitude"][0]) == pytest.approx(linear, rel=3e-3)
        assert np.all(np.diff(ds["amplitude"].values) > 0.0)  # grows with P0
    assert "<svg" in (tmp_path / "a.svg").read_text()[:500]


BAD = [
    (["--damping", "dashpot", "--excitation", "harmonic-force", "--excitation-amplitude",
      "1", "--frequencies", "1200:1600"], ["unknown damping law 'dashpot'"]),
    (["--damping", "viscous", "--damping-ratio", "12", "--excitation", "harmonic-force",
      "--excitation-amplitude", "1", "--frequencies", "1200:1600"],
     ["--damping-ratio", "outside"]),
    ([*DAMPED_FORCE, "--frequencies", "1:1600"], ["--frequencies", "1e-3 f0"]),
    ([*DAMPED_FORCE, "--frequencies", f"1200:{F0 * 1.1e3}"], ["--frequencies", "1e3 f0"]),
    (["--damping-ratio", "0.03", "--excitation", "harmonic-force", "--excitation-amplitude",
      "1", "--frequencies", "1200:1600"], ["--damping-ratio", "not given"]),
    (["--excitation-amplitude", "1", "--frequencies", "1200:1600"],
     ["--excitation-amplitude", "not given"]),
    (["--amplitudes", "0.1:1"], ["needs a normal excitation"]),
    (["--damping", "viscous", "--damping-ratio", "0.03", "--frequencies", "1200:1600"],
     ["needs a normal excitation"]),
    (["--excitation", "prescribed-penetration", "--excitation-mean", "2e-7",
      "--excitation-amplitude", "1e-7", "--frequencies", "1200:1600"],
     ["PrescribedPenetration"]),
    ([*DAMPED_FORCE], ["--frequencies F1:F2", "--amplitudes A1:A2"]),
    ([*DAMPED_FORCE, "--frequencies", "1200"], ["--frequencies", "START:END"]),
    ([*DAMPED_FORCE, "--frequencies", "1200:1200"], ["--frequencies", "differ"]),
    ([*DAMPED_FORCE, "--frequencies", "1200:abc"], ["--frequencies", "two numbers"]),
    ([*DAMPED_FORCE, "--frequencies", "1_200:1600"], ["'_'"]),
    ([*DAMPED_FORCE, "--frequencies", "1200:1600", "--amplitudes", "0.1:1"],
     ["--amplitudes", "--frequencies"]),
    ([*DAMPED_FORCE, "--excitation-frequency", "1400", "--frequencies", "1200:1600"],
     ["--excitation-frequency cannot be combined with --frequencies"]),
    ([*DAMPED_FORCE, "--frequencies", "1200:1600", "--max-points", "1"], ["--max-points"]),
    ([*DAMPED_FORCE, "--frequencies", "1200:1600", "--out", "r.csv"], ["r.csv"]),
    ([*DAMPED_FORCE, "--frequencies", "1200:1600", "--plot", "r.gif"], ["r.gif"]),
    ([*DAMPED_FORCE, "--frequencies", "1200:1600", "--out", "same.nc", "--plot", "same.nc"],
     ["same.nc"]),
]  # fmt: skip


@pytest.mark.parametrize(("args", "words"), BAD)
def test_bad_inputs_are_one_line_and_write_nothing(capsys, tmp_path, monkeypatch, args, words):
    monkeypatch.chdir(tmp_path)
    status, out, err = run(capsys, "response", *args)
    one_line_failure(status, err, *words)
    assert out == ""
    assert list(tmp_path.iterdir()) == []


def test_an_existing_output_needs_overwrite(capsys, tmp_path):
    out = tmp_path / "r.nc"
    out.write_bytes(b"old")
    status, _, err = run(capsys, "response", *DAMPED_FORCE, "--frequencies", "1200:1300",
                         "--out", out)  # fmt: skip
    one_line_failure(status, err, "--overwrite")
    assert out.read_bytes() == b"old"
