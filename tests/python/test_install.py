"""`cmake --install` puts the package beside the command: importable from the prefix's dist-packages (or
site-packages) folder, and finding the installed masse command for its studies."""

import os
import pathlib
import subprocess
import sys

import pytest

BUILD = os.environ.get("MASSE_BUILD_DIR")
CMAKE = os.environ.get("CMAKE_COMMAND", "cmake")


@pytest.mark.skipif(not BUILD, reason="run by ctest, which names the build folder")
def test_installed_module_imports_and_finds_the_installed_command(tmp_path):
    prefix = tmp_path / "prefix"
    for component in ("python", "app"):
        subprocess.run([CMAKE, "--install", BUILD, "--prefix", str(prefix), "--component", component], check=True,
                       capture_output=True)
    (package,) = prefix.glob("lib/python3.*/*-packages/masse")
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "MASSE_EXECUTABLE")}
    env["PYTHONPATH"] = str(package.parent)
    done = subprocess.run([sys.executable, "-c", "import masse; print(masse.__file__); print(masse.executable())"],
                          check=True, capture_output=True, text=True, env=env, cwd=tmp_path)
    module, command = done.stdout.split()
    assert pathlib.Path(module).parent == package
    assert pathlib.Path(command) == prefix / "bin" / "masse"
    assert os.access(command, os.X_OK)
