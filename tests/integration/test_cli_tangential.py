"""The tangential side on the command line: --tangential, --friction and --drive (and their
TOML tables) in simulate and info; --force against a drive; map, sweep and response refuse
a tangential side other than the paper's in one line (exit 2) before computing, but for a
compliant contact in a time sweep (--method time): a spring agrees with the event method,
a Mindlin spring is the rk4 runs of simulate.

The trajectories are checked against closed forms of the drives (F of a harmonic drive
and of a drive spring, x = v t of a prescribed velocity), the linear contact spring
f = k_t (x - u), and the identity of a ConstantForce drive with the same --force."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from cli_inprocess import one_line_failure, run

import microslip as ms

P = ms.Parameters()
RUN = ["--amplitude", "1e-7", "--duration", "0.006"]
COMPLIANT = ["--tangential", "spring", "--tangential-stiffness", "1e6"]
STATIC_KINETIC = ["--friction", "static-kinetic", "--friction-mu-static", "0.2",
                  "--friction-mu-kinetic", "0.12"]  # fmt: skip


def simulate(capsys, tmp_path, *flags, name="run.nc"):
    out = tmp_path / name
    status, stdout, err = run(capsys, "simulate", *flags, "--out", out)
    assert status == 0, err
    assert "simulated" in stdout
    return xr.open_dataset(out)


def test_harmonic_drive_force_and_the_tangential_parts_in_the_file(capsys, tmp_path):
    f0, f1, fd = 0.1, 0.3, 150.0
    flags = [*COMPLIANT, *STATIC_KINETIC, "--drive", "harmonic", "--drive-mean", str(f0),
             "--drive-amplitude", str(f1), "--drive-frequency", str(fd), *RUN]  # fmt: skip
    with simulate(capsys, tmp_path, *flags) as ds:
        assert ds.attrs["tangential"] == "TangentialSpring"
        assert ds.attrs["tangential_stiffness"] == 1e6
        assert ds.attrs["friction"] == "StaticKinetic"
        assert ds.attrs["friction_mu_static"] == 0.2
        assert ds.attrs["drive"] == "HarmonicDrive"
        assert ds.attrs["drive_frequency"] == fd
        for name, unit in (("u", "m"), ("spring_force", "N"), ("F", "N")):
            assert ds[name].attrs["units"] == unit
        t = ds["time"].values
        np.testing.assert_allclose(
            ds["F"].values, f0 + f1 * np.sin(2 * np.pi * fd * t), rtol=0, atol=1e-12
        )
        assert np.ptp(ds["x"].values) > 0.0


def test_compliant_contact_spring_is_linear_in_x_minus_u(capsys, tmp_path):
    """f = k_t (x - u) for the constant-stiffness spring, through stick and slip
    (Coulomb friction: mu_s = mu_k, no force drop at slip starts)."""
    k_t = 1e6
    flags = ["--tangential", "spring", "--tangential-stiffness", str(k_t), "--drive",
             "harmonic", "--drive-mean", "0.1", "--drive-amplitude", "0.3",
             "--drive-frequency", "150", *RUN]  # fmt: skip
    with simulate(capsys, tmp_path, *flags) as ds:
        x, u, f = ds["x"].values, ds["u"].values, ds["spring_force"].values
        state = ds["state"].values
    np.testing.assert_allclose(f, k_t * (x - u), rtol=0, atol=1e-9 * np.max(np.abs(f)))
    assert np.max(np.abs(f)) > 0.1 and len(set(state.tolist())) >= 2  # stick and slip


def test_spring_drive_and_prescribed_velocity_follow_their_laws(capsys, tmp_path):
    k, v = 1e5, 2e-4
    flags = ["--drive", "spring", "--drive-stiffness", str(k), "--drive-velocity", str(v), *RUN]
    with simulate(capsys, tmp_path, *flags, name="spring.nc") as ds:
        t, x = ds["time"].values, ds["x"].values
        np.testing.assert_allclose(ds["F"].values, k * (v * t - x), rtol=1e-12, atol=1e-15)
        assert "u" not in ds  # a rigid contact has no contact point
    flags = ["--drive", "prescribed-velocity", "--drive-velocity", "1e-3", *COMPLIANT, *RUN]
    with simulate(capsys, tmp_path, *flags, name="kinematic.nc") as ds:
        t = ds["time"].values
        np.testing.assert_allclose(ds["x"].values, 1e-3 * t, rtol=1e-12, atol=1e-18)
        np.testing.assert_allclose(ds["xdot"].values, 1e-3, rtol=1e-12)
        assert ds.attrs["drive"] == "PrescribedVelocity"


def test_constant_force_drive_is_the_force_flag(capsys, tmp_path):
    flags = ["--duration", "0.004", "--amplitude", "1.5e-7", "--samples", "50"]
    with simulate(capsys, tmp_path, "--force", "0.5", *flags, name="force.nc") as by_flag:
        x_flag = by_flag["x"].values
        assert "F" not in by_flag
    drive = ["--drive", "constant-force", "--drive-force", "0.5"]
    with simulate(capsys, tmp_path, *drive, *flags, name="drive.nc") as by_drive:
        np.testing.assert_array_equal(by_drive["x"].values, x_flag)
        np.testing.assert_array_equal(by_drive["F"].values, 0.5)
        assert by_drive.attrs["drive_force"] == 0.5
    assert np.ptp(x_flag) > 0.0  # it slid: the comparison is not of two rests


def test_the_tangential_tables_of_a_config_file(capsys, tmp_path):
    config = tmp_path / "run.toml"
    config.write_text(
        '[tangential]\nkind = "mindlin"\nratio = 0.8\n'
        '[friction]\nlaw = "static-kinetic"\nmu_static = 0.2\nmu_kinetic = 0.15\n'
        '[drive]\nkind = "constant-force"\nforce = 0.4\n'
        "[simulate]\namplitude = 1e-7\nduration = 0.002\n"
    )
    with simulate(capsys, tmp_path, "--config", config) as ds:
        assert ds.attrs["tangential"] == "MindlinSpring"
        assert ds.attrs["tangential_ratio"] == 0.8
        assert ds.attrs["friction_mu_kinetic"] == 0.15
        np.testing.assert_array_equal(ds["F"].values, 0.4)
        assert {"u", "spring_force"} <= set(ds.data_vars)
    # a --force in the file conflicts with the file's drive: named by its key
    config.write_text(config.read_text().replace("amplitude", "force = 0.3\namplitude"))
    status, _, err = run(capsys, "simulate", "--config", config)
    one_line_failure(status, err, "force in [simulate] of", "drive constant-force",
                     "kind in [drive] of", "--drive-force")  # fmt: skip


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["simulate", "--drive", "harmonic", "--drive-mean", "0", "--drive-amplitude", "1",
          "--drive-frequency", "100", "--force", "0.3", *RUN],
         ["--force cannot be combined with drive harmonic (--drive)", "remove --force"]),
        (["simulate", *RUN], ["--force is required", "--drive"]),
        (["simulate", "--drive", "constant-force", *RUN], ["needs --drive-force [N]"]),
        (["simulate", "--drive-force", "0.3", *RUN], ["--drive-force", "not given"]),
        (["map", *COMPLIANT, "--force", "0.1:0.5:3", "--amplitude", "1e-7", "--out", "m.nc"],
         ["--tangential: microslip map does not support tangential=TangentialSpring",
          "--method time", "microslip simulate", "microslip friction"]),
        (["map", "--drive", "constant-force", "--drive-force", "0.3", "--force", "0.1:0.5:3",
          "--amplitude", "1e-7", "--out", "m.nc"], ["--drive:", "drive=ConstantForce"]),
        (["sweep", *STATIC_KINETIC, "--param", "m2=1.5,2", "--force", "0.3",
          "--amplitude", "1e-7", "--out", "s.nc"],
         ["--friction: microslip sweep does not support friction=StaticKinetic"]),
        (["sweep", "--tangential", "spring", "--param", "tangential.stiffness=1e6,2e6",
          "--force", "0.3", "--amplitude", "1e-7", "--out", "s.nc"],
         ["tangential=TangentialSpring"]),
        (["response", "--excitation", "harmonic-force", "--excitation-amplitude", "0.5",
          "--frequencies", "1000:1500", *STATIC_KINETIC, "--out", "r.nc"],
         ["--friction: microslip response does not support friction=StaticKinetic"]),
        (["response", "--excitation", "harmonic-force", "--excitation-amplitude", "0.5",
          "--frequencies", "1000:1500", "--drive", "prescribed-velocity", "--drive-velocity",
          "1e-3"], ["--drive: microslip response", "drive=PrescribedVelocity"]),
    ],
)  # fmt: skip
def test_refusals_before_computing(capsys, tmp_path, monkeypatch, args, words):
    monkeypatch.chdir(tmp_path)
    status, out, err = run(capsys, *args)
    one_line_failure(status, err, *words)
    assert out == ""
    assert list(tmp_path.iterdir()) == []


def test_map_with_the_paper_kinds_named_is_the_papers_map(capsys, tmp_path):
    grid = ["--force", "0.2,0.6", "--amplitude", "1e-7,2e-7", "--quiet"]
    status, _, err = run(capsys, "map", *grid, "--out", tmp_path / "paper.nc")
    assert status == 0, err
    status, _, err = run(capsys, "map", *grid, "--tangential", "rigid", "--friction",
                         "coulomb", "--drive", "none", "--out", tmp_path / "named.nc")  # fmt: skip
    assert status == 0, err
    with xr.open_dataset(tmp_path / "paper.nc") as a, xr.open_dataset(tmp_path / "named.nc") as b:
        np.testing.assert_array_equal(a["mean_velocity"].values, b["mean_velocity"].values)
        assert np.any(a["mean_velocity"].values > 0.0)


@pytest.mark.parametrize(
    ("flags", "model"),
    [
        (["spring", "--tangential-stiffness", str(4.0 * P.contact_stiffness)],
         ms.Model(P, tangential=ms.TangentialSpring(4.0 * P.contact_stiffness))),
        (["mindlin", "--tangential-ratio", "0.8235"],
         ms.Model(P, tangential=ms.MindlinSpring(0.8235))),
    ],
    ids=["spring", "mindlin"],
)  # fmt: skip
def test_time_sweep_of_a_compliant_contact(capsys, tmp_path, flags, model):
    """--method time takes a compliant contact, from the paper's initial state at the
    step of the faster of the normal and tangential oscillations (k_t = 4 K_n: the
    tangential one). A spring runs on the spring-lane kernel, a Mindlin spring on the
    Mindlin-lane kernel: x(T)/T agrees with the event method (rtol 1e-12) to 1e-6 of
    the largest."""
    out = tmp_path / "compliant.nc"
    grid = ["--force", "0.2,0.6", "--amplitude", "1e-7,2.5e-7", "--method", "time",
            "--duration", "0.004"]  # fmt: skip
    status, _, err = run(capsys, "sweep", "--tangential", *flags, *grid, "--quiet", "--out", out)
    assert status == 0, err
    with xr.open_dataset(out) as ds:
        v = ds["mean_velocity"]
        assert ds.attrs["tangential"] == type(model.tangential).__name__
        scale = float(np.abs(v).max())
        assert scale > 0.0
        for force in (0.2, 0.6):
            for amplitude in (1e-7, 2.5e-7):
                value = float(v.sel(force=force, amplitude=amplitude))
                r = ms.simulate(model, force=force, amplitude=amplitude, duration=0.004,
                                rtol=1e-12)  # fmt: skip
                assert abs(value - r.x[-1] / 0.004) <= 1e-6 * scale


def test_info_shows_the_tangential_parts_with_units(capsys):
    flags = [
        "--tangential", "mindlin", "--tangential-ratio", "0.8", *STATIC_KINETIC,
        "--drive", "spring", "--drive-stiffness", "1e5", "--drive-velocity", "1e-4",
    ]  # fmt: skip
    status, out, err = run(capsys, "info", "--json", *flags)
    assert status == 0, err
    info = json.loads(out)
    expected = {
        "tangential.ratio": (0.8, "1"), "friction.mu_static": (0.2, "1"),
        "friction.mu_kinetic": (0.12, "1"), "drive.stiffness": (1e5, "N m-1"),
        "drive.velocity": (1e-4, "m s-1"),
    }  # fmt: skip
    for name, (value, unit) in expected.items():
        assert (info[name]["value"], info[name]["unit"]) == (value, unit), name
    # k_t = lambda K_n at the static deflection, K_n = m2 m g / y0
    y0 = (P.mass * P.g / (P.area * P.c_n)) ** (1.0 / P.m2)
    k_t = info["tangential.stiffness_at_y0"]
    assert k_t["unit"] == "N m-1"
    assert k_t["value"] == pytest.approx(0.8 * P.m2 * P.mass * P.g / y0, rel=1e-12)
    assert "unused" in info["mu"]["description"]  # StaticKinetic has its own coefficients
    status, out, _ = run(capsys, "info", *flags)
    assert "tangential=MindlinSpring(ratio=0.8)" in out
    assert "friction=StaticKinetic(mu_static=0.2, mu_kinetic=0.12)" in out
    assert "drive=SpringDrive(stiffness=100000.0, velocity=0.0001)" in out
    assert "drive.velocity" in out and "m s-1" in out
    status, out, _ = run(capsys, "info", "--tangential", "rigid")
    assert "tangential=Rigid()" in out
