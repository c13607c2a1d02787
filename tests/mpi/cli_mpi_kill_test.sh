#!/usr/bin/env bash
# Faults while `mpirun -np P pnf filter` writes OUT (README, "Beyond one machine"): a rank killed
# (SIGKILL) during the write, and SIGTERM to mpirun during the write. Either way OUT is not
# written and the exit code is not 0; the job's staging folder (.OUT.pnf-mpi-PID-XXXXXX), which
# a SIGKILL can leave, is removed by the next run writing OUT, after which nothing but OUT is
# beside it.
# Usage: cli_mpi_kill_test.sh PNF MPIEXEC WORK_DIR
set -euo pipefail
pnf=$1
mpiexec=$2
work=$3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work"

if [ -z "${PNF_DEVICE:-}" ] && ! "$pnf" devices >/dev/null 2>&1; then
  echo "no OpenCL device and PNF_DEVICE unset: skipped (set PNF_DEVICE to make this a failure)"
  exit 0
fi

# A large flat cloud, filtered with no passes and written as ascii PLY through rank 0: the
# write (2 to 3 s here) is the longest step, so a kill is sure to land in it, and it outlasts
# the second Open MPI's mpirun takes to pass a SIGTERM on to the ranks.
python3 - <<'PY'
import random, struct
random.seed(7)
side = 900
rows = bytearray()
for i in range(side * side):
    x, y = (i % side) * 0.01, (i // side) * 0.01
    rows += struct.pack("<6d", x, y, 0.001 * random.random(), 0.05 * random.random(), 0.0, 1.0)
header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {side * side}\nproperty double x\n"
          "property double y\nproperty double z\nproperty double nx\nproperty double ny\nproperty double nz\nend_header\n")
open("big.ply", "wb").write(header.encode() + rows)
PY
flags=(--iterations 0 --ascii --radius 0.005)

# Waits until OUT's staging folder exists (the write has begun); fails after 60 s.
wait_for_write() {
  for _ in $(seq 6000); do
    if ls -A | grep -q "^\.$1\.pnf-mpi-"; then return 0; fi
    sleep 0.01
  done
  fail "the write of $1 never began"
}
beside() { ls -A | grep -v -x -F -e big.ply -e "$1" | grep -v '\.log$\|\.pid$' || true; }

echo "== SIGKILL to rank 1 during the write"
set +e
"$mpiexec" --oversubscribe -np 1 "$pnf" filter big.ply k.ply "${flags[@]}" : \
  -np 1 sh -c 'echo $$ > rank1.pid; exec "$0" "$@"' "$pnf" filter big.ply k.ply "${flags[@]}" >kill.log 2>&1 &
job=$!
wait_for_write k.ply
kill -9 "$(cat rank1.pid)"
wait $job
code=$?
set -e
[ "$code" != 0 ] || fail "a rank killed during the write gave exit 0"
[ ! -e k.ply ] || fail "OUT written by a job whose rank was killed during the write"
echo "left by the killed job: '$(beside k.ply)'"
[ -z "$(beside k.ply | grep -v '^\.k\.ply\.pnf-mpi-')" ] || fail "left beside OUT: $(beside k.ply)"
timeout 120 "$mpiexec" --oversubscribe -np 2 "$pnf" filter big.ply k.ply "${flags[@]}" -q
[ -e k.ply ] && [ -z "$(beside k.ply)" ] || fail "after the next run, beside OUT: $(beside k.ply)"

echo "== SIGTERM to mpirun during the write"
set +e
"$mpiexec" --oversubscribe -np 2 "$pnf" filter big.ply t.ply "${flags[@]}" >term.log 2>&1 &
job=$!
wait_for_write t.ply
kill -TERM $job
wait $job
code=$?
set -e
grep -v "^ *$" term.log | head -5 || true  # empty when mpirun ended the ranks first
[ "$code" != 0 ] || fail "mpirun exited 0 after SIGTERM"
# Open MPI's mpirun exits 1 when signalled, whatever its ranks did; the ranks heard of it before
# the write ended, so OUT must not be written, nor "wrote" printed.
[ ! -e t.ply ] || fail "exit $code, but OUT was written"
! grep -q "wrote" term.log || fail "'wrote' printed, exit $code"
echo "left by the signalled job: '$(beside t.ply | grep -v -x k.ply)'"
timeout 120 "$mpiexec" --oversubscribe -np 2 "$pnf" filter big.ply t.ply "${flags[@]}" -q
[ -e t.ply ] && [ -z "$(beside t.ply | grep -v -x k.ply)" ] || fail "after the next run, beside OUT: $(beside t.ply)"
echo "PASS"
