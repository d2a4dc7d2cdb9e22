"""`cmake --install` puts the package beside the command: importable from the prefix's dist-packages (or
site-packages) folder, and finding the installed masse command for its studies."""

import json
import os
import pathlib
import shutil
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


@pytest.mark.skipif(not BUILD, reason="run by ctest, which names the build folder")
def test_pip_installs_the_module_and_its_command_into_a_virtual_environment(tmp_path):
    """`pip install --no-build-isolation .` from Debian's packages alone (setup.py): here into a virtual environment
    that sees Debian's numpy, building in the project's own build folder (MASSE_CMAKE_BUILD_DIR), from a copy of the
    files pip reads so that the checkout gets no build files of its own."""
    source = pathlib.Path(__file__).resolve().parents[2]
    project = tmp_path / "project"
    (project / "python").mkdir(parents=True)
    for name in ("setup.py", "pyproject.toml"):
        shutil.copy2(source / name, project / name)
    shutil.copytree(source / "python" / "masse", project / "python" / "masse")
    environment = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(environment)], check=True)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "MASSE_EXECUTABLE")}
    env["MASSE_CMAKE_BUILD_DIR"] = BUILD
    subprocess.run([str(environment / "bin" / "python"), "-m", "pip", "install", "--no-build-isolation", "--no-deps",
                    "--no-index", "--quiet", str(project)], check=True, capture_output=True, env=env, cwd=tmp_path)
    del env["MASSE_CMAKE_BUILD_DIR"]
    done = subprocess.run([str(environment / "bin" / "python"), "-c",
                           "import sys, masse; print(masse.__file__); print(masse.executable()); "
                           "s = masse.Scene.load(sys.argv[1]); s.step(2); print(s.state_hash_text())",
                           str(source / "data" / "scenes" / "sag.json")],
                          check=True, capture_output=True, text=True, env=env, cwd=tmp_path)
    module, command, state = done.stdout.split()
    assert pathlib.Path(module).is_relative_to(environment)
    assert pathlib.Path(command) == pathlib.Path(module).parent / "bin" / "masse"
    assert os.access(command, os.X_OK)
    # The packed command runs the same scene to the same state as the module steps it.
    out = tmp_path / "run"
    subprocess.run([command, "run", str(source / "data" / "scenes" / "sag.json"), "--duration", "0.06", "--quiet",
                    "--out", str(out)], check=True, capture_output=True, env=env, cwd=tmp_path)
    assert json.loads((out / "summary.json").read_text())["final"]["state_hash"] == state
