#!/usr/bin/env bash
# scripts/demo.sh builds what it runs, the pnf command (target pnf_cli), and not the test suites
# or benchmarks (a newcomer's first demo once spent most of its 6 minutes compiling tests).
# Runs a copy of the script in a scratch folder with cmake, setup and the tool replaced by stubs
# that record what they were asked, so it takes a second and builds nothing.
set -euo pipefail
source_dir=$1
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/scripts" "$scratch/bin" "$scratch/build/tools"
cp "$source_dir"/scripts/*.sh "$scratch/scripts/"
printf '#!/usr/bin/env bash\necho setup >> "%s/calls"\n' "$scratch" > "$scratch/scripts/setup.sh"
printf '#!/usr/bin/env bash\necho "cmake $*" >> "%s/calls"\n' "$scratch" > "$scratch/bin/cmake"
printf '#!/usr/bin/env bash\necho "pnf $*" >> "%s/calls"\n' "$scratch" > "$scratch/build/tools/pnf"
chmod +x "$scratch/bin/cmake" "$scratch/build/tools/pnf"
PATH="$scratch/bin:$PATH" bash "$scratch/scripts/demo.sh" --points 500
cat "$scratch/calls"
fail() { echo "demo_script_test: $1" >&2; exit 1; }
grep -q '^pnf demo --points 500$' "$scratch/calls" || fail "the demo did not run the tool with its arguments"
builds=$(grep '^cmake --build' "$scratch/calls") || fail "the demo built nothing"
while read -r line; do
  [[ $line == *"--target pnf_cli"* ]] || fail "a build of more than the tool: $line"
done <<< "$builds"
exit 0
