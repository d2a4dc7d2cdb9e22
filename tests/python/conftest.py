"""Shared fixtures of the Python module's tests: where the sources and the masse command are, and the message the
command prints for bad input, to compare with the module's."""

import os
import pathlib
import subprocess

import pytest

SOURCE = pathlib.Path(os.environ.get("MASSE_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
SCENES = SOURCE / "data" / "scenes"


@pytest.fixture
def masse_command():
    """The masse command built with the module (ctest sets MASSE_EXECUTABLE)."""
    import masse
    return masse.executable()


def run_command(*args, cwd=None):
    """Runs the masse command; returns (exit code, stdout, stderr)."""
    import masse
    done = subprocess.run([masse.executable(), *map(str, args)], capture_output=True, text=True, cwd=cwd)
    return done.returncode, done.stdout, done.stderr


def command_message(*args, cwd=None):
    """The message `masse ARGS` prints for bad input, without "masse: " (it must exit with code 2)."""
    code, _, stderr = run_command(*args, cwd=cwd)
    assert code == 2, stderr
    lines = [line for line in stderr.splitlines() if line.startswith("masse: ")]
    assert lines, stderr
    return lines[-1][len("masse: "):]
