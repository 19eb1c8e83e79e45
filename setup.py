"""Builds the extension module ppcr with the project's CMake (python/CMakeLists.txt), for the
interpreter that runs this script, and hands it to setuptools (pyproject.toml says how to call
it). Only the libraries and the module are built: no tools, tests or synthetic generator.
PPCR_CMAKE_ARGS adds CMake arguments (e.g. "-DPPCR_USE_OPENMP=OFF")."""
import os
import pathlib
import shlex
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = pathlib.Path(self.build_temp).resolve() / "cmake"
        configure = [
            "cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
            "-DPPCR_BUILD_PYTHON=ON", f"-DPython_EXECUTABLE={sys.executable}",
            "-DPPCR_BUILD_TOOLS=OFF", "-DPPCR_BUILD_TESTS=OFF", "-DPPCR_BUILD_SYNTHETIC=OFF",
            "-DPPCR_BUILD_BENCHMARKS=OFF", "-DPPCR_INSTALL=OFF",
            *shlex.split(os.environ.get("PPCR_CMAKE_ARGS", "")),
        ]
        subprocess.run(configure, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        subprocess.run(["cmake", "--build", str(build), "--target", "ppcr_python", "-j", jobs],
                       check=True)
        built = next((build / "python").glob("ppcr*.so"), None)
        if built is None:
            sys.exit(f"setup.py: the build made no module in {build / 'python'}")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        self.copy_file(str(built), str(target))


# No Python package beside the extension: setuptools must not look for any (src/ is C++).
setup(ext_modules=[CMakeExtension("ppcr")], cmdclass={"build_ext": CMakeBuild}, packages=[],
      py_modules=[])
