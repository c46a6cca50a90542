"""The command line as a user sees it: outputs, units, and every error path (exit 2)."""

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import microslip as ms


def test_info_json_matches_the_paper(cli):
    result = cli("info", "--json")
    assert result.returncode == 0, result.stderr
    info = json.loads(result.stdout)
    assert info["static_deflection"]["unit"] == "m"
    assert info["static_deflection"]["value"] == pytest.approx(2.25e-7, rel=2e-3)
    assert info["natural_frequency"]["value"] == pytest.approx(1485.0, rel=1e-3)
    assert info["natural_frequency"]["unit"] == "Hz"


def test_info_takes_parameter_flags_and_config(cli, tmp_path):
    config = tmp_path / "model.toml"
    config.write_text("[parameters]\nmu = 0.2\nmass = 2.0\n")
    result = cli("info", "--json", "--config", str(config), "--mass", "4")
    assert result.returncode == 0, result.stderr
    info = json.loads(result.stdout)
    assert info["mu"]["value"] == 0.2  # from the file
    assert info["mass"]["value"] == 4.0  # the flag wins
    assert info["static_friction_force"]["value"] == pytest.approx(0.2 * 4.0 * 9.81)


def test_simulate_writes_netcdf_with_units(cli, tmp_path):
    out = tmp_path / "run.nc"
    result = cli(
        "simulate", "--force", "0.5", "--amplitude", "1.5e-7", "--duration", "0.003",
        "--out", str(out),
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    ds = xr.open_dataset(out)
    for name in [*ds.data_vars, *ds.coords]:
        assert ds[name].attrs.get("units"), name
    assert float(ds.time[-1]) == 0.003
    reference = ms.simulate(force=0.5, amplitude=1.5e-7, duration=0.003)
    np.testing.assert_array_equal(ds["x"].values, reference.x)


def test_simulate_csv_and_config_and_rk4(cli, tmp_path):
    config = tmp_path / "run.toml"
    config.write_text(
        "[parameters]\nmu = 0.1\n[simulate]\nforce = 0.5\namplitude = 1.5e-7\n"
        "duration = 0.002\nmethod = 'rk4'\n"
    )
    out = tmp_path / "run.csv"
    result = cli("simulate", "--config", str(config), "--out", str(out))
    assert result.returncode == 0, result.stderr
    header = out.read_text().splitlines()[0]
    assert header.startswith("time [s],y [m],ydot [m s-1],x [m]")


def test_simulate_plot(cli, tmp_path):
    plot = tmp_path / "run.png"
    result = cli(
        "simulate", "--force", "0.5", "--amplitude", "1.5e-7", "--duration", "0.002",
        "--plot", str(plot), "--samples", "400",
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


BAD_SIMULATE = [
    (["--force", "abc", "--amplitude", "1e-7", "--duration", "0.01"], "--force"),
    (["--force", "0.5", "--amplitude", "-1e-7", "--duration", "0.01"], "amplitude"),
    (["--force", "0.5", "--amplitude", "1e-7", "--duration", "-1"], "duration"),
    (["--force", "0.5", "--amplitude", "1e-7", "--duration", "nan"], "--duration"),
    (["--force", "0.5", "--amplitude", "1e-7", "--duration", "0.01", "--mass", "0"], "mass"),
    (["--force", "0.5", "--amplitude", "1e-7", "--duration", "0.01", "--area", "-2"], "area"),
    (["--force", "0.5", "--amplitude", "1e-7", "--duration", "0.01", "--c-n", "inf"], "c_n"),
    (["--force", "0.5", "--amplitude", "1e-7", "--duration", "0.01", "--m2", "0"], "m2"),
    (["--force", "0.5", "--amplitude", "1e-7", "--duration", "0.01", "--mu", "-0.1"], "mu"),
    (["--force", "0.5", "--amplitude", "1e-7", "--duration", "0.01", "--method", "euler"],
     "method"),
    (["--force", "0.5", "--amplitude", "1e-7", "--duration", "0.01", "--method", "rk4",
      "--dt", "1e-4"], "dt"),
    (["--force", "0.5", "--duration", "0.01"], "amplitude"),
    (["--amplitude", "1e-7", "--duration", "0.01"], "force"),
]  # fmt: skip


@pytest.mark.parametrize(("args", "field"), BAD_SIMULATE)
def test_simulate_bad_input_is_one_line_exit_2(cli, tmp_path, args, field):
    out = tmp_path / "run.nc"
    result = cli("simulate", *args, "--out", str(out))
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    assert field in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1  # no usage dump
    assert not out.exists()
    assert list(tmp_path.iterdir()) == []


def test_unreadable_config_and_unknown_keys(cli, tmp_path):
    missing = cli("info", "--config", str(tmp_path / "nope.toml"))
    assert missing.returncode == 2 and "nope.toml" in missing.stderr
    broken = tmp_path / "broken.toml"
    broken.write_text("[parameters\nmu = ")
    result = cli("info", "--config", str(broken))
    assert result.returncode == 2 and "broken.toml" in result.stderr
    unknown = tmp_path / "unknown.toml"
    unknown.write_text("[parameters]\nfriction = 0.3\n")
    result = cli("info", "--config", str(unknown))
    assert result.returncode == 2 and "friction" in result.stderr
    wrong_type = tmp_path / "wrong.toml"
    wrong_type.write_text("[parameters]\nmu = 'high'\n")
    result = cli("info", "--config", str(wrong_type))
    assert result.returncode == 2 and "mu" in result.stderr
    assert "Traceback" not in result.stderr


def test_unwritable_output_leaves_nothing(cli, tmp_path):
    result = cli(
        "simulate", "--force", "0.5", "--amplitude", "1e-7", "--duration", "0.001",
        "--out", str(tmp_path / "missing-dir" / "run.nc"),
    )  # fmt: skip
    assert result.returncode == 2 and "missing-dir" in result.stderr
    result = cli(
        "simulate", "--force", "0.5", "--amplitude", "1e-7", "--duration", "0.001",
        "--out", str(tmp_path / "run.txt"),
    )  # fmt: skip
    assert result.returncode == 2 and "suffix" in result.stderr
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux /proc")
@pytest.mark.parametrize("command", ["simulate", "map"])
def test_directory_that_refuses_files(cli, command):
    # /proc exists and passes os.access for root, but no file can be created in it.
    args = ["--force", "0.5", "--amplitude", "1e-7", "--out", "/proc/microslip-run.nc"]
    if command == "simulate":
        args += ["--duration", "0.001"]
    result = cli(command, *args)
    assert result.returncode == 2
    assert "'/proc' is not writable" in result.stderr and "Traceback" not in result.stderr


BAD_MAP = [
    (["--force", "0.9:0.1:5", "--amplitude", "0:3e-7:4"], "reversed"),
    (["--force", "0.1:0.9:0", "--amplitude", "0:3e-7:4"], "count"),
    (["--force", "0.1:0.9:5", "--amplitude", "nan"], "finite"),
    (["--force", "0.1:0.9:5", "--amplitude", "0:3e-7"], "start:stop:count"),
    (["--force", "0.1:0.9:5", "--amplitude", "0:3e-7:4", "--workers", "0"], "workers"),
    (["--force", "-0.1,0.5", "--amplitude", "0:3e-7:4"], "force"),
]  # fmt: skip


@pytest.mark.parametrize(("args", "message"), BAD_MAP)
def test_map_bad_input(cli, tmp_path, args, message):
    out = tmp_path / "map.nc"
    result = cli("map", *args, "--out", str(out), "--quiet")
    assert result.returncode == 2, result.stdout
    assert message in result.stderr
    assert "Traceback" not in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_sweep_unknown_parameter(cli, tmp_path):
    result = cli(
        "sweep", "--param", "stiffness=1:2:3", "--force", "0.5", "--amplitude", "1e-7",
        "--out", str(tmp_path / "s.nc"),
    )  # fmt: skip
    assert result.returncode == 2
    assert "stiffness" in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_map_writes_netcdf_and_plot(cli, tmp_path):
    out, plot = tmp_path / "map.nc", tmp_path / "map.png"
    result = cli(
        "map", "--force", "0.1:0.9:9", "--amplitude", "0:3e-7:7", "--out", str(out),
        "--plot", str(plot),
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    ds = xr.open_dataset(out)
    assert ds["mean_velocity"].dims == ("force", "amplitude")
    assert ds["mean_velocity"].attrs["units"] == "m s-1"
    assert ds["force"].attrs["units"] == "N" and ds["amplitude"].attrs["units"] == "m"
    expected = ms.mean_velocity(force=0.5, amplitude=1.5e-7)
    assert float(ds["mean_velocity"].sel(force=0.5, amplitude=1.5e-7)) == expected
    assert plot.stat().st_size > 10_000
    assert not (tmp_path / "map.nc.partial.zarr").exists()


def test_sweep_over_parameters(cli, tmp_path):
    out = tmp_path / "sweep.nc"
    result = cli(
        "sweep", "--param", "mu=0.08,0.12", "--param", "m2=1.5:2.5:3", "--force", "0.5",
        "--amplitude", "1e-7,2e-7", "--out", str(out), "--quiet",
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    v = xr.open_dataset(out)["mean_velocity"]
    assert v.dims == ("mu", "m2", "force", "amplitude")
    assert v.shape == (2, 3, 1, 2)
    p = ms.Parameters(mu=0.12, m2=1.5)
    assert float(v.sel(mu=0.12, m2=1.5, force=0.5, amplitude=2e-7)) == ms.mean_velocity(
        p, force=0.5, amplitude=2e-7
    )


@pytest.mark.parametrize(
    ("axes", "force", "amplitude"),
    [
        (["--param", "mu=0.08,0.12", "--param", "m2=1.5,2"], "0.1:0.9:5", "0:3e-7:4"),  # panels
        (["--param", "mu=0.08,0.12"], "0.1:0.9:5", "2e-7"),  # curves against F
        (["--param", "m2=1.5:2.5:5"], "0.5", "2e-7"),  # curve against a parameter
        ([], "0.5", "0:3e-7:11"),  # curve against A
    ],
    ids=["panels", "curves-F", "curve-m2", "curve-A"],
)
def test_sweep_plots(cli, tmp_path, axes, force, amplitude):
    out, plot = tmp_path / "sweep.nc", tmp_path / "sweep.png"
    result = cli(
        "sweep", *axes, "--force", force, "--amplitude", amplitude, "--out", str(out),
        "--plot", str(plot), "--quiet",
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert out.exists()


@pytest.mark.parametrize(
    ("axes", "force", "amplitude", "message"),
    [
        (["--param", "mu=0.1:0.2:5", "--param", "m2=1:3:6"], "0.1:0.9:5", "0:3e-7:4", "30 maps"),
        (["--param", "mu=0.1:0.2:13"], "0.5", "0:3e-7:4", "13 curves"),
        ([], "0.5", "2e-7", "single point"),
    ],
    ids=["too-many-maps", "too-many-curves", "single-point"],
)
def test_sweep_plot_refused_before_computing(cli, tmp_path, axes, force, amplitude, message):
    result = cli(
        "sweep", *axes, "--force", force, "--amplitude", amplitude,
        "--out", str(tmp_path / "s.nc"), "--plot", str(tmp_path / "s.png"),
    )  # fmt: skip
    assert result.returncode == 2
    assert message in result.stderr and "Traceback" not in result.stderr
    assert list(tmp_path.iterdir()) == []
