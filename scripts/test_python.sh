#!/usr/bin/env bash
# Builds and installs the Python module and the pnf command into a virtual environment
# (build/venv, which sees the packages already installed for python3, so that numpy or open3d
# there need no second download), then runs python/tests with pytest. The CMake build stays in
# build/pip, so a second run recompiles only what changed. Python build and test tools come from
# PyPI. The tests run build/venv/bin/pnf, the command this install put there (test_cli.py checks
# that it is there and works; PNF_CLI names another one for the parity tests).
set -euo pipefail
cd "$(dirname "$0")/.."
python=${PYTHON:-python3}
venv=build/venv
if [ ! -x "$venv/bin/python" ]; then
  "$python" -m venv --system-site-packages "$venv"
fi
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check scikit-build-core pytest numpy
# Optional: the laspy interop test skips without it (open3d is large; install it by hand to test it).
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check laspy ||
  echo "test_python: laspy did not install; its interop test will skip"
CMAKE_BUILD_PARALLEL_LEVEL="$(nproc)" "$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
  --no-build-isolation .
"$venv/bin/python" -m pytest -q -p no:cacheprovider python/tests
