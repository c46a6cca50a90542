"""The model's parts from flags and TOML tables (cli/model_options.py): every flag, every
refusal (one line naming where the value came from), and flags overriding the file."""

from __future__ import annotations

import pytest

import microslip as ms
from microslip.cli.main import build_parser
from microslip.cli.model_options import kind_name
from microslip.cli.options import CliError, gather

P = ms.Parameters()
F0 = P.natural_frequency


def model_of(tmp_path, *flags, toml: str | None = None, command: str = "info", provided=None):
    argv = [command, *flags]
    if toml is not None:
        config = tmp_path / "run.toml"
        config.write_text(toml)
        argv += ["--config", str(config)]
    args = build_parser().parse_args([str(a) for a in argv])
    return gather(args, command).model(provided)


def refused(tmp_path, *flags, toml=None, provided=None) -> str:
    with pytest.raises(ValueError) as error:
        model_of(tmp_path, *flags, toml=toml, provided=provided)
    text = str(error.value)
    assert "\n" not in text
    return text


def test_no_part_is_the_paper_model(tmp_path):
    model = model_of(tmp_path)
    assert model == ms.Model(P)
    assert model.is_paper


@pytest.mark.parametrize(
    ("flags", "expected"),
    [
        (["--damping", "viscous", "--damping-ratio", "0.03"], ms.Model(P, ms.Viscous(0.03))),
        (
            ["--damping", "hunt-crossley", "--damping-ratio", "0.2"],
            ms.Model(P, ms.HuntCrossley(0.2)),
        ),
        (["--damping", "none"], ms.Model(P)),
        (["--excitation", "none"], ms.Model(P)),
        (
            ["--excitation", "harmonic-force", "--excitation-amplitude", "0.5",
             "--excitation-frequency", "1400"],
            ms.Model(P, excitation=ms.HarmonicForce(amplitude=0.5, frequency=1400.0)),
        ),
        (
            ["--excitation", "base-motion", "--excitation-amplitude", "2e-8",
             "--excitation-frequency", "900"],
            ms.Model(P, excitation=ms.BaseMotion(amplitude=2e-8, frequency=900.0)),
        ),
        (
            ["--excitation", "prescribed-penetration", "--excitation-mean", "2e-7",
             "--excitation-amplitude", "1e-7", "--excitation-frequency", "1000"],
            ms.Model(P, excitation=ms.PrescribedPenetration(2e-7, 1e-7, 1000.0)),
        ),
        (
            ["--damping", "viscous", "--damping-ratio", "0.05", "--excitation",
             "harmonic-force", "--excitation-amplitude", "1", "--excitation-frequency", "1500",
             "--mu", "0.2"],
            ms.Model(P.replace(mu=0.2), ms.Viscous(0.05), ms.HarmonicForce(1.0, 1500.0)),
        ),
    ],
)  # fmt: skip
def test_every_flag_builds_its_part(tmp_path, flags, expected):
    assert model_of(tmp_path, *flags) == expected


@pytest.mark.parametrize("command", ["simulate", "map", "sweep", "response", "info"])
def test_every_model_command_takes_the_parts(tmp_path, command):
    model = model_of(tmp_path, "--damping", "viscous", "--damping-ratio", "0.1", command=command)
    assert model.damping == ms.Viscous(0.1)


def test_toml_tables_build_the_parts(tmp_path):
    toml = (
        "[parameters]\nmu = 0.2\n"
        '[damping]\nlaw = "viscous"\nratio = 0.03\n'
        '[excitation]\nkind = "harmonic-force"\namplitude = 0.5\nfrequency = 1400\n'
    )
    model = model_of(tmp_path, toml=toml)
    assert model == ms.Model(P.replace(mu=0.2), ms.Viscous(0.03), ms.HarmonicForce(0.5, 1400.0))


def test_a_flag_overrides_the_files_field(tmp_path):
    toml = (
        '[damping]\nlaw = "viscous"\nratio = 0.03\n'
        '[excitation]\nkind = "harmonic-force"\namplitude = 0.5\nfrequency = 1400.0\n'
    )
    model = model_of(tmp_path, "--damping-ratio", "0.07", "--excitation-frequency", "1300",
                     toml=toml)  # fmt: skip
    assert model.damping == ms.Viscous(0.07)
    assert model.excitation == ms.HarmonicForce(0.5, 1300.0)  # amplitude from the file


def test_the_same_kind_by_flag_keeps_the_files_fields(tmp_path):
    toml = '[damping]\nlaw = "viscous"\nratio = 0.03\n'
    assert model_of(tmp_path, "--damping", "viscous", toml=toml).damping == ms.Viscous(0.03)


def test_another_kind_by_flag_replaces_the_files_part(tmp_path):
    # an amplitude in N of a harmonic force must not become one in m of a base motion
    toml = '[excitation]\nkind = "harmonic-force"\namplitude = 0.5\nfrequency = 1400.0\n'
    text = refused(tmp_path, "--excitation", "base-motion", toml=toml)
    assert "--excitation-amplitude [m]" in text
    model = model_of(tmp_path, "--excitation", "base-motion", "--excitation-amplitude", "1e-8",
                     "--excitation-frequency", "1000", toml=toml)  # fmt: skip
    assert model.excitation == ms.BaseMotion(1e-8, 1000.0)


def test_none_by_flag_switches_the_files_part_off(tmp_path):
    toml = '[damping]\nlaw = "hunt-crossley"\nratio = 0.03\n'
    assert model_of(tmp_path, "--damping", "none", toml=toml).damping is None


@pytest.mark.parametrize(
    ("flags", "toml", "words"),
    [
        (["--damping-ratio", "0.1"], None,
         ["--damping-ratio", "not given", "--damping {viscous,hunt-crossley}"]),
        (["--excitation-frequency", "1400"], None, ["--excitation-frequency", "not given"]),
        ([], "[damping]\nratio = 0.1\n", ["ratio in [damping] of", "run.toml", "not given"]),
        (["--damping", "none", "--damping-ratio", "0.1"], None,
         ["--damping-ratio has no effect with damping none"]),
        ([], '[damping]\nlaw = "none"\nratio = 0.1\n',
         ["ratio in [damping]", "no effect with damping none"]),
        (["--damping", "dashpot"], None, ["--damping", "unknown damping law 'dashpot'",
                                          "viscous, hunt-crossley"]),
        ([], '[damping]\nlaw = "Viscous"\nratio = 0.1\n',
         ["law in [damping] of", "unknown damping law 'Viscous'"]),
        (["--excitation", "shaker"], None, ["unknown excitation kind 'shaker'"]),
        (["--damping", "viscous"], None, ["needs --damping-ratio [1]"]),
        (["--excitation", "harmonic-force", "--excitation-frequency", "1400"], None,
         ["needs --excitation-amplitude [N]"]),
        (["--excitation", "harmonic-force", "--excitation-amplitude", "0.5"], None,
         ["needs --excitation-frequency [Hz]"]),
        (["--excitation", "prescribed-penetration", "--excitation-amplitude", "1e-8",
          "--excitation-frequency", "1000"], None, ["needs --excitation-mean [m]"]),
        (["--excitation", "base-motion", "--excitation-amplitude", "1e-8",
          "--excitation-frequency", "1000", "--excitation-mean", "1e-7"], None,
         ["--excitation-mean has no effect with excitation base-motion"]),
        (["--damping", "viscous", "--damping-ratio", "11"], None,
         ["--damping-ratio:", "damping.ratio=11.0", "outside"]),
        (["--damping", "viscous", "--damping-ratio", "-0.1"], None, ["--damping-ratio:"]),
        (["--damping", "viscous", "--damping-ratio", "inf"], None,
         ["--damping-ratio:", "finite"]),
        (["--excitation", "harmonic-force", "--excitation-amplitude", "0.5",
          "--excitation-frequency", str(F0 * 1e3 * 1.01)], None,
         ["--excitation-frequency:", "outside the supported range", "1e3 f0"]),
        (["--excitation", "harmonic-force", "--excitation-amplitude", "0.5",
          "--excitation-frequency", str(F0 * 1e-3 * 0.99)], None,
         ["--excitation-frequency:", "1e-3 f0"]),
        (["--excitation", "harmonic-force", "--excitation-amplitude", "-1",
          "--excitation-frequency", "1000"], None, ["--excitation-amplitude:"]),
        ([], '[excitation]\nkind = "harmonic-force"\namplitude = 0.5\nfrequency = 1e9\n',
         ["frequency in [excitation] of", "run.toml", "outside"]),
    ],
)  # fmt: skip
def test_refusals_are_one_line_naming_the_source(tmp_path, flags, toml, words):
    text = refused(tmp_path, *flags, toml=toml)
    for word in words:
        assert word in text, (word, text)


@pytest.mark.parametrize(
    ("toml", "words"),
    [
        ("[damping]\nlaw = 'viscous'\nzeta = 0.1\n", ["unknown key 'zeta' in [damping]"]),
        ("[excitation]\nkind = 'harmonic-force'\nomega = 1\n", ["unknown key 'omega'"]),
        ("[damping]\nlaw = 1\n", ["law in [damping] must be a string"]),
        ("[damping]\nlaw = 'viscous'\nratio = true\n", ["ratio in [damping] must be a"]),
        ("[damping]\nlaw = 'viscous'\nratio = '0.1'\n", ["ratio in [damping] must be a"]),
        ("[damping]\nlaw = 'viscous'\nratio = nan\n", ["ratio in [damping] must be a finite"]),
        ("damping = 3\n", ["[damping] must be a table"]),
        ("[dampng]\nlaw = 'viscous'\n", ["unknown table [dampng]"]),
    ],
)
def test_toml_tables_are_checked(tmp_path, toml, words):
    text = refused(tmp_path, toml=toml)
    for word in words:
        assert word in text, (word, text)


def test_a_field_the_command_sets_needs_no_flag_but_refuses_one(tmp_path):
    what = ("--frequencies", "--frequencies")
    model = model_of(
        tmp_path, "--excitation", "harmonic-force", "--excitation-amplitude", "0.5",
        provided={"excitation.frequency": (1200.0, what[0])},
    )  # fmt: skip
    assert model.excitation == ms.HarmonicForce(0.5, 1200.0)
    text = refused(
        tmp_path, "--excitation", "harmonic-force", "--excitation-amplitude", "0.5",
        "--excitation-frequency", "1000", provided={"excitation.frequency": (1200.0, what[0])},
    )  # fmt: skip
    assert "--excitation-frequency cannot be combined with --frequencies" in text
    text = refused(tmp_path, provided={"excitation.frequency": (1200.0, "--frequencies")})
    assert "no excitation part" in text and "--excitation" in text


def test_figures_refuses_part_tables(tmp_path):
    config = tmp_path / "run.toml"
    config.write_text("[damping]\nlaw = 'viscous'\nratio = 0.1\n")
    args = build_parser().parse_args(["figures", "--config", str(config)])
    with pytest.raises(CliError, match=r"\[damping\] in .*run.toml: figures draws the paper"):
        gather(args, "figures")
    with pytest.raises(SystemExit):  # figures has no part flags at all
        build_parser().parse_args(["figures", "--damping", "viscous"])


def test_kind_names_round_trip():
    assert kind_name("damping", None) == "none"
    assert kind_name("damping", ms.HuntCrossley(0.1)) == "hunt-crossley"
    assert kind_name("excitation", ms.BaseMotion(1e-8, 1000.0)) == "base-motion"
