#!/usr/bin/env bash
# One call on a lent GPU machine (docs/performance.md "GPU (NVIDIA H200)", docs/mpi.md "Strong
# scaling on 16 cores"): probe the machine, make the NVIDIA OpenCL driver visible, time pnf_bench
# on the GPU and on PoCL's CPU device, filter a 1M-point demo house with the CLI, and run
# `mpirun -np P pnf filter` for P = 1..16 on the reference backend and on PoCL (one thread a rank),
# checking that the outputs agree across P. Every step has its own time limit, so one hang or
# failure does not lose the rest; everything is logged under $OUT.
#
# The machine has no OpenCL loader, PoCL or Open MPI; they travel in .devcarry/root.tar.xz, built
# on a Debian 12 host: the Release binaries (/opt/pnfdev/bin) and the files of Debian's
# openmpi-bin, libopenmpi3, libpocl2, pocl-opencl-icd and the shared libraries they need
# (libLLVM-15, libclang-cpp15, ...), unpacked into / without replacing files already there.
#
# Usage, in the repository root: OUT=/tmp/out bash bench/device_run.sh
#   LOCAL=1 (dry run here: binaries from build-gpu, no unpacking, small sizes)
set -u
OUT=${OUT:-/tmp/device_out}
mkdir -p "$OUT"
exec > >(tee -a "$OUT/log.txt") 2>&1
LOCAL=${LOCAL:-0}
step() { echo; echo "=== [$(date +%T), ${SECONDS}s] $*"; }
left() { [ "$SECONDS" -lt "$1" ]; }  # true while under $1 seconds into the script
W=/tmp/pnfw; rm -rf "$W"; mkdir -p "$W/logs"
export HOME=${HOME:-/root} POCL_CACHE_DIR=/tmp/pocl-cache
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_btl=self,vader OMPI_MCA_pml=ob1 OMPI_MCA_btl_vader_single_copy_mechanism=none
export OMPI_MCA_btl_vader_backing_directory=/tmp OMPI_MCA_rmaps_base_oversubscribe=1

if [ "$LOCAL" = 1 ]; then
  B=$PWD/build-gpu/bin; mkdir -p "$B"
  ln -sf "$PWD/build-gpu/tools/pnf" "$PWD/build-gpu/bench/pnf_bench" "$PWD/build-gpu/bench/pnf_fp32_ceiling" "$B/"
  MPIRUN=mpirun; N_DEMO=30000; SIGMA_MPI=4; RANKS="1 2 4"; SWEEP=10000,30000; WL=face; BIG=""
else
  B=/opt/pnfdev/bin; MPIRUN=/usr/bin/orterun; N_DEMO=1000000; SIGMA_MPI=4; RANKS="1 2 4 8 16"
  SWEEP=100000,1000000,2000000; WL=face,dog,cube; BIG=",big"
  step "unpack .devcarry/root.tar.xz into / (existing files kept)"
  time tar -xJf .devcarry/root.tar.xz --skip-old-files -C / || echo "UNPACK FAILED"
  ldconfig
fi

if [ "${PART:-main}" = extra ]; then
  # The second call: the GPU's own ceilings (CuPy FMA chains, a PyTorch copy), a second
  # pnf_bench run for the spread, 2M points at sigma_f 8 whole and chunked, and a repeat of the
  # strong scaling (mpirun for every P).
  nvocl=$(ls /usr/local/nvidia/lib64/libnvidia-opencl.so.1 2>/dev/null)
  [ -n "$nvocl" ] && { grep -qs nvidia-opencl /etc/OpenCL/vendors/*.icd || echo "$nvocl" > /etc/OpenCL/vendors/nvidia.icd; }
  timeout 20 "$B/pnf" devices
  step "GPU ceilings"
  cat > "$W/ceil.py" <<'PY'
import cupy as cp, torch
src = r"""extern "C" __global__ void chains(float* out, int iters, float a, float b) {
  float x[8];
  for (int k = 0; k < 8; ++k) x[k] = threadIdx.x + k;
  for (int i = 0; i < iters; ++i)
    #pragma unroll
    for (int k = 0; k < 8; ++k) x[k] = fmaf(x[k], a, b);
  float s = 0; for (int k = 0; k < 8; ++k) s += x[k];
  out[blockIdx.x * blockDim.x + threadIdx.x] = s;
}"""
f = cp.RawKernel(src, "chains")
blocks, threads, iters = 132 * 64, 256, 1024
out = cp.empty(blocks * threads, cp.float32)
for _ in range(3): f((blocks,), (threads,), (out, cp.int32(iters), cp.float32(0.9999), cp.float32(1e-4)))
s, e = cp.cuda.Event(), cp.cuda.Event()
best = 0
for _ in range(5):
    s.record(); f((blocks,), (threads,), (out, cp.int32(iters), cp.float32(0.9999), cp.float32(1e-4))); e.record(); e.synchronize()
    ms = cp.cuda.get_elapsed_time(s, e); best = max(best, blocks * threads * iters * 8 * 2 / ms / 1e9)
print(f"fp32 FMA chains (CuPy): {best:.1f} TFLOP/s")
x = torch.randn(2**29, device="cuda"); y = torch.empty_like(x)
for _ in range(3): y.copy_(x)
a, b = torch.cuda.Event(enable_timing=True), torch.cuda.Event(enable_timing=True)
a.record()
for _ in range(20): y.copy_(x)
b.record(); torch.cuda.synchronize(); ms = a.elapsed_time(b) / 20
print(f"device-to-device copy (PyTorch, 2 GiB): {2 * x.numel() * 4 / ms / 1e6:.0f} GB/s read+write")
PY
  timeout 90 python3 "$W/ceil.py"
  step "GPU: pnf_bench, second run"
  timeout 120 "$B/pnf_bench" --device gpu --workloads face,dog,cube --sweep 1000000,2000000 --repeats 5 --passes 4 \
    --json "$OUT/bench_gpu_run2.json" 2>&1 | tee "$W/logs/bench_gpu_run2.txt"
  step "2M points at sigma_f 8 on the GPU: whole (--memory-budget 65536) and chunked (default 3 GiB)"
  PNF_DEVICE=gpu timeout 90 "$B/pnf" demo --points 2000000 --dir "$W/d2"
  for mb in 65536 3072; do
    timeout 90 /usr/bin/time -f "wall %e s, max rss %M KiB" "$B/pnf" filter "$W/d2/house_noisy.ply" "$W/d2/o.ply" \
      --device opencl:gpu --sigma-f 8 --iterations 4 --memory-budget $mb
  done
  step "1M demo house, strong scaling repeated"
  PNF_DEVICE=gpu timeout 60 "$B/pnf" demo --points 1000000 --dir "$W" > /dev/null
  IN=$W/house_noisy.ply
  for name in pocl ref; do
    for p in 1 2 4 8 16; do
      [ $SECONDS -lt 230 ] || break
      [ $name = pocl ] && dev=opencl:cpu it=4 || dev=reference it=2
      t0=$(date +%s.%N)
      OCL_ICD_VENDORS=libpocl.so.2 timeout 60 "$MPIRUN" --bind-to none -x OMP_NUM_THREADS=1 -x POCL_MAX_PTHREAD_COUNT=1 \
        -np $p "$B/pnf" filter "$IN" "$W/r.ply" --device $dev --sigma-f 4 --iterations $it --memory-budget 65536 \
        > "$W/logs/mpi2_${name}_$p.txt" 2>&1
      echo "MPI $name P=$p rc=$? wall $(python3 -c "print($(date +%s.%N)-$t0)") s"; grep "passes\|lists\|setup" "$W/logs/mpi2_${name}_$p.txt"
    done
  done
  tar -czf "$OUT/logs2.tgz" -C "$W" logs; ls -la "$OUT"
  exit 0
fi

step "machine"
date -u; uname -a; head -4 /etc/os-release
nvidia-smi || echo "no nvidia-smi"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem,power.limit --format=csv
grep -m1 "model name" /proc/cpuinfo; nproc; lscpu | grep -E "^(Model name|CPU\(s\)|Thread|Core|Socket|NUMA node\(|L2|L3|Flags)" | cut -c1-400
free -g; df -h /tmp | tail -1
which ld gcc python3 || true
ldd "$B/pnf" | grep "not found" && echo "MISSING LIBRARIES for pnf"

step "NVIDIA OpenCL driver"
ls /etc/OpenCL/vendors/ 2>/dev/null && cat /etc/OpenCL/vendors/*.icd
nvocl=$(find /usr/local/nvidia /usr/lib/x86_64-linux-gnu /usr/lib64 /usr/lib -maxdepth 3 -name 'libnvidia-opencl.so*' 2>/dev/null | sort | head -5)
[ -z "$nvocl" ] && nvocl=$(timeout 30 find / -name 'libnvidia-opencl.so*' -not -path '/proc/*' 2>/dev/null | sort | head -5)
ls /usr/local/nvidia/* 2>/dev/null | head -40
echo "found: $nvocl"
lib=$(echo "$nvocl" | grep -m1 'so\.1$' || echo "$nvocl" | head -1)
if [ -n "$lib" ]; then
  export LD_LIBRARY_PATH="$(dirname "$lib")${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  grep -qs nvidia-opencl /etc/OpenCL/vendors/*.icd || { mkdir -p /etc/OpenCL/vendors; echo "$lib" > /etc/OpenCL/vendors/nvidia.icd; }
  cat /etc/OpenCL/vendors/nvidia.icd 2>/dev/null
fi
step "pnf devices"
timeout 120 "$B/pnf" devices 2>&1 | tee "$W/devices.txt"
GPU=""; CPU=""
grep -qi nvidia "$W/devices.txt" && GPU=gpu
grep -qi "portable" "$W/devices.txt" && CPU=cpu
[ "$LOCAL" = 1 ] && GPU=cpu
echo "GPU selector: '${GPU}', CPU selector: '${CPU}'"

step "fp32 ceiling of the CPU"
timeout 60 "$B/pnf_fp32_ceiling"

if [ -n "$GPU" ]; then
  step "GPU: pnf_bench"
  timeout 240 "$B/pnf_bench" --device "$GPU" --workloads "$WL$BIG" --sweep "$SWEEP" --repeats 3 --passes 4 \
    --lanes 16 --json "$OUT/bench_gpu.json" 2>&1 | tee "$W/logs/bench_gpu.txt"
  nvidia-smi --query-gpu=clocks.sm,clocks.mem,temperature.gpu,power.draw --format=csv
fi

step "demo house ($N_DEMO points) and pnf filter on each device"
PNF_DEVICE=${GPU:-${CPU:-reference}} timeout 120 "$B/pnf" demo --points "$N_DEMO" --dir "$W"
IN=$W/house_noisy.ply
for dev in $GPU $CPU reference; do
  [ "$dev" = reference ] && d=reference || d=opencl:$dev
  [ "$LOCAL" = 1 ] && [ "$dev" = cpu ] && continue
  timeout 150 /usr/bin/time -f "wall %e s, max rss %M KiB" "$B/pnf" filter "$IN" "$W/out_$dev.ply" --device "$d" \
    --sigma-f 4 --iterations 4 --memory-budget 65536 2>&1 | tee "$W/logs/cli_$dev.txt"
done

# Strong scaling: one thread a rank (reference: OMP_NUM_THREADS=1; PoCL: also
# POCL_MAX_PTHREAD_COUNT=1), ranks unbound; P = 1 runs without mpirun.
scale() {  # backend device iterations limit_s
  local name=$1 dev=$2 it=$3 lim=$4
  for p in $RANKS; do
    left 380 || { echo "skip $name P=$p: out of time"; continue; }
    local flags=(filter "$IN" "$W/mpi_${name}_$p.ply" --device "$dev" --sigma-f "$SIGMA_MPI" --iterations "$it" --memory-budget 65536)
    local t0=$(date +%s.%N)
    if [ "$p" = 1 ]; then
      OMP_NUM_THREADS=1 POCL_MAX_PTHREAD_COUNT=1 timeout "$lim" "$B/pnf" "${flags[@]}" > "$W/logs/mpi_${name}_$p.txt" 2>&1
    else
      timeout "$lim" "$MPIRUN" --bind-to none -x OMP_NUM_THREADS=1 -x POCL_MAX_PTHREAD_COUNT=1 \
        -np "$p" "$B/pnf" "${flags[@]}" > "$W/logs/mpi_${name}_$p.txt" 2>&1
    fi
    local rc=$? t1=$(date +%s.%N)
    echo "MPI $name P=$p rc=$rc wall $(echo "$t1 - $t0" | bc 2>/dev/null || python3 -c "print($t1-$t0)") s"
    grep -v "^  mean radius\|^  sigma_f" "$W/logs/mpi_${name}_$p.txt"
  done
}
if [ -n "$CPU" ]; then
  step "MPI strong scaling, PoCL CPU device, 1 thread a rank"
  POCL_MAX_PTHREAD_COUNT=1 timeout 60 "$B/pnf" filter "$IN" "$W/warm.ply" --device opencl:cpu --iterations 1 >/dev/null 2>&1
  OCL_ICD_VENDORS=libpocl.so.2 scale pocl opencl:cpu 4 120
fi
step "MPI strong scaling, reference backend (double), 1 thread a rank"
scale ref reference 2 150

step "agreement across P (normals' angle to P = 1's, degrees)"
cat > "$W/angles.py" <<'PY'
import sys, numpy as np
def normals(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    head = data[:end].decode().splitlines()
    types = {"double": "<f8", "float": "<f4", "uchar": "u1", "int": "<i4", "uint": "<u4"}
    fields, n, inside = [], 0, False
    for line in head:
        w = line.split()
        if w[:2] == ["element", "vertex"]: n, inside = int(w[2]), True
        elif w[0] == "element": inside = False
        elif w[0] == "property" and inside: fields.append((w[2], types[w[1]]))
    v = np.frombuffer(data, dtype=np.dtype(fields), count=n, offset=end)
    return np.stack([v["nx"], v["ny"], v["nz"]], 1).astype(np.float64)
a = normals(sys.argv[1])
for b_path in sys.argv[2:]:
    b = normals(b_path)
    deg = np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.sum(a * b, 1)))
    print(f"{b_path.split('/')[-1]} vs {sys.argv[1].split('/')[-1]}: max {deg.max():.3g}, mean {deg.mean():.3g}, "
          f"identical bytes {open(sys.argv[1],'rb').read() == open(b_path,'rb').read()}")
PY
for name in pocl ref; do
  ls "$W"/mpi_${name}_*.ply >/dev/null 2>&1 && timeout 60 python3 "$W/angles.py" "$W/mpi_${name}_1.ply" $(ls "$W"/mpi_${name}_*.ply)
done
ls "$W"/out_*.ply >/dev/null 2>&1 && timeout 60 python3 "$W/angles.py" "$W/out_reference.ply" "$W"/out_*.ply

if [ -n "$CPU" ] && left 330; then
  step "PoCL CPU device, all threads: pnf_bench"
  timeout 120 "$B/pnf_bench" --device "$CPU" --workloads "$WL" --sweep 1000000 --repeats 3 --passes 2 \
    --json "$OUT/bench_pocl.json" 2>&1 | tee "$W/logs/bench_pocl.txt"
fi
if [ -n "$GPU" ] && [ "$LOCAL" != 1 ] && left 340; then
  step "MPI, every rank on the one GPU (OMP threads 16/P for the lists)"
  for p in 2 4 8; do
    left 380 || break
    t0=$(date +%s.%N)
    timeout 60 "$MPIRUN" --bind-to none -x OMP_NUM_THREADS=$((16 / p)) -np "$p" "$B/pnf" filter "$IN" \
      "$W/mpi_gpu_$p.ply" --device opencl:gpu --sigma-f 4 --iterations 4 --memory-budget 65536 > "$W/logs/mpi_gpu_$p.txt" 2>&1
    echo "MPI gpu P=$p rc=$? wall $(python3 -c "print($(date +%s.%N)-$t0)") s"; tail -3 "$W/logs/mpi_gpu_$p.txt"
  done
fi

step "done"
cp "$W/devices.txt" "$W/logs/" 2>/dev/null
tar -czf "$OUT/logs.tgz" -C "$W" logs
ls -la "$OUT"
