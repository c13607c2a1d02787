#!/usr/bin/env bash
# `mpirun -np P pnf filter` honours every flag as one process does, on the OpenCL device
# (PNF_DEVICE, else the default rule: PoCL here): --pcd-data and --ascii encodings, --max-seconds
# and --max-pairs for the whole job (exit 2, nothing written), --in-place, --stop-change; a
# usage error is printed once (rank 0).
# Usage: cli_mpi_flags_test.sh PNF MPIEXEC WORK_DIR
set -euo pipefail
pnf=$1
mpiexec=$2
work=$3
here=$(cd "$(dirname "$0")" && pwd)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1
run() { timeout 120 "$mpiexec" --oversubscribe "$@"; }
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work"

# A test may skip only when no OpenCL device exists and PNF_DEVICE is unset.
if [ -z "${PNF_DEVICE:-}" ] && ! "$pnf" devices >/dev/null 2>&1; then
  echo "no OpenCL device and PNF_DEVICE unset: skipped (set PNF_DEVICE to make this a failure)"
  exit 0
fi

"$pnf" demo --points 4000 --dir . --device reference >/dev/null
in=house_noisy.ply
sum_before=$(md5sum "$in")
nothing_beside() {  # nothing but the inputs and logs in the folder
  local left
  left=$(ls -A | grep -v -x -F -e "$in" -e house_clean.ply -e house_filtered.ply -e house.png -e big |
    grep -v '\.log$\|\.txt$' || true)
  [ -z "$left" ] || fail "left beside OUT: $left"
}

echo "== --pcd-data and --ascii: the encodings one process writes"
for flags in "pcd --pcd-data ascii" "pcd --pcd-data binary_compressed" "pcd --ascii" "ply --ascii"; do
  set -- $flags
  ext=$1
  shift
  "$pnf" filter "$in" one.$ext "$@" -q
  run -np 2 "$pnf" filter "$in" two.$ext "$@" -q
  head -c 400 one.$ext | grep -a -E "^(DATA|format) " >want.txt
  head -c 400 two.$ext | grep -a -E "^(DATA|format) " >got.txt
  cmp -s want.txt got.txt || fail "$flags: one process '$(cat want.txt)', 2 ranks '$(cat got.txt)'"
  echo "$flags: $(cat got.txt)"
  rm one.$ext two.$ext
done
grep -q "DATA ascii" <(run -np 2 "$pnf" filter "$in" a.pcd --pcd-data ascii -q && head -c 400 a.pcd) ||
  fail "--pcd-data ascii under mpirun did not write DATA ascii"
rm a.pcd

echo "== --max-seconds too small: exit 2, as one process, nothing written"
set +e
"$pnf" filter "$in" ms1.ply --max-seconds 0.0001 2>ms1.log
one=$?
run -np 3 "$pnf" filter "$in" ms3.ply --max-seconds 0.0001 2>ms3.log
three=$?
set -e
[ "$one" = 2 ] || fail "one process: exit $one for --max-seconds 0.0001 (want 2)"
[ "$three" = 2 ] || { cat ms3.log; fail "3 ranks: exit $three for --max-seconds 0.0001 (want 2)"; }
grep -q "would take about" ms3.log || fail "no estimate in: $(cat ms3.log)"
[ "$(grep -c 'pnf: error' ms3.log)" = 1 ] || fail "the refusal is not printed once: $(cat ms3.log)"
nothing_beside

echo "== --max-pairs counts the whole job's pairs"
# 20k points at sigma_f 2: each of 4 ranks holds about 40% of the points (its own and its halo).
"$pnf" demo --points 20000 --dir big --device reference >/dev/null
run -np 4 "$pnf" filter big/house_noisy.ply p4.ply --sigma-f 2 2>p4.log
pairs=$(grep -o "neighbours *[0-9]* pairs" p4.log | grep -o "[0-9]*")
[ -n "$pairs" ] || fail "no pair count in: $(cat p4.log)"
rm p4.ply
# A limit below the job's total but far above any one rank's share (under half of it).
set +e
run -np 4 "$pnf" filter big/house_noisy.ply p4.ply --sigma-f 2 --max-pairs $((pairs - 1)) 2>p4.log
code=$?
set -e
[ "$code" = 2 ] || { cat p4.log; fail "exit $code for a job of $pairs pairs under --max-pairs $((pairs - 1)) (want 2)"; }
grep -q "whole job" p4.log || fail "not refused for the whole job: $(cat p4.log)"
[ "$(grep -c 'pnf: error' p4.log)" = 1 ] || fail "the refusal is not printed once"
nothing_beside
# The ranks' own estimates sample their points: a limit 5% above the job's count passes.
run -np 4 "$pnf" filter big/house_noisy.ply p4.ply --sigma-f 2 --max-pairs $((pairs + pairs / 20)) -q ||
  fail "a job of $pairs pairs refused at --max-pairs $((pairs + pairs / 20))"
rm p4.ply

echo "== --in-place"
cp "$in" inplace.ply
set +e
run -np 2 "$pnf" filter inplace.ply inplace.ply 2>inplace.log
code=$?
set -e
[ "$code" = 2 ] || fail "exit $code for OUT = IN without --in-place (want 2)"
[ "$(grep -c 'pnf: error' inplace.log)" = 1 ] || fail "printed $(grep -c 'pnf: error' inplace.log) times"
"$pnf" filter inplace.ply one_inplace.ply -q
run -np 2 "$pnf" filter inplace.ply inplace.ply --in-place -q
[ "$(md5sum <inplace.ply)" != "$(md5sum <"$in")" ] || fail "--in-place left the file as it was"
cmp -s one_inplace.ply inplace.ply || fail "--in-place: not the one-process bytes"
rm inplace.ply one_inplace.ply
nothing_beside

echo "== --stop-change: the passes one process runs"
"$pnf" filter "$in" s1.ply --stop-change 0.5 --iterations 30 2>s1.log
run -np 3 "$pnf" filter "$in" s3.ply --stop-change 0.5 --iterations 30 2>s3.log
n1=$(grep -o "stop rule *[0-9]*" s1.log | grep -o "[0-9]*$")
n3=$(grep -o "stop rule *[0-9]*" s3.log | grep -o "[0-9]*$")
[ -n "$n1" ] && [ "$n1" -lt 30 ] || fail "one process did not stop early: $(cat s1.log)"
[ "$n3" = "$n1" ] || fail "3 ranks ran ${n3:-?} passes, one process $n1"
rm s1.ply s3.ply

echo "== a usage error, printed once"
# The command-line parser's errors: the one-process message, once (mpirun adds its own notes).
for args in "$in" "$in x.ply --sigma-f abc" "$in x.ply --auto --sigma-f 3" "$in x.ply --no-such-flag"; do
  set +e
  "$pnf" filter $args >one.log 2>&1
  run -np 3 "$pnf" filter $args >usage.log 2>&1
  code=$?
  set -e
  [ "$code" = 2 ] || fail "'pnf filter $args': exit $code (want 2)"
  first=$(head -1 one.log)
  [ -n "$first" ] && [ "$(grep -c -x -F -e "$first" usage.log)" = 1 ] ||
    { cat usage.log; fail "'pnf filter $args': '$first' not printed once"; }
done
# The library's refusals (bad output format): one line, from rank 0.
set +e
run -np 3 "$pnf" filter "$in" x.obj >usage.log 2>&1
code=$?
set -e
[ "$code" = 2 ] || fail "exit $code for an unknown output format (want 2)"
[ "$(grep -c 'pnf: error' usage.log)" = 1 ] || { cat usage.log; fail "the format error is not printed once"; }
[ "$(md5sum "$in")" = "$sum_before" ] || fail "the input changed"
nothing_beside
echo "PASS"
