"""Every flag and config key: typed TOML values, no abbreviations, no flags that do nothing,
``python -m microslip``, CF metadata of the files, and one line for any failure."""

import subprocess
import sys

import numpy as np
import pytest
import xarray as xr
from cli_inprocess import MAP, SIM, one_line_failure, run

import microslip as ms
from microslip.cli.main import main

BAD_TOML = [
    ("map", "[map]\nout = 5\nforce = '0.5'\namplitude = '1e-7'\n", "out"),
    ("map", "[map]\nout = 'm.nc'\nforce = true\namplitude = '1e-7'\n", "force"),
    ("map", "[map]\nout = 'm.nc'\nforce = [0.1, true]\namplitude = '1e-7'\n", "force"),
    ("map", "[map]\nout = 'm.nc'\nforce = 0.5\namplitude = {a = 1}\n", "amplitude"),
    ("map", "[map]\nout = 'm.nc'\nforce = 0.5\namplitude = 1e-7\nworkers = 1.5\n", "workers"),
    ("map", "[map]\nout = 'm.nc'\nforce = 0.5\namplitude = 1e-7\nquiet = 'yes'\n", "quiet"),
    ("sweep", "[sweep]\nout = 'm.nc'\nforce = 0.5\namplitude = 1e-7\nparam = 5\n", "param"),
    ("simulate", "[simulate]\nforce = 'abc'\namplitude = 1e-7\nduration = 0.01\n", "force"),
    ("simulate", "[simulate]\nforce = 0.5\namplitude = 1e-7\nduration = [1, 2]\n", "duration"),
    ("simulate", "[simulate]\nforce = 0.5\namplitude = 1e-7\nduration = true\n", "duration"),
    ("simulate", "[simulate]\nforce = 0.5\namplitude = 1e-7\nduration = nan\n", "duration"),
    ("simulate", "[simulate]\nforce = 0.5\namplitude = 1e-7\nduration = 1\nsamples = 2.5\n",
     "samples"),
    ("simulate", "[simulate]\nforce = 0.5\namplitude = 1e-7\nduration = 1\nmethod = 4\n",
     "method"),
    ("simulate", "[simulate]\nforce = 0.5\ninitial_state = [1, 2]\nduration = 1\n",
     "initial_state"),
    ("simulate", "[simulate]\nforce = 0.5\namplitude = 1e-7\nduration = 1\noverwrite = 1\n",
     "overwrite"),
    ("info", "[parameters]\nmu = true\n", "mu"),
    ("info", "[parameters]\nmass = [1.0]\n", "mass"),
    ("info", "[info]\njson = 'no'\n", "json"),
    ("figures", "[figures]\ndpi = 'high'\n", "dpi"),
]  # fmt: skip


@pytest.mark.parametrize(("command", "text", "key"), BAD_TOML)
def test_toml_value_of_the_wrong_type_is_one_line(capsys, tmp_path, command, text, key):
    config = tmp_path / "run.toml"
    config.write_text(text)
    status, _, err = run(capsys, command, "--config", config)
    one_line_failure(status, err, key, "run.toml")
    assert [p.name for p in tmp_path.iterdir()] == ["run.toml"]


def test_toml_values_of_every_kind_are_accepted(capsys, tmp_path):
    config = tmp_path / "run.toml"
    config.write_text(
        "[parameters]\nmass = 1\n"  # an integer is a number
        "[map]\nforce = [0.2, 0.4]\namplitude = 1.5e-7\nout = 'm.nc'\nquiet = true\n"
    )
    status, out, err = run(capsys, "map", "--config", config, "--out", tmp_path / "m.nc")
    assert status == 0, err
    assert out == ""  # quiet = true was taken
    with xr.open_dataset(tmp_path / "m.nc") as ds:
        np.testing.assert_array_equal(ds["force"].values, [0.2, 0.4])
        assert float(ds["mean_velocity"].sel(force=0.4, amplitude=1.5e-7)) == ms.mean_velocity(
            force=0.4, amplitude=1.5e-7
        )


@pytest.mark.parametrize(
    ("args", "prefix"),
    [
        (["simulate", "--forc", "0.5", "--amplitude", "1e-7", "--duration", "0.01"], "--forc"),
        (["simulate", "--force", "0.5", "--amp", "1e-7", "--duration", "0.01"], "--amp"),
        (["map", "--force", "0.5", "--amplitude", "1e-7", "--meth", "time"], "--meth"),
        (["info", "--js"], "--js"),
        (["figures", "--on", "fig2"], "--on"),
    ],
)
def test_abbreviated_flags_are_refused(capsys, tmp_path, args, prefix):
    status, _, err = run(capsys, *args)
    one_line_failure(status, err, "unrecognized arguments", prefix)
    assert list(tmp_path.iterdir()) == []


NO_OP = [
    ([*SIM, "--dt", "1e-6"], "--dt", "event"),
    ([*SIM, "--method", "rk4", "--rtol", "1e-6"], "--rtol", "rk4"),
    ([*SIM, "--method", "rk4", "--atol", "1e-6"], "--atol", "rk4"),
    ([*SIM, "--samples", "10", "--save-every", "2"], "--samples", "--save-every"),
    ([*MAP, "--dt", "1e-6"], "--dt", "steady"),
    ([*MAP, "--duration", "0.1"], "--duration", "steady"),
    ([*MAP, "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], "--workers", "--scheduler"),
    (["sweep", "--param", "mu=0.1,0.2", *MAP[1:], "--dt", "1e-6"], "--dt", "steady"),
]  # fmt: skip


@pytest.mark.parametrize(("args", "flag", "why"), NO_OP)
def test_flags_that_would_do_nothing_are_refused(capsys, tmp_path, args, flag, why):
    out = tmp_path / ("run.nc" if args[0] == "simulate" else "map.nc")
    status, _, err = run(capsys, *args, "--out", out)
    one_line_failure(status, err, flag, why)
    assert list(tmp_path.iterdir()) == []


def test_config_key_that_would_do_nothing_is_named(capsys, tmp_path):
    config = tmp_path / "run.toml"
    config.write_text("[map]\ndt = 1e-6\n")
    status, _, err = run(capsys, *MAP, "--out", tmp_path / "m.nc", "--config", config)
    one_line_failure(status, err, "dt in [map] of", "run.toml", "steady")
    # The flag that makes it meaningful, given on the command line, makes it valid.
    config.write_text("[map]\nmethod = 'time'\n")
    status, _, err = run(capsys, *MAP, "--out", tmp_path / "m.nc", "--config", config, "--dt", "1")
    one_line_failure(status, err, "dt")  # now checked as a time step: too large


def test_python_dash_m_microslip():
    result = subprocess.run(
        [sys.executable, "-m", "microslip", "info", "--json"], capture_output=True, text=True
    )
    assert result.returncode == 0, result.stderr
    assert '"natural_frequency"' in result.stdout
    version = subprocess.run(
        [sys.executable, "-m", "microslip", "--version"], capture_output=True, text=True
    )
    assert version.stdout.strip() == f"microslip {ms.__version__}"


def _check_cf(path, command):
    with xr.open_dataset(path) as ds:
        attrs = ds.attrs
        assert attrs["Conventions"] == "CF-1.10"
        assert attrs["source"] == f"microslip {ms.__version__}"
        assert "Grudzinski" in attrs["references"] and "43(1)" in attrs["references"]
        assert attrs["title"].startswith("microslip")
        assert f" {command} " in attrs["history"] and "--force" in attrs["history"]
        for name in [*ds.data_vars, *ds.coords]:
            var = ds[name]
            if "flag_values" in var.attrs:
                assert len(var.attrs["flag_meanings"].split()) == len(var.attrs["flag_values"])
            else:
                assert var.attrs.get("units"), name


def test_netcdf_outputs_carry_cf_metadata(capsys, tmp_path):
    assert run(capsys, *SIM, "--out", tmp_path / "run.nc")[0] == 0
    _check_cf(tmp_path / "run.nc", "simulate")
    assert run(capsys, *MAP, "--out", tmp_path / "map.nc")[0] == 0
    _check_cf(tmp_path / "map.nc", "map")
    sweep = ["sweep", "--param", "mu=0.1,0.2", *MAP[1:], "--out", tmp_path / "s.nc"]
    assert run(capsys, *sweep)[0] == 0
    _check_cf(tmp_path / "s.nc", "sweep")
    with xr.open_dataset(tmp_path / "s.nc") as ds:
        assert ds["mu"].attrs["units"] == "1"


def test_unexpected_error_is_one_line_unless_debugging(capsys, monkeypatch):
    import microslip.cli.commands as commands

    def broken(args):
        raise KeyError("boom")

    monkeypatch.setattr(commands, "cmd_info", broken)
    monkeypatch.setattr("microslip.cli.parser.cmd_info", broken)
    monkeypatch.delenv("MICROSLIP_DEBUG", raising=False)
    status, _, err = run(capsys, "info")
    one_line_failure(status, err, "internal error", "KeyError", "please report")
    monkeypatch.setenv("MICROSLIP_DEBUG", "1")
    with pytest.raises(KeyError):
        main(["info"])


def test_simulate_thins_long_output_with_the_budget_and_says_so(capsys, monkeypatch, tmp_path):
    import microslip.budget as budget

    asked = {}

    def save_every(params, *, duration, method, dt=None, **kwargs):
        asked.update(duration=duration, method=method, dt=dt)
        return 7

    monkeypatch.setattr(budget, "default_save_every", save_every)
    status, _, err = run(capsys, *SIM, "--method", "rk4", "--out", tmp_path / "run.nc")
    assert status == 0, err
    assert asked == {"duration": 0.002, "method": "rk4", "dt": None}
    assert len(err.strip().splitlines()) == 1 and "1 step in 7" in err
    reference = ms.simulate(force=0.5, amplitude=1.5e-7, duration=0.002, method="rk4", save_every=7)
    with xr.open_dataset(tmp_path / "run.nc") as ds:
        np.testing.assert_array_equal(ds["time"].values, reference.t)
    # An explicit choice is kept, and nothing is said.
    status, _, err = run(capsys, *SIM, "--save-every", "3")
    assert status == 0 and err == ""


def test_allow_large_reaches_the_budget_checks(capsys, monkeypatch, tmp_path):
    from microslip.sweeps import SweepSpec

    seen = []

    def check_budget(self, *, allow_large=False):  # records the flag, checks nothing
        seen.append(allow_large)
        return self.estimate()

    monkeypatch.setattr(SweepSpec, "check_budget", check_budget)
    assert run(capsys, *MAP, "--out", tmp_path / "a.nc")[0] == 0
    assert run(capsys, *MAP, "--out", tmp_path / "b.nc", "--allow-large")[0] == 0
    assert seen == [False, True]
    real = ms.simulate
    calls = []

    def spy(*args, **kwargs):
        calls.append(kwargs.get("allow_large"))
        return real(*args, **kwargs)

    monkeypatch.setattr(ms, "simulate", spy)
    assert run(capsys, *SIM)[0] == 0
    assert run(capsys, *SIM, "--allow-large")[0] == 0
    assert calls == [False, True]
