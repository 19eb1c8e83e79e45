#!/usr/bin/env bash
# ppcr installed as a user installs it, offline on Debian 12, then the pytest suite run against the
# installed module (not the build tree's): pip into a virtual environment that sees Debian's numpy,
# and a wheel built with python3 -m build and installed into a second one.
# Usage: pip_install_test.sh SOURCE_DIR WORK_DIR PYTHON
set -euo pipefail
unset PYTHONPATH  # the installed module, never the build tree's
source_dir=$1 work=$2 python=$3
rm -rf "$work"
mkdir -p "$work"
# pip and build copy the source tree; keep them away from the build folders inside it.
tree="$work/source"
mkdir -p "$tree"
(cd "$source_dir" && git ls-files -z --cached --others --exclude-standard 2>/dev/null || find . -path ./build -prune -o -type f -print0) |
  (cd "$source_dir" && xargs -0 cp --parents -t "$tree")

run_suite() {  # VENV: the pytest suite from outside the source tree, against VENV's ppcr
  local venv=$1
  (cd "$work" && "$venv/bin/python" -c "import ppcr, sys; assert ppcr.__file__.startswith('$venv'), ppcr.__file__")
  (cd "$source_dir/python/tests" && PYTHONDONTWRITEBYTECODE=1 \
    "$venv/bin/python" -m pytest -q -p no:cacheprovider -rs \
      --rootdir "$source_dir/python/tests" "$source_dir/python/tests")
}

"$python" -m venv --system-site-packages "$work/venv"
"$work/venv/bin/pip" install --no-build-isolation --no-index "$tree"
run_suite "$work/venv"

(cd "$tree" && "$python" -m build --no-isolation --wheel --outdir "$work/dist")
"$python" -m venv --system-site-packages "$work/venv-wheel"
"$work/venv-wheel/bin/pip" install --no-index "$work"/dist/ppcr-*.whl
run_suite "$work/venv-wheel"
echo "pip_install_test: pip install . and the wheel both import and pass the suite"
