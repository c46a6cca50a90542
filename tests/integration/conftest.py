import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def run_cli(
    *args: str, cwd: Path | None = None, timeout: float = 300
) -> subprocess.CompletedProcess:
    """Run the installed ``microslip`` entry point as a user would."""
    exe = Path(sys.executable).with_name("microslip")
    command = [str(exe)] if exe.exists() else [sys.executable, "-m", "microslip.cli.main"]
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    return subprocess.run(
        [*command, *args], capture_output=True, text=True, cwd=cwd, timeout=timeout, env=env
    )


@pytest.fixture
def cli():
    return run_cli
