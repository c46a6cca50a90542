"""Running the command line in-process (``main([...])``) for the CLI tests."""

from microslip.cli.main import main

SIM = ["simulate", "--force", "0.5", "--amplitude", "1.5e-7", "--duration", "0.002"]
MAP = ["map", "--force", "0.1:0.9:3", "--amplitude", "0:3e-7:3", "--quiet"]


def run(capsys, *args):
    """(exit status, stdout, stderr) of ``microslip ARGS``."""
    status = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return status, out, err


def one_line_failure(status, err, *words):
    """A refusal: exit status 2, one line on stderr (no traceback) holding ``words``."""
    assert status == 2, err
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err
    for word in words:
        assert word in err, (word, err)
