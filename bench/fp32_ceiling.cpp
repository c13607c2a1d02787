// pnf_fp32_ceiling: the host CPU's fp32 FMA throughput, the ceiling pnf_bench's GFLOP/s are set
// against (docs/performance.md). Twelve independent FMA chains held in registers, in the widest
// vectors the CPU has (AVX-512, else AVX2 + FMA), on 1 thread and on every hardware thread; prints
// the best of five runs. Twelve chains cover the FMA latency (4 cycles) times two FMA ports, so a
// lower figure than the vector width x 2 ports x clock means the machine, not the loop.
#include <immintrin.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

namespace {

constexpr int kChains = 12;
constexpr long kIterations = 100'000'000;

float sum_of(const float* lanes, int count) {
  float sum = 0;
  for (int i = 0; i < count; ++i) sum += lanes[i];
  return sum;
}

__attribute__((target("avx512f"))) float chains_avx512(long iterations) {
  __m512 acc[kChains];
  const __m512 scale = _mm512_set1_ps(0.999999f), offset = _mm512_set1_ps(1e-7f);
  for (int i = 0; i < kChains; ++i) acc[i] = _mm512_set1_ps(1.0f + i);
  for (long k = 0; k < iterations; ++k) {
#pragma GCC unroll 12
    for (int i = 0; i < kChains; ++i) acc[i] = _mm512_fmadd_ps(acc[i], scale, offset);
  }
  for (int i = 1; i < kChains; ++i) acc[0] = _mm512_add_ps(acc[0], acc[i]);
  alignas(64) float lanes[16];
  _mm512_store_ps(lanes, acc[0]);
  return sum_of(lanes, 16);
}

__attribute__((target("avx2,fma"))) float chains_avx2(long iterations) {
  __m256 acc[kChains];
  const __m256 scale = _mm256_set1_ps(0.999999f), offset = _mm256_set1_ps(1e-7f);
  for (int i = 0; i < kChains; ++i) acc[i] = _mm256_set1_ps(1.0f + i);
  for (long k = 0; k < iterations; ++k) {
#pragma GCC unroll 12
    for (int i = 0; i < kChains; ++i) acc[i] = _mm256_fmadd_ps(acc[i], scale, offset);
  }
  for (int i = 1; i < kChains; ++i) acc[0] = _mm256_add_ps(acc[0], acc[i]);
  alignas(32) float lanes[8];
  _mm256_store_ps(lanes, acc[0]);
  return sum_of(lanes, 8);
}

double best_gflops(int threads, int lanes, float (*chains)(long)) {
  double best = 0;
  for (int run = 0; run < 5; ++run) {
    std::vector<float> sink(threads);
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::thread> workers;
    for (int t = 0; t < threads; ++t) workers.emplace_back([&, t] { sink[t] = chains(kIterations); });
    for (auto& worker : workers) worker.join();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // The sums are printed nowhere, but reading them keeps the loops from being dropped.
    if (sink[0] == 0.0f) std::puts("");
    best = std::max(best, threads * double(kIterations) * kChains * lanes * 2 / seconds / 1e9);
  }
  return best;
}

}  // namespace

int main() {
  __builtin_cpu_init();
  const bool avx512 = __builtin_cpu_supports("avx512f");
  if (!avx512 && !(__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))) {
    std::fprintf(stderr, "pnf_fp32_ceiling: this CPU has neither AVX-512F nor AVX2 with FMA\n");
    return 1;
  }
  const int lanes = avx512 ? 16 : 8;
  auto* chains = avx512 ? chains_avx512 : chains_avx2;
  const int threads = int(std::max(1u, std::thread::hardware_concurrency()));
  std::printf("%s, %d fp32 lanes, %d chains of FMAs, best of 5 runs\n", avx512 ? "AVX-512" : "AVX2", lanes, kChains);
  std::printf("1 thread:   %.1f GFLOP/s\n", best_gflops(1, lanes, chains));
  std::printf("%d threads: %.1f GFLOP/s\n", threads, best_gflops(threads, lanes, chains));
}
