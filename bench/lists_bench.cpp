// pnf_lists_bench: times the neighbour-list build (count pass, fill pass) of a bench workload
// for several SpatialIndex::ListTuning variants, interleaved (A B C A B C ...) so that the
// machine's load falls on all alike; prints per variant the median and min..max of each pass,
// the ratio to the first variant, and the candidates scanned per neighbour. Also checks that
// every variant gives the same lists as the first, and reports the lists' runs of consecutive ids
// (issue 13, item 3).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <numeric>

#include "bench_workloads.hpp"
#include "filter_engine.hpp"
#include "spatial/spatial_index.hpp"

namespace {

using namespace pnf;
using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

struct Variant {
  std::string name;
  detail::SpatialIndex::ListTuning tuning;
  bool keep = false;  // the count keeps the blocks' candidates for the fill
  std::vector<double> count_s, fill_s;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pnf_lists_bench: time the neighbour-list build per variant, interleaved"};
  std::string workload = "dog";
  int repeats = 5;
  std::size_t chunk = 0;
  std::vector<std::string> names = {"base", "wide"};
  app.add_option("--workload", workload, "a pnf_bench workload (default dog)");
  app.add_option("--repeats", repeats, "rounds (default 5)");
  app.add_option("--variants", names,
                 "base (plain scans, blocks 1 radius), wide (AVX-512/AVX2 scans), wide-half, wide-1.5 "
                 "(block extent 0.5, 1.5 radii), avx512 (explicit AVX-512 count and compaction), avx512-half, avx2 "
                 "(explicit AVX2 count and compaction), keep (explicit AVX-512, else AVX2, the count keeps the "
                 "blocks' candidates for the fill: what pnf runs)")
      ->delimiter(',');
  app.add_option("--chunk", chunk,
                 "fill in chunks of this many points into one reused buffer, as a chunked run refills its lists "
                 "each pass (default 0: the whole cloud at once)");
  CLI11_PARSE(app, argc, argv);

  bench::Workload w = bench::make_workload(workload, "");
  // The cloud as the engine prepares it (Morton curve, centred on the bounding box) and the
  // reach of its lists, as the filter resolves them.
  const detail::PreparedCloud prepared = detail::prepare_cloud(w.cloud, w.params, w.cloud.size());
  detail::SpatialIndex& search = *prepared.search;
  const double reach = prepared.plan.reach;
  const std::size_t n = w.cloud.size();
  const std::vector<std::uint32_t> all_counts = search.count_within(reach);
  const double neighbours_mean = double(std::accumulate(all_counts.begin(), all_counts.end(), std::size_t(0))) /
                                 double(std::max<std::size_t>(n, 1));

  std::vector<Variant> variants;
  for (const std::string& name : names) {
    Variant v;
    v.name = name;
    v.tuning.wide_scan = name != "base";
    v.tuning.avx512_scan = name.rfind("avx512", 0) == 0;
    v.tuning.avx2_scan = name == "avx2";
    if (name == "avx512-half") v.tuning.block_extent_in_radii = 0.5;
    v.keep = name == "keep";
    if (v.keep) v.tuning.avx512_scan = v.tuning.avx2_scan = true;
    if (name == "wide-half") v.tuning.block_extent_in_radii = 0.5;
    if (name == "wide-1.5") v.tuning.block_extent_in_radii = 1.5;
    variants.push_back(v);
  }
  std::fprintf(stderr, "%s: %zu points, reach %.4g, %.1f neighbours a point\n", workload.c_str(), n, reach,
               neighbours_mean);
  std::vector<std::uint32_t> first_indices;
  std::vector<std::uint32_t> counts, indices;
  std::vector<std::uint64_t> offsets;
  for (int r = -1; r < repeats; ++r) {  // round -1: warm-up, checked, not timed
    for (Variant& v : variants) {
      search.set_list_tuning(v.tuning);
      auto t = Clock::now();
      detail::BlockCandidates candidates;
      counts = search.count_within(reach, 0, n, {}, v.keep ? &candidates : nullptr);
      const double count_s = std::chrono::duration<double>(Clock::now() - t).count();
      // Into storage allocated and touched once (round -1), as the device buffer is reused by
      // a run's passes: the fill's own cost, without the first touch of 1.3 GB of pages. With
      // --chunk, chunk by chunk into one buffer, as a chunked run refills.
      const std::size_t step = chunk > 0 ? std::min(chunk, n) : n;
      std::size_t largest = 0;
      for (std::size_t at = 0; at < n; at += step) {
        largest = std::max(
            largest, std::accumulate(counts.begin() + at, counts.begin() + std::min(n, at + step), std::size_t(0)));
      }
      offsets.resize(step + 1);
      indices.resize(largest);
      std::uint64_t checksum = 0;
      t = Clock::now();
      for (std::size_t at = 0; at < n; at += step) {
        const std::size_t m = std::min(step, n - at);
        search.fill_lists(reach, at, m, counts, offsets.data(), indices.data(), {}, v.keep ? &candidates : nullptr);
        if (chunk > 0 && r < 0)
          checksum += std::accumulate(indices.begin(), indices.begin() + offsets[m], std::uint64_t(0));
      }
      const double fill_s = std::chrono::duration<double>(Clock::now() - t).count();
      if (chunk > 0) indices.assign(1, std::uint32_t(checksum));  // compared across variants below
      if (r < 0 && v.keep) {
        std::fprintf(stderr, "%s: %s candidates kept, %.1f MB\n", v.name.c_str(),
                     candidates.covers(reach, 0, n) ? "all" : "no", double(candidates.bytes()) / 1e6);
      }
      if (r < 0) {
        if (first_indices.empty()) {
          first_indices = indices;
        } else if (indices != first_indices) {
          std::fprintf(stderr, "pnf_lists_bench: variant %s gives different lists\n", v.name.c_str());
          return 1;
        }
        continue;
      }
      v.count_s.push_back(count_s);
      v.fill_s.push_back(fill_s);
    }
  }
  std::printf("%-10s %10s %17s %10s %17s %10s %8s\n", "variant", "count_s", "spread", "fill_s", "spread", "total_s",
              "ratio");
  double base_total = 0;
  for (const Variant& v : variants) {
    std::vector<double> total(v.count_s.size());
    for (std::size_t i = 0; i < total.size(); ++i) total[i] = v.count_s[i] + v.fill_s[i];
    const double t = median(total);
    if (base_total == 0) base_total = t;
    std::printf("%-10s %10.3f %8.3f..%-8.3f %10.3f %8.3f..%-8.3f %10.3f %8.2f  (total %.3f..%.3f)\n", v.name.c_str(),
                median(v.count_s), *std::min_element(v.count_s.begin(), v.count_s.end()),
                *std::max_element(v.count_s.begin(), v.count_s.end()), median(v.fill_s),
                *std::min_element(v.fill_s.begin(), v.fill_s.end()),
                *std::max_element(v.fill_s.begin(), v.fill_s.end()), t, base_total / t,
                *std::min_element(total.begin(), total.end()), *std::max_element(total.begin(), total.end()));
  }

  if (chunk > 0) return 0;  // the whole lists (below) may not fit
  // Runs of consecutive ids in the lists (item 3's plan): a run is a maximal i, i+1, ... i+m.
  search.set_list_tuning({});
  const detail::CsrLists lists = search.lists_within(reach, 0, n, counts);
  std::size_t runs = 0;
  for (std::size_t p = 0; p < n; ++p) {
    for (std::uint64_t k = lists.offsets[p]; k < lists.offsets[p + 1]; ++k) {
      runs += k == lists.offsets[p] || lists.indices[k] != lists.indices[k - 1] + 1;
    }
  }
  const double pairs = double(lists.indices.size());
  for (const double extent : {0.5, 1.0, 1.5}) {
    detail::SpatialIndex::ListTuning tuning;
    tuning.block_extent_in_radii = extent;
    search.set_list_tuning(tuning);
    const auto t = Clock::now();
    const double scanned = double(search.candidates_scanned(reach, 0, n));
    std::printf(
        "blocks %.1f radii across: %.2f candidates scanned per neighbour; the searches alone (FLANN, sort, "
        "gather) %.3f s\n",
        extent, scanned / double(lists.indices.size()), std::chrono::duration<double>(Clock::now() - t).count());
  }
  std::printf("lists: %.0f pairs, %.1f per point; runs of consecutive ids: %.1f per list, mean length %.2f\n", pairs,
              pairs / double(n), double(runs) / double(n), pairs / double(runs));
  return 0;
}
