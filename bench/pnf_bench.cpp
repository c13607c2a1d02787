// pnf_bench: times the filter per workload and backend, prints a table and writes JSON.
//
// Each workload runs in its own child process so that its peak host memory (ru_maxrss) is its
// own. Per workload and variant: one warm-up pass (program build and first touch excluded from
// the medians; its list build, in memory never touched before as in a fresh `pnf filter`, is
// reported as first_s), then `--repeats` full runs; figures are medians with the min..max spread
// of the per-run medians.
#include <sys/resource.h>
#include <sys/utsname.h>
#include <sys/wait.h>
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <map>
#include <sstream>

#include "bench_workloads.hpp"
#include "eval_clouds.hpp"
#include "filter_engine.hpp"
#include "opencl_backend.hpp"
#include "pnf/normal_filter.hpp"
#include "reference_backend.hpp"

namespace {

using namespace pnf;
using namespace pnf::bench;

struct Row {
  std::string workload, source, variant, device;
  std::size_t points = 0, neighbours_max = 0, pairs = 0, chunks = 0, passes = 0;
  double sigma_f = 0, sigma_g = 0, neighbours_mean = 0;
  double list_s = 0, list_first_s = 0, upload_s = 0, pass_s = 0, pass_min_s = 0, pass_max_s = 0, kernel_s = 0;
  double peak_host_mib = 0, device_mib = 0;
  std::size_t degenerate_kept = 0;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

double peak_host_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

// One way to run the filter: a name and a backend (built once, reused by every run).
struct Variant {
  std::string name;
  FilterOptions options;  // backend kind and device, for the engine and the summary
  std::unique_ptr<detail::FilterBackend> backend;
  ProgressCallback progress = {};  // set: the passes run in slices (filter_engine.cpp, run_slices)
};

// `first` is the warm-up run: its lists were written to memory never touched before, as in a
// fresh `pnf filter` process; the timed runs reuse the warm buffers.
Row to_row(const Workload& w, const std::string& variant, int passes, const FilterSummary& first,
           const std::vector<FilterSummary>& runs) {
  std::vector<double> lists, uploads, run_medians, all_passes, kernels;
  for (const FilterSummary& s : runs) {
    lists.push_back(s.neighbour_seconds);
    uploads.push_back(s.upload_seconds);
    run_medians.push_back(median(s.pass_seconds));
    all_passes.insert(all_passes.end(), s.pass_seconds.begin(), s.pass_seconds.end());
    kernels.push_back(median(s.kernel_seconds));
  }
  const FilterSummary& s = runs.back();
  Row row;
  row.workload = w.name;
  row.source = w.source;
  row.variant = variant;
  row.device = s.device;
  row.points = s.points;
  row.sigma_f = s.sigma_f;
  row.sigma_g = s.sigma_g;
  row.neighbours_mean = s.neighbours_mean;
  row.neighbours_max = s.neighbours_max;
  row.pairs = s.neighbour_pairs;
  row.chunks = s.chunks;
  row.passes = std::size_t(passes);
  row.degenerate_kept = s.degenerate_kept;
  row.list_s = median(lists);
  row.list_first_s = first.neighbour_seconds;
  row.upload_s = median(uploads);
  row.pass_s = median(all_passes);
  row.pass_min_s = *std::min_element(run_medians.begin(), run_medians.end());
  row.pass_max_s = *std::max_element(run_medians.begin(), run_medians.end());
  row.kernel_s = median(kernels);
  row.device_mib = double(s.device_bytes) / (1024.0 * 1024.0);
  row.peak_host_mib = peak_host_mib();
  return row;
}

// Each variant: one warm-up pass (program build and first touch; see to_row); then `repeats`
// rounds, each running every variant once in turn (A B C A B C ...), so that a change in the
// machine's load falls on all variants alike and their ratios stay comparable.
std::vector<Row> measure(const Workload& w, std::vector<Variant>& variants, int passes, int repeats) {
  FilterParams params = w.params;
  params.iterations = 1;
  std::vector<Vec3> normals(w.cloud.size());
  std::vector<FilterSummary> warm_ups;
  for (Variant& v : variants)
    warm_ups.push_back(detail::run_filter(*v.backend, v.options, w.cloud, normals, params, v.progress));
  params.iterations = passes;
  std::vector<std::vector<FilterSummary>> runs(variants.size());
  for (int r = 0; r < repeats; ++r) {
    for (std::size_t i = 0; i < variants.size(); ++i) {
      const Variant& v = variants[i];
      runs[i].push_back(detail::run_filter(*v.backend, v.options, w.cloud, normals, params, v.progress));
    }
  }
  std::vector<Row> rows;
  for (std::size_t i = 0; i < variants.size(); ++i)
    rows.push_back(to_row(w, variants[i].name, passes, warm_ups[i], runs[i]));
  return rows;
}

std::string json(const Row& r) {
  std::ostringstream o;
  const double mpairs = r.pass_s > 0 ? double(r.pairs) / r.pass_s / 1e6 : 0;
  o << "{\"workload\":\"" << r.workload << "\",\"source\":\"" << r.source << "\",\"variant\":\"" << r.variant
    << "\",\"device\":\"" << r.device << "\",\"points\":" << r.points << ",\"sigma_f\":" << r.sigma_f
    << ",\"sigma_g\":" << r.sigma_g << ",\"neighbours_mean\":" << r.neighbours_mean
    << ",\"neighbours_max\":" << r.neighbours_max << ",\"pairs_per_pass\":" << r.pairs << ",\"chunks\":" << r.chunks
    << ",\"passes\":" << r.passes << ",\"list_build_s\":" << r.list_s << ",\"list_build_first_s\":" << r.list_first_s
    << ",\"upload_s\":" << r.upload_s << ",\"pass_s\":" << r.pass_s << ",\"pass_s_min\":" << r.pass_min_s
    << ",\"pass_s_max\":" << r.pass_max_s << ",\"kernel_s\":" << r.kernel_s
    << ",\"degenerate_kept\":" << r.degenerate_kept << ",\"mpairs_per_s\":" << mpairs
    << ",\"gflops\":" << mpairs * kFlopsPerPair / 1000 << ",\"peak_host_mib\":" << r.peak_host_mib
    << ",\"device_mib\":" << r.device_mib << "}";
  return o.str();
}

// Runs `body` in a child process and returns the lines it wrote to the pipe.
std::vector<std::string> in_child(const std::function<std::vector<std::string>()>& body) {
  int fds[2];
  if (pipe(fds) != 0) return {};
  std::fflush(stdout);
  std::fflush(stderr);
  pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    int code = 0;
    std::string out;
    try {
      for (const std::string& line : body()) out += line + "\n";
    } catch (const std::exception& e) {
      std::fprintf(stderr, "pnf_bench: %s\n", e.what());
      code = 1;
    }
    ssize_t written = write(fds[1], out.data(), out.size());
    (void)written;
    close(fds[1]);
    _exit(code);
  }
  close(fds[1]);
  std::string text;
  char buf[4096];
  ssize_t n;
  while ((n = read(fds[0], buf, sizeof buf)) > 0) text.append(buf, std::size_t(n));
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string field(const std::string& json, const std::string& key) {
  auto at = json.find("\"" + key + "\":");
  if (at == std::string::npos) return "";
  at += key.size() + 3;
  if (json[at] == '"') return json.substr(at + 1, json.find('"', at + 1) - at - 1);
  return json.substr(at, json.find_first_of(",}", at) - at);
}

double num(const std::string& json, const std::string& key) {
  std::string v = field(json, key);
  return v.empty() ? 0 : std::stod(v);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pnf_bench: time the normal filter per workload and backend; prints a table, writes JSON"};
  std::vector<std::string> workloads = {"face", "dog", "bunny"};
  std::vector<std::size_t> sweep;
  std::string json_path = "pnf_bench.json", device, data_dir = PNF_SHARED_DATA_DIR;
  int repeats = 3, passes = 4;
  bool reference = false, sliced = false;
  std::vector<int> lanes;
  std::vector<std::string> kernel_options;
  app.add_option("--workloads", workloads, "face, dog, bunny (default these three), cube, big, stray")->delimiter(',');
  app.add_option("--sweep", sweep, "also run the synthetic house at these sizes, e.g. 10000,100000,1000000")
      ->delimiter(',');
  app.add_option("--repeats", repeats, "timed runs per workload (default 3)")->check(CLI::PositiveNumber);
  app.add_option("--passes", passes, "passes per run (default 4)")->check(CLI::PositiveNumber);
  app.add_option("--lanes", lanes, "also time these kernel lane counts, e.g. 1,4,8,16 (variants opencl-L<n>)")
      ->delimiter(',');
  app.add_option("--kernel-options", kernel_options,
                 "also time the kernel built with these extra OpenCL build options, ';'-separated, e.g. "
                 "'-DPNF_WEIGHT_CUT_EXPONENT=-1e30;-cl-denorms-are-zero' (variants 'opencl <options>')")
      ->delimiter(';');
  app.add_flag("--sliced", sliced,
               "also time the OpenCL passes run with a progress callback, in slices of about 0.2 s each waited "
               "for (variant opencl-sliced: what the CLI runs)");
  app.add_flag("--reference", reference, "also time the CPU reference on 1 thread and on all threads (slow)");
  app.add_option("--device", device, "OpenCL device selector (default $PNF_DEVICE)");
  app.add_option("--json", json_path, "where to write the results (default pnf_bench.json)");
  app.add_option("--data", data_dir, "the team's shared data folder (for bunny)");
  CLI11_PARSE(app, argc, argv);
  for (std::size_t n : sweep) workloads.push_back("sweep-" + std::to_string(n));

  std::vector<std::string> rows;
  for (const std::string& name : workloads) {
    std::vector<std::string> lines = in_child([&] {
      std::vector<std::string> out;
      Workload w = make_workload(name, data_dir);
      if (w.name.empty()) {
        std::fprintf(stderr, "pnf_bench: skipping %s (no data at %s)\n", name.c_str(), data_dir.c_str());
        return out;
      }
      std::fprintf(stderr, "pnf_bench: %s (%zu points)...\n", name.c_str(), w.cloud.size());
      // Kernel variants go through the internal backend factory: lane width and build options
      // are not part of the public API.
      FilterOptions opencl;
      opencl.device = Device::parse(device).resolved();
      const std::string selector = opencl.device.selector;
      std::vector<Variant> variants;
      variants.push_back({"opencl", opencl, detail::make_opencl_backend(selector, 0)});
      if (sliced) {
        variants.push_back({"opencl-sliced", opencl, detail::make_opencl_backend(selector, 0),
                            [](const PassProgress&) { return true; }});
      }
      for (int l : lanes) {
        variants.push_back({"opencl-L" + std::to_string(l), opencl, detail::make_opencl_backend(selector, l)});
      }
      for (const std::string& k : kernel_options) {
        variants.push_back({"opencl " + k, opencl, detail::make_opencl_backend(selector, 0, k)});
      }
      for (const Row& row : measure(w, variants, passes, repeats)) out.push_back(json(row));
      variants.clear();
      if (reference) {
        FilterOptions one;
        one.device = Device::reference();
        std::vector<Variant> single;
        single.push_back({"reference-1t", one, detail::make_reference_backend(1)});
        out.push_back(json(measure(w, single, 1, 1)[0]));
        single.clear();
        single.push_back({"reference-all", one, detail::make_reference_backend(0)});
        out.push_back(json(measure(w, single, 1, 1)[0]));
      }
      return out;
    });
    rows.insert(rows.end(), lines.begin(), lines.end());
  }

  std::printf("%-12s %-13s %8s %9s %7s %5s %8s %8s %8s %9s %15s %8s %7s %9s %9s\n", "workload", "variant", "points",
              "sigma_f", "nbr", "max", "lists_s", "first_s", "upload_s", "pass_s", "spread", "Mpair/s", "GFLOP/s",
              "host_MiB", "dev_MiB");
  std::map<std::string, double> opencl_pass;
  for (const std::string& r : rows) {
    if (field(r, "variant") == "opencl") opencl_pass[field(r, "workload")] = num(r, "pass_s");
    std::printf("%-12s %-13s %8.0f %9.4g %7.1f %5.0f %8.3f %8.3f %8.3f %9.4f %7.4f..%-7.4f %8.1f %7.2f %9.0f %9.1f\n",
                field(r, "workload").c_str(), field(r, "variant").c_str(), num(r, "points"), num(r, "sigma_f"),
                num(r, "neighbours_mean"), num(r, "neighbours_max"), num(r, "list_build_s"),
                num(r, "list_build_first_s"), num(r, "upload_s"), num(r, "pass_s"), num(r, "pass_s_min"),
                num(r, "pass_s_max"), num(r, "mpairs_per_s"), num(r, "gflops"), num(r, "peak_host_mib"),
                num(r, "device_mib"));
  }
  std::printf("\nratios (same run): neighbour lists / one OpenCL pass; reference pass / OpenCL pass\n");
  for (const std::string& r : rows) {
    const std::string w = field(r, "workload"), v = field(r, "variant");
    if (v == "opencl")
      std::printf("  %-12s lists/pass %.2f\n", w.c_str(), num(r, "list_build_s") / num(r, "pass_s"));
    else if (opencl_pass[w] > 0)
      std::printf("  %-12s %s / opencl %.2f\n", w.c_str(), v.c_str(), num(r, "pass_s") / opencl_pass[w]);
  }
  if (!rows.empty()) std::printf("device: %s\n", field(rows[0], "device").c_str());

  utsname host{};
  uname(&host);
  char date[32];
  std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  std::ofstream out(json_path);
  out << "{\"date\":\"" << date << "\",\"host\":\"" << host.nodename << " " << host.machine
      << "\",\"cpus\":" << sysconf(_SC_NPROCESSORS_ONLN) << ",\"commit\":\""
      << pnf::eval::command_output("git -C '" PNF_SOURCE_DIR "' rev-parse --short HEAD 2>/dev/null")
      << "\",\"flops_per_pair\":" << kFlopsPerPair << ",\"repeats\":" << repeats << ",\"results\":[\n";
  for (std::size_t i = 0; i < rows.size(); ++i) out << "  " << rows[i] << (i + 1 < rows.size() ? ",\n" : "\n");
  out << "]}\n";
  std::printf("wrote %s\n", json_path.c_str());
  return rows.empty() ? 1 : 0;
}
