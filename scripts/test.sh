#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite (GoogleTest under ctest, on the OpenCL device
# that PNF_DEVICE or the default rule picks: PoCL's CPU device on a machine without a GPU), then
# builds and installs the Python module and runs its tests (scripts/test_python.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
(cd build && ctest --output-on-failure -j"$(nproc)" --timeout 900)
bash scripts/test_python.sh
