"""The model's parts through every command: simulate, info, map/sweep and figures, as
flags and as TOML tables; the files name the parts; refusals are one line (exit 2)."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from cli_inprocess import one_line_failure, run

import microslip as ms

P = ms.Parameters()
FORCED = [
    "--damping", "viscous", "--damping-ratio", "0.05",
    "--excitation", "harmonic-force", "--excitation-amplitude", "0.5",
    "--excitation-frequency", "1400",
]  # fmt: skip


def test_simulate_with_parts_writes_them_and_the_normal_force(capsys, tmp_path):
    out = tmp_path / "run.nc"
    status, stdout, err = run(capsys, "simulate", *FORCED, "--force", "0.5",
                              "--duration", "0.004", "--out", out)  # fmt: skip
    assert status == 0, err
    assert "simulated" in stdout
    with xr.open_dataset(out) as ds:
        assert ds.attrs["damping"] == "Viscous"
        assert ds.attrs["damping_ratio"] == 0.05
        assert ds.attrs["excitation"] == "HarmonicForce"
        assert ds.attrs["excitation_amplitude"] == 0.5
        assert ds.attrs["excitation_frequency"] == 1400.0
        assert ds["N"].attrs["units"] == "N"
        n = ds["N"].values
        y = ds["y"].values
        assert np.all(n >= 0.0)
    # N is the damped, forced law's: the elastic force alone would differ (c ẏ)
    elastic = P.area * P.c_n * np.clip(y, 0.0, None) ** P.m2
    assert np.max(np.abs(n - elastic)) > 1e-3 * P.mass * P.g
    # a forced model starts from rest at the static deflection: no amplitude needed
    assert y[0] == pytest.approx(P.static_deflection, rel=1e-12)


def test_simulate_takes_the_parts_from_a_config_file(capsys, tmp_path):
    config = tmp_path / "run.toml"
    config.write_text(
        '[damping]\nlaw = "hunt-crossley"\nratio = 0.1\n'
        "[simulate]\nforce = 0.3\namplitude = 1.5e-7\nduration = 0.002\n"
    )
    out = tmp_path / "run.nc"
    status, _, err = run(capsys, "simulate", "--config", config, "--out", out)
    assert status == 0, err
    with xr.open_dataset(out) as ds:
        assert ds.attrs["damping"] == "HuntCrossley"
        assert ds.attrs["damping_ratio"] == 0.1
        assert ds.attrs["excitation"] == "none"


def test_free_vibration_still_needs_its_amplitude(capsys):
    status, _, err = run(capsys, "simulate", "--damping", "viscous", "--damping-ratio", "0.1",
                         "--force", "0.5", "--duration", "0.001")  # fmt: skip
    one_line_failure(status, err, "--amplitude")


def test_info_lists_the_parts(capsys):
    status, out, err = run(capsys, "info", "--json", *FORCED)
    assert status == 0, err
    info = json.loads(out)
    assert info["damping.ratio"]["value"] == 0.05
    assert info["excitation.frequency"] == {
        "value": 1400.0, "unit": "Hz", "description": info["excitation.frequency"]["description"]
    }  # fmt: skip
    k = P.m2 * P.mass * P.g / P.static_deflection
    assert info["damping.coefficient"]["value"] == pytest.approx(2 * 0.05 * np.sqrt(k * P.mass))
    status, out, _ = run(capsys, "info", *FORCED)
    assert "parts: damping=Viscous(ratio=0.05), excitation=HarmonicForce(" in out
    status, out, _ = run(capsys, "info", "--json")
    assert not any("." in key for key in json.loads(out))  # the paper's model: no parts


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["simulate", "--damping", "foo", "--force", "0.5", "--amplitude", "1e-7",
          "--duration", "0.001"], ["unknown damping law 'foo'"]),
        (["simulate", "--damping", "viscous", "--damping-ratio", "10.5", "--force", "0.5",
          "--amplitude", "1e-7", "--duration", "0.001"], ["--damping-ratio", "outside"]),
        (["simulate", "--excitation-frequency", "1400", "--force", "0.5", "--amplitude",
          "1e-7", "--duration", "0.001"], ["--excitation-frequency", "not given"]),
        (["simulate", "--excitation", "harmonic-force", "--excitation-amplitude", "0.5",
          "--excitation-frequency", "1", "--force", "0.5", "--duration", "0.001"],
         ["--excitation-frequency", "1e-3 f0"]),
        (["map", *FORCED, "--force", "0.1:0.5:3", "--out", "m.nc"], ["sweep --param"]),
        (["sweep", "--param", "excitation.frequency=1200,1400", "--force", "0.3",
          "--amplitude", "1e-7", "--out", "s.nc"], ["no excitation part"]),
        (["sweep", *FORCED, "--param", "excitation.frequency=1200,1400", "--force", "0.3",
          "--out", "s.nc"],
         ["--param excitation.frequency=... cannot be combined with --excitation-frequency"]),
        (["sweep", "--damping", "viscous", "--damping-ratio", "0.1", "--param",
          "damping.ratio=0.1,0.2", "--force", "0.3", "--amplitude", "1e-7", "--out", "s.nc"],
         ["--damping-ratio", "--param"]),
        (["sweep", "--excitation", "harmonic-force", "--excitation-amplitude", "0.5",
          "--param", "excitation.frequency=1,1400", "--force", "0.3", "--out", "s.nc"],
         ["excitation.frequency", "outside"]),
    ],
)  # fmt: skip
def test_refusals_before_computing(capsys, tmp_path, monkeypatch, args, words):
    monkeypatch.chdir(tmp_path)
    status, out, err = run(capsys, *args)
    one_line_failure(status, err, *words)
    assert out == ""
    assert list(tmp_path.iterdir()) == []


def test_figures_refuses_parts_in_its_config(capsys, tmp_path):
    config = tmp_path / "run.toml"
    config.write_text('[excitation]\nkind = "harmonic-force"\namplitude = 1.0\n')
    status, _, err = run(capsys, "figures", "--config", config, "--out", tmp_path / "f")
    one_line_failure(status, err, "[excitation]", "paper's model")
    assert not (tmp_path / "f").exists()


def test_sweep_over_excitation_frequency(capsys, tmp_path):
    """A forced sweep: v over force x excitation.frequency (needs the sweeps of Models)."""
    out = tmp_path / "s.nc"
    status, _, err = run(
        capsys, "sweep", "--damping", "viscous", "--damping-ratio", "0.03", "--excitation",
        "harmonic-force", "--excitation-amplitude", "0.5",
        "--param", "excitation.frequency=1200,1500", "--force", "0.2,0.6", "--out", out,
        "--quiet",
    )  # fmt: skip
    assert status == 0, err
    with xr.open_dataset(out) as ds:
        v = ds["mean_velocity"]
        assert v.attrs["units"] == "m s-1"
        assert v.sizes["force"] == 2
        assert 2 in v.sizes.values()  # the frequency axis
        assert ds.attrs["excitation"] == "HarmonicForce"
        values = v.values
        assert np.all(np.isfinite(values)) and np.all(values >= 0.0)
