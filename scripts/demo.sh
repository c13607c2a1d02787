#!/usr/bin/env bash
# Sets up, builds, and runs pnf's main job on a model it makes itself: a noisy synthetic scan of a
# house with sharp edges. Prints how much the filter improved the normals; writes the noisy and
# filtered models to ./pnf-demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
./build/tools/pnf demo "$@"
