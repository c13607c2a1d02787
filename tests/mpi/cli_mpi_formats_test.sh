#!/usr/bin/env bash
# OUT of `mpirun -np P pnf filter` against one process's OUT, P = 1..4, in every format the CLI
# writes, on a cloud with sharp edges (the demo house), on the OpenCL device (PNF_DEVICE, else
# PoCL here). P = 1 must be byte-identical (mpirun -np 1 is one process). For P > 1 SPEC asks for
# the same bytes; until each rank visits a point's neighbours in the one process's order (issue
# 31, item 1) the normals' float sums may round apart, so this checks what the README promises
# today: every byte but the normals' equal (binary PLY), positions unchanged and each normal
# within 1e-3 degrees (every format, read back through a binary PLY). It prints, per format and
# P, whether the bytes were identical.
# TODO(issue 31, item 1): once neighbour order is the global one, require `cmp` for every P.
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
identical=0
different=0
for i in "${!formats[@]}"; do
  set -- ${formats[$i]}
  ext=$1
  shift
  "$pnf" filter in.ply "one$i.$ext" --iterations 2 "$@" -q
  "$pnf" filter "one$i.$ext" "one$i.back.ply" --iterations 0 --device reference -q
  for p in 1 2 3 4; do
    out="p$p.$i.$ext"
    run -np "$p" "$pnf" filter in.ply "$out" --iterations 2 "$@" -q
    if cmp -s "one$i.$ext" "$out"; then
      identical=$((identical + 1))
      echo "${formats[$i]}, P = $p: byte-identical"
      continue
    fi
    [ "$p" != 1 ] || fail "${formats[$i]}: mpirun -np 1 is not byte-identical to one process"
    different=$((different + 1))
    if [ "$ext" = ply ] && [ $# = 0 ]; then
      # Binary PLY: every byte but the normals' as one process's.
      python3 "$here/compare_ply.py" "one$i.$ext" "$out" >/dev/null || fail "${formats[$i]}, P = $p"
    fi
    "$pnf" filter "$out" "p$p.$i.back.ply" --iterations 0 --device reference -q
    max=$(python3 "$here/compare_ply.py" "one$i.back.ply" "p$p.$i.back.ply" 0.001) ||
      fail "${formats[$i]}, P = $p: $max"
    echo "${formats[$i]}, P = $p: not byte-identical; $max"
  done
done
echo "$identical byte-identical, $different within 1e-3 degrees only"
echo "PASS"
