"""Range strings and TOML configuration: every malformed input is a ValueError naming it."""

import numpy as np
import pytest

from microslip.io.config import command_options, load_config, parameters_from_config
from microslip.io.ranges import parse_values


def test_inclusive_linspace_lists_and_single_values():
    np.testing.assert_array_equal(parse_values("F", "0.1:0.9:5"), np.linspace(0.1, 0.9, 5))
    np.testing.assert_array_equal(parse_values("F", "0.1,0.5"), [0.1, 0.5])
    np.testing.assert_array_equal(parse_values("F", "0.5"), [0.5])
    np.testing.assert_array_equal(parse_values("F", "0.5:0.5:1"), [0.5])


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "empty"),
        ("0.9:0.1:5", "reversed"),
        ("0.1:0.9:0", "count must be >= 1"),
        ("0.1:0.9:-3", "count must be >= 1"),
        ("0.1:0.9:2.5", "count must be an integer"),
        ("0.1:0.9", "start:stop:count"),
        ("0.1:0.1:4", "empty range"),
        ("0.1:0.9:1", "count 1 needs start == stop"),
        ("nan", "finite"),
        ("0:inf:3", "finite"),
        ("a,b", "not a number"),
        ("0.1,0.1", "repeated"),
    ],
)
def test_bad_ranges(text, message):
    with pytest.raises(ValueError, match=message) as error:
        parse_values("--force", text)
    assert "--force" in str(error.value)


def test_config_tables(tmp_path):
    path = tmp_path / "c.toml"
    path.write_text("[parameters]\nmu = 0.2\n[simulate]\nforce = 0.5\nsave-every = 3\n")
    data = load_config(path)
    assert parameters_from_config(data, "c.toml") == {"mu": 0.2}
    schemas = {"simulate": {"force", "save_every"}, "info": {"json"}}
    options = command_options(data, "simulate", schemas, "c.toml")
    assert options == {"force": 0.5, "save_every": 3}
    assert command_options(data, "info", schemas, "c.toml") == {}  # a shared file
    with pytest.raises(ValueError, match="unknown option 'force'"):
        command_options(data, "simulate", {"simulate": {"duration"}}, "c.toml")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("[paramters]\nmu = 0.5\n", r"unknown table \[paramters\]"),
        ("[Parameters]\nmu = 0.5\n", r"unknown table \[Parameters\]"),
        ("mu = 0.5\n", r"unknown table \[mu\]"),
        ("[simulate]\nfoo = 1\n", r"unknown option 'foo' in \[simulate\]"),  # read by info
        (
            "[simulate]\ninitial-state = '0,0,0,0'\ninitial_state = '0,0,0,0'\n",
            "'initial-state' and 'initial_state' in \\[simulate\\] are the same option",
        ),
    ],
)
def test_config_refuses_unknown_tables_other_commands_keys_and_repeats(tmp_path, text, message):
    path = tmp_path / "c.toml"
    path.write_text(text)
    schemas = {"simulate": {"force", "initial_state"}, "info": {"json"}}
    with pytest.raises(ValueError, match=message):
        command_options(load_config(path), "info", schemas, str(path))


def test_config_not_utf8_and_huge_integer_name_the_file_and_key(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes("[parameters]\n# m\xfc\nmu = 0.2\n".encode("latin-1"))
    with pytest.raises(ValueError, match=r"latin1\.toml.*not UTF-8"):
        load_config(path)
    with pytest.raises(ValueError, match=r"x\.toml: c_n in \[parameters\] must be a number"):
        parameters_from_config({"parameters": {"c_n": 10**400}}, "x.toml")


def test_config_errors_name_the_file(tmp_path):
    with pytest.raises(ValueError, match=r"missing\.toml"):
        load_config(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("mu = = 3")
    with pytest.raises(ValueError, match=r"bad\.toml"):
        load_config(bad)
    with pytest.raises(ValueError, match="unknown parameter 'stiffness'"):
        parameters_from_config({"parameters": {"stiffness": 1.0}}, "x.toml")


@pytest.mark.parametrize("value", ["true", "'0.2'", "[0.2]", "{a = 1}"])
def test_parameter_values_must_be_numbers(tmp_path, value):
    path = tmp_path / "c.toml"
    path.write_text(f"[parameters]\nmu = {value}\n")
    with pytest.raises(ValueError, match=r"c\.toml: mu in \[parameters\] must be a number"):
        parameters_from_config(load_config(path), str(path))


def test_integer_parameters_become_floats(tmp_path):
    path = tmp_path / "c.toml"
    path.write_text("[parameters]\nmass = 2\n")
    values = parameters_from_config(load_config(path), "c.toml")
    assert values == {"mass": 2.0} and type(values["mass"]) is float
