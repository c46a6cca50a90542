"""The model's parts from flags and TOML tables (cli/model_options.py): every flag, every
refusal (one line naming where the value came from), and flags overriding the file."""

from __future__ import annotations

import numpy as np
import pytest

import microslip as ms
from microslip.cli.model_options import kind_name
from microslip.cli.options import CliError, gather
from microslip.cli.parser import build_parser

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


# -- the tangential side: tangential contact, friction law, drive ------------------------
K_N = P.contact_stiffness


@pytest.mark.parametrize(
    ("flags", "expected"),
    [
        (["--tangential", "rigid"], ms.Model(P, tangential=ms.Rigid())),
        (["--tangential", "spring", "--tangential-stiffness", "1e6"],
         ms.Model(P, tangential=ms.TangentialSpring(1e6))),
        (["--tangential", "mindlin", "--tangential-ratio", "0.8"],
         ms.Model(P, tangential=ms.MindlinSpring(0.8))),
        (["--friction", "coulomb"], ms.Model(P, friction=ms.Coulomb())),
        (["--friction", "static-kinetic", "--friction-mu-static", "0.2",
          "--friction-mu-kinetic", "0.15"],
         ms.Model(P, friction=ms.StaticKinetic(0.2, 0.15))),
        (["--friction", "stribeck", "--friction-mu-static", "0.2", "--friction-mu-kinetic",
          "0.1", "--friction-velocity", "1e-4", "--friction-exponent", "1.5"],
         ms.Model(P, friction=ms.Stribeck(0.2, 0.1, 1e-4, 1.5))),
        (["--drive", "none"], ms.Model(P)),
        (["--drive", "constant-force", "--drive-force", "-0.3"],
         ms.Model(P, drive=ms.ConstantForce(-0.3))),
        (["--drive", "harmonic", "--drive-mean", "0.1", "--drive-amplitude", "0.4",
          "--drive-frequency", "120"],
         ms.Model(P, drive=ms.HarmonicDrive(0.1, 0.4, 120.0))),
        (["--drive", "spring", "--drive-stiffness", "1e5", "--drive-velocity", "2e-4"],
         ms.Model(P, drive=ms.SpringDrive(1e5, 2e-4))),
        (["--drive", "prescribed-velocity", "--drive-velocity", "1e-3"],
         ms.Model(P, drive=ms.PrescribedVelocity(1e-3))),
        (["--tangential", "spring", "--tangential-stiffness", "2e6", "--friction",
          "static-kinetic", "--friction-mu-static", "0.3", "--friction-mu-kinetic", "0.2",
          "--drive", "harmonic", "--drive-mean", "0", "--drive-amplitude", "1",
          "--drive-frequency", "50", "--damping", "viscous", "--damping-ratio", "0.1"],
         ms.Model(P, ms.Viscous(0.1), None, ms.TangentialSpring(2e6),
                  ms.StaticKinetic(0.3, 0.2), ms.HarmonicDrive(0.0, 1.0, 50.0))),
    ],
)  # fmt: skip
def test_every_tangential_flag_builds_its_part(tmp_path, flags, expected):
    model = model_of(tmp_path, *flags)
    assert model == expected
    assert model.describe() == expected.describe()


def test_the_paper_kinds_named_explicitly_keep_the_paper_model(tmp_path):
    model = model_of(tmp_path, "--tangential", "rigid", "--friction", "coulomb")
    assert model.is_paper and not model.is_compliant
    assert model_of(tmp_path).tangential is None  # not given: None, the paper's


def test_toml_tables_of_the_tangential_side(tmp_path):
    toml = (
        '[tangential]\nkind = "mindlin"\nratio = 0.7\n'
        '[friction]\nlaw = "static-kinetic"\nmu_static = 0.25\nmu-kinetic = 0.2\n'
        '[drive]\nkind = "spring"\nstiffness = 1e5\nvelocity = 1e-4\n'
    )
    model = model_of(tmp_path, toml=toml)
    assert model == ms.Model(
        P, tangential=ms.MindlinSpring(0.7), friction=ms.StaticKinetic(0.25, 0.2),
        drive=ms.SpringDrive(1e5, 1e-4),
    )  # fmt: skip
    # flags override one field; another kind replaces the file's part
    model = model_of(tmp_path, "--friction-mu-static", "0.4", "--drive", "prescribed-velocity",
                     "--drive-velocity", "1e-3", toml=toml)  # fmt: skip
    assert model.friction == ms.StaticKinetic(0.4, 0.2)
    assert model.drive == ms.PrescribedVelocity(1e-3)
    # the file's drive velocity (of the spring) does not carry over to another kind
    text = refused(tmp_path, "--drive", "prescribed-velocity", toml=toml)
    assert "needs --drive-velocity [m s-1]" in text


@pytest.mark.parametrize(
    ("flags", "toml", "words"),
    [
        (["--tangential-stiffness", "1e6"], None,
         ["--tangential-stiffness is a field of the tangential part, which is not given",
          "--tangential {spring}"]),
        (["--friction-mu-static", "0.2"], None,
         ["--friction-mu-static", "not given", "--friction {static-kinetic,stribeck}"]),
        (["--drive-velocity", "1e-3"], None,
         ["--drive-velocity", "--drive {spring,prescribed-velocity}"]),
        (["--tangential", "rigid", "--tangential-stiffness", "1e6"], None,
         ["--tangential-stiffness has no effect with tangential rigid", "its fields: none"]),
        (["--tangential", "spring", "--tangential-ratio", "0.8"], None,
         ["--tangential-ratio has no effect with tangential spring", "its fields: stiffness"]),
        (["--friction", "coulomb", "--friction-mu-kinetic", "0.1"], None,
         ["--friction-mu-kinetic has no effect with friction coulomb"]),
        (["--drive", "none", "--drive-force", "1"], None,
         ["--drive-force has no effect with drive none"]),
        (["--tangential", "spring"], None, ["needs --tangential-stiffness [N m-1]"]),
        (["--tangential", "mindlin"], None, ["needs --tangential-ratio [1]"]),
        (["--friction", "stribeck", "--friction-mu-static", "0.2", "--friction-mu-kinetic",
          "0.1", "--friction-velocity", "1e-4"], None, ["needs --friction-exponent [1]"]),
        (["--drive", "harmonic", "--drive-mean", "0", "--drive-amplitude", "1"], None,
         ["needs --drive-frequency [Hz]"]),
        (["--drive", "constant-force"], None, ["needs --drive-force [N]"]),
        (["--tangential", "elastic"], None,
         ["unknown tangential kind 'elastic'", "rigid, spring, mindlin"]),
        (["--friction", "viscous"], None, ["unknown friction law 'viscous'"]),
        (["--drive", "harmonic-force"], None, ["unknown drive kind 'harmonic-force'"]),
        (["--tangential", "spring", "--tangential-stiffness", str(K_N * 2e6)], None,
         ["--tangential-stiffness:", "outside the supported range", "1e6 K_n"]),
        (["--friction", "static-kinetic", "--friction-mu-static", "0.1",
          "--friction-mu-kinetic", "0.2"], None, ["--friction-mu-static:", "must be >="]),
        (["--drive", "harmonic", "--drive-mean", "0", "--drive-amplitude", "1",
          "--drive-frequency", "1e9"], None, ["--drive-frequency:", "outside"]),
        (["--drive", "prescribed-velocity", "--drive-velocity", "nan"], None,
         ["--drive-velocity:", "finite"]),
        ([], '[tangential]\nkind = "spring"\nstiffness = -1.0\n',
         ["stiffness in [tangential] of", "run.toml", "outside"]),
        ([], '[friction]\nkind = "stribeck"\n', ["unknown key 'kind' in [friction]", "law"]),
        ([], '[drive]\nlaw = "spring"\n', ["unknown key 'law' in [drive]", "kind"]),
        ([], '[friction]\nlaw = "static-kinetic"\nmu_static = 0.2\nmu-static = 0.2\n',
         ["'mu_static' and 'mu-static' in [friction] are the same key"]),
        ([], '[tangential]\nkind = "spring"\nstiffness = "1e6"\n',
         ["stiffness in [tangential] must be a finite number"]),
        (["--friction", "stribeck", "--friction-mu-static", "0.2", "--friction-mu-kinetic",
          "0.1", "--friction-velocity", "1e-4", "--friction-exponent", "2", "--tangential",
          "spring", "--tangential-stiffness", "1e6"], None, ["Stribeck needs tangential"]),
    ],
)  # fmt: skip
def test_tangential_refusals_are_one_line_naming_the_source(tmp_path, flags, toml, words):
    text = refused(tmp_path, *flags, toml=toml)
    for word in words:
        assert word in text, (word, text)


def test_the_command_may_set_the_drive_velocity(tmp_path):
    model = model_of(tmp_path, "--drive", "prescribed-velocity",
                     provided={"drive.velocity": (2e-3, "--velocities")})  # fmt: skip
    assert model.drive == ms.PrescribedVelocity(2e-3)
    text = refused(tmp_path, "--drive", "prescribed-velocity", "--drive-velocity", "1e-3",
                   provided={"drive.velocity": (2e-3, "--velocities")})  # fmt: skip
    assert "--drive-velocity cannot be combined with --velocities" in text
    text = refused(tmp_path, provided={"drive.velocity": (2e-3, "--velocities")})
    assert "no drive part" in text


def test_tangential_kind_names_round_trip():
    assert kind_name("tangential", None) == "rigid"
    assert kind_name("friction", None) == "coulomb"
    assert kind_name("drive", None) == "none"
    assert kind_name("tangential", ms.MindlinSpring(0.8)) == "mindlin"
    assert kind_name("friction", ms.StaticKinetic(0.2, 0.1)) == "static-kinetic"
    assert kind_name("drive", ms.PrescribedVelocity(1e-3)) == "prescribed-velocity"


def test_every_part_class_has_a_command_line_kind():
    """The static table names every registered part, and every field of each."""
    from microslip.cli.model_options import SLOTS
    from microslip.model.composition import PART_TYPES

    assert [s.name for s in SLOTS] == list(PART_TYPES)
    for slot in SLOTS:
        classes = {name for name in slot.kinds.values() if name is not None}
        assert classes == {cls.__name__ for cls in PART_TYPES[slot.name]}
        for cls in PART_TYPES[slot.name]:
            assert set(cls.field_names()) <= set(slot.fields), cls


def test_paper_tangential_side_is_required_by_name(tmp_path):
    from microslip.cli.model_options import require_paper_tangential

    argv = ["map", "--friction", "static-kinetic", "--friction-mu-static", "0.2",
            "--friction-mu-kinetic", "0.1"]  # fmt: skip
    opts = gather(build_parser().parse_args(argv), "map")
    with pytest.raises(CliError, match=r"^--friction: microslip map does not support "
                       r"friction=StaticKinetic; use X$"):  # fmt: skip
        require_paper_tangential(opts.model(), opts.parts, "map", instead="use X")
    opts = gather(build_parser().parse_args(["map", "--tangential", "rigid"]), "map")
    require_paper_tangential(opts.model(), opts.parts, "map", instead="use X")  # accepted


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("1e-6:1e-2:5:log", [1e-6, 1e-5, 1e-4, 1e-3, 1e-2]),
        ("1e-3:1e-3:1:log", [1e-3]),
        ("0:1:3", [0.0, 0.5, 1.0]),
        ("0.1,0.3", [0.1, 0.3]),
        (" 2e-3 ", [2e-3]),
    ],
)
def test_parse_range_linear_log_and_lists(text, expected):
    from microslip.cli.options import parse_range

    values = parse_range("--velocities", text)
    assert values == pytest.approx(expected, rel=1e-13, abs=0.0)
    if text.endswith("log"):
        assert values[0] == expected[0] and values[-1] == expected[-1]  # exact ends
        assert np.diff(np.log10(values)) == pytest.approx(np.ones(values.size - 1) * 1.0)


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("0:1e-2:5:log", ["0 < start"]),
        ("-1:1:3:log", ["0 < start"]),
        ("1e-3:log", ["start:stop:count:log"]),
        ("1e-3,1e-2:log", ["start:stop:count:log"]),
        ("1e-2:1e-3:4:log", ["reversed"]),
        ("1e-3:1e-2:4:lin", ["start:stop:count"]),
        ("1_0:20:3", ["'_' is not allowed"]),
    ],
)
def test_parse_range_refusals_name_the_option(text, words):
    from microslip.cli.options import parse_range

    with pytest.raises(CliError) as error:
        parse_range("--velocities", text)
    assert str(error.value).startswith("--velocities")
    for word in words:
        assert word in str(error.value), (word, str(error.value))
