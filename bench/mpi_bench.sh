#!/usr/bin/env bash
# Distributed filter figures (docs/mpi.md): for each case and rank count P, the points and halo
# points per rank, bytes exchanged per pass, each rank's peak memory (getrusage via GNU time's
# %M, per process) and the time per pass, from `mpirun -np P pnf filter` on a synthetic house.
# P above the core count runs oversubscribed: its volumes hold, its times do not.
# Usage: bench/mpi_bench.sh PNF OUT.jsonl "POINTS SIGMA_F ITERATIONS P..." ...
#   e.g. bench/mpi_bench.sh build/tools/pnf docs/bench_mpi.jsonl "200000 4 2 single 1 2 4 8" "1000000 8 1 single 3"
set -euo pipefail
pnf=$(realpath "$1"); out=$(realpath -m "$2"); shift 2
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
commit=$(git -C "$(dirname "$0")" rev-parse --short HEAD 2>/dev/null || echo unknown)
: > "$out"
for case in "$@"; do
  read -r points sigma iterations ranks <<<"$case"
  "$pnf" demo --points "$points" --dir "$work" >/dev/null
  for p in $ranks; do
    flags=(filter "$work/house_noisy.ply" "$work/out.ply" --device reference --sigma-f "$sigma"
           --iterations "$iterations" --memory-budget 65536)
    if [ "$p" = single ]; then
      /usr/bin/time -f "rss_kib %M" -o "$work/rss.0" "$pnf" "${flags[@]}" 2>"$work/log"
    else
      mpirun --oversubscribe -np "$p" sh -c '/usr/bin/time -f "rss_kib %M" -o "$0/rss.$OMPI_COMM_WORLD_RANK" "$@"' \
        "$work" "$pnf" "${flags[@]}" 2>"$work/log"
    fi
    rss=$(cat "$work"/rss.* | awk '{print $2}' | sort -n | paste -sd, -)
    rm -f "$work"/rss.*
    python3 - "$work/log" "$p" "$points" "$sigma" "$iterations" "$rss" "$commit" >>"$out" <<'PY'
import json, re, sys
log, p, points, sigma, iterations, rss, commit = sys.argv[1:]
text = open(log).read()
def grab(pattern, cast=float, default=None):
    m = re.search(pattern, text)
    return cast(m.group(1)) if m else default
row = {"ranks": p, "points": int(points), "sigma_f": float(sigma), "iterations": int(iterations),
       "peak_rss_mib_per_rank": [round(int(k) / 1024, 1) for k in rss.split(",")], "commit": commit,
       "pass_seconds": [float(x) for x in re.search(r"passes\s+\d+[^:]*:([\d. ]+) s", text).group(1).split()],
       "neighbour_pairs": grab(r"([\d]+) pairs per pass", int)}
if "halo points per rank" in text:
    m = re.search(r"points per rank (\d+)\.\.(\d+), halo points per rank (\d+)\.\.(\d+)", text)
    row.update(owned=[int(m.group(1)), int(m.group(2))], halo=[int(m.group(3)), int(m.group(4))],
               exchanged_mib_per_pass=grab(r"exchange\s+([\d.]+) MiB per pass"),
               messages_per_pass=grab(r"in (\d+) messages", int),
               moved_mib_once=grab(r"([\d.]+) MiB moved once"),
               setup=re.search(r"setup\s+(.*)", text).group(1))
print(json.dumps(row))
PY
    tail -1 "$out"
  done
done
