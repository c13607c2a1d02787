#!/usr/bin/env bash
# Builds the whole project with clang, AddressSanitizer and UndefinedBehaviorSanitizer into
# ./build-asan, with the libFuzzer targets, and runs every test there: the GoogleTest suite, the
# consumer package test and each fuzzer for PNF_FUZZ_SECONDS (default 20).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DPNF_SANITIZE=ON -DPNF_BUILD_FUZZERS=ON -DPNF_BUILD_BENCH=OFF \
  -DPNF_FUZZ_SECONDS="${PNF_FUZZ_SECONDS:-20}" >/dev/null
cmake --build build-asan -j"$(nproc)"
# The OpenCL ICD loader and PoCL keep allocations until exit; their leaks are not ours.
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
# intercept_tls_get_addr=0: up to LLVM 16 (Debian 12 has 14) the runtime's __tls_get_addr
# interceptor takes a dynamic TLS block that happens to start 16 bytes past a page boundary for a
# pre-2.25 glibc header and hands LSan's tracer a bogus range, which kills it at exit ("Tracer
# caught signal 11") after a passing test: PnfFilter.RoundedRankOneJacobianKeepsTheNormalInFloat
# on some machines, every run (Mudlet/Mudlet#9930 has the mechanism). Leaks are still checked;
# only pointers kept solely in dlopen'd libraries' thread-locals are no longer roots.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:intercept_tls_get_addr=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd build-asan
ctest --output-on-failure -j"$(nproc)" --timeout 900
