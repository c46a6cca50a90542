"""``python -m microslip``: the ``microslip`` command."""

from microslip.cli.main import entry_point

if __name__ == "__main__":
    entry_point()
