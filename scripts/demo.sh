#!/usr/bin/env bash
# Sets up, builds, and runs pnf's main job on a model it makes itself: a noisy synthetic scan of a
# house with sharp edges. Prints how much the filter improved the normals; writes the noisy and
# filtered models to ./pnf-demo/.
#
# It builds the pnf command alone (target pnf_cli), not the test suites and benchmarks, in the
# same ./build as scripts/build.sh and scripts/test.sh: those still build everything there.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target pnf_cli
./build/tools/pnf demo "$@"
