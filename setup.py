"""The pip build of the Python module masse: setuptools runs the project's own CMake build for the extension
masse._masse and the masse command that masse.sweep runs, and packs both with python/masse/__init__.py.

setuptools (python3-setuptools) is the backend because it is Debian's own; scikit-build-core, which would drive CMake
for us, is not packaged for Debian 12, and pip must not fetch from other registries here. MASSE_CMAKE_BUILD_DIR names
a CMake build folder to build in and reuse (the tests point it at the project's own); without it the build goes in
setuptools' temporary folder.
"""

import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE = pathlib.Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = pathlib.Path(os.environ.get("MASSE_CMAKE_BUILD_DIR") or pathlib.Path(self.build_temp) / "cmake")
        build = build.resolve()
        if not (build / "CMakeCache.txt").exists():
            subprocess.run(["cmake", "-S", str(SOURCE), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                            f"-DPython3_EXECUTABLE={sys.executable}"], check=True)
        jobs = str(os.cpu_count() or 1)
        subprocess.run(["cmake", "--build", str(build), "--target", "masse_python", "masse", "--parallel", jobs],
                       check=True)
        package = pathlib.Path(self.get_ext_fullpath(ext.name)).parent
        package.mkdir(parents=True, exist_ok=True)
        (module,) = (build / "python" / "masse").glob("_masse*.so")
        shutil.copy2(module, package / module.name)
        # The command beside the module, found by masse.executable() through _config.py.
        (package / "bin").mkdir(exist_ok=True)
        shutil.copy2(build / "bin" / "masse", package / "bin" / "masse")
        (package / "_config.py").write_text(
            "# Written by setup.py: the masse command packed with this module.\nimport os\n\n"
            "MASSE_EXECUTABLE = os.path.join(os.path.dirname(__file__), \"bin\", \"masse\")\n")


setup(
    packages=["masse"],
    package_dir={"masse": "python/masse"},
    ext_modules=[Extension("masse._masse", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
