#!/usr/bin/env bash
# OUT of `mpirun -np P pnf filter` against one process's OUT, P = 1..4, in every format the CLI
# writes, on a cloud with sharp edges (the demo house), on the OpenCL device (PNF_DEVICE, else
# PoCL here): the same bytes for every P (docs/method.md, "Distributed runs (MPI)": each rank
# orders, re-centres and lists its points as one process does the whole cloud).
# Usage: cli_mpi_formats_test.sh PNF MPIEXEC WORK_DIR
set -euo pipefail
pnf=$1
mpiexec=$2
work=$3
here=$(cd "$(dirname "$0")" && pwd)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
run() { timeout 120 "$mpiexec" --oversubscribe "$@"; }
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work"

if [ -z "${PNF_DEVICE:-}" ] && ! "$pnf" devices >/dev/null 2>&1; then
  echo "no OpenCL device and PNF_DEVICE unset: skipped (set PNF_DEVICE to make this a failure)"
  exit 0
fi

"$pnf" demo --points 3000 --dir . --device reference >/dev/null
python3 "$here/make_rich_ply.py" house_noisy.ply in.ply

# The formats and encodings pnf filter writes: OUT's extension, then flags.
formats=("ply" "ply --ascii" "pcd" "pcd --pcd-data ascii" "pcd --pcd-data binary_compressed" "xyz" "xyzn" "pwn")
for i in "${!formats[@]}"; do
  set -- ${formats[$i]}
  ext=$1
  shift
  "$pnf" filter in.ply "one$i.$ext" --iterations 2 "$@" -q
  for p in 1 2 3 4; do
    out="p$p.$i.$ext"
    run -np "$p" "$pnf" filter in.ply "$out" --iterations 2 "$@" -q
    if ! cmp -s "one$i.$ext" "$out"; then
      if [ "$ext" = ply ] && [ $# = 0 ]; then
        python3 "$here/compare_ply.py" "one$i.$ext" "$out" 0 || true  # says what differs
      fi
      fail "${formats[$i]}, P = $p: not the one process's bytes"
    fi
    echo "${formats[$i]}, P = $p: byte-identical"
  done
done
echo PASS
