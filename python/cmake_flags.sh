#!/usr/bin/env bash
# Prints the CMake flags that build the Python module for Debian's interpreter (or $PPCR_PYTHON),
# when it has what the module needs: pybind11's CMake package, Python's headers and numpy
# (tools/install_deps.sh installs pybind11-dev, python3-dev and python3-numpy). Otherwise prints
# nothing, and says why on stderr. Used by tools/demo.sh and tools/test.sh:
#   cmake -S . -B build $(python/cmake_flags.sh)
# The interpreter is named explicitly: a pyenv or venv python first in PATH (often without numpy
# or with another ABI) would otherwise be the one CMake finds.
set -euo pipefail
python=${PPCR_PYTHON:-/usr/bin/python3}
why=""
if [[ ! -x $python ]]; then
  why="no $python"
elif ! "$python" -c "import numpy" 2>/dev/null; then
  why="$python cannot import numpy (python3-numpy)"
elif ! "$python" -c "import os, sysconfig, sys
sys.exit(not os.path.isfile(os.path.join(sysconfig.get_paths()['include'], 'Python.h')))"; then
  why="no Python.h for $python (python3-dev)"
elif [[ ! -f /usr/lib/cmake/pybind11/pybind11Config.cmake ]]; then
  why="no pybind11 CMake package (pybind11-dev)"
fi
if [[ -n $why ]]; then
  echo "ppcr: the Python module is not built: $why" >&2
else
  echo "-DPPCR_BUILD_PYTHON=ON -DPython_EXECUTABLE=$python"
fi
