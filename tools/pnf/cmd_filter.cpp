#include <chrono>
#include <cstdio>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "launcher.hpp"
#include "pnf/filter_file_options.hpp"
#include "pnf/improve_normals_auto.hpp"
#include "pnf/options_text.hpp"
#include "pnf/point_file.hpp"
#ifdef PNF_WITH_MPI
#include "filter_mpi.hpp"
#endif

namespace pnf::cli {
namespace {

constexpr double kMiB = 1024.0 * 1024.0;

struct FilterFlags {
  std::string in, out;
  FilterParams params;
  std::string units = to_string(FilterParams{}.units);
  double radius = 0;
  // Shown in --help as the library's default, never restated.
  double memory_mib = double(MemoryPolicy{}.budget_bytes) / kMiB;
  std::size_t max_pairs = MemoryPolicy{}.max_neighbour_pairs;
  double max_seconds = FilterOptions{}.max_seconds;
  DeviceFlags device;
  bool ascii = false, quiet = false, in_place = false;
  std::string pcd_data;
  bool automatic = false;   // --auto: sigma_f, sigma_g and passes from the data
  double stop_change = -1;  // --stop-change DEG; < 0 when not given
};

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// `params` are the ones the run used: the flags' units and radius are applied to a copy. With
// --auto, `passes_kept` is what the judge kept of the passes run (params.iterations says the same).
void print_summary(const FilterFlags& f, const FilterParams& params, const FilterSummary& s, double read_s,
                   double write_s, int passes_kept = -1) {
  std::fprintf(stderr, "pnf filter: %zu points from %s (read in %.2f s)\n", s.points, f.in.c_str(), read_s);
  if (params.units == Units::radius) {
    std::fprintf(stderr, "  mean radius  %.6g (%s)\n", s.mean_radius, to_string(s.radius_source));
    std::fprintf(stderr, "  sigma_f      %.6g model units, sigma_g %.6g (radius units: %g, %g)\n", s.sigma_f, s.sigma_g,
                 params.sigma_f, params.sigma_g);
  } else {
    std::fprintf(stderr, "  sigma_f      %.6g model units, sigma_g %.6g (absolute units)\n", s.sigma_f, s.sigma_g);
  }
  std::fprintf(stderr, "  neighbours   mean %.1f, max %zu per point; %zu pairs per pass", s.neighbours_mean,
               s.neighbours_max, s.neighbour_pairs);
  // The lists are cut into chunks only where passes run (0 chunks where none ran).
  if (s.chunks > 0) std::fprintf(stderr, " in %zu chunk%s", s.chunks, s.chunks == 1 ? "" : "s");
  std::fprintf(stderr, "\n");
  std::fprintf(stderr, "  device       %s [%s]\n", s.device.c_str(), s.backend.c_str());
  std::fprintf(stderr, "  lists        %.3f s, upload %.3f s\n", s.neighbour_seconds, s.upload_seconds);
  if (s.pass_seconds.empty()) {
    std::fprintf(stderr, "  passes       none\n");  // as the distributed summary says it
  } else {
    std::fprintf(stderr, "  passes       %zu:", s.pass_seconds.size());
    for (double t : s.pass_seconds) std::fprintf(stderr, " %.3f", t);
    std::fprintf(stderr, " s\n");
  }
  if (passes_kept >= 0) {
    std::fprintf(stderr, "  judged       %d of %d passes kept (%s)", passes_kept, s.passes_run,
                 passes_kept == 0 ? "the input normals returned" : "judged the best, above");
    if (!s.mean_change_deg.empty()) {
      std::fprintf(stderr, "; mean change per pass:");
      for (double d : s.mean_change_deg) std::fprintf(stderr, " %.3g", d);
      std::fprintf(stderr, " deg");
    }
    std::fprintf(stderr, "\n");
  } else if (params.stop_change_deg > 0) {
    std::fprintf(stderr,
                 "  stop rule    %d of at most %d passes run (%s below %g deg); mean change per pass:", s.passes_run,
                 params.iterations, s.passes_run < params.iterations ? "stopped when the change fell" : "never fell",
                 params.stop_change_deg);
    for (double d : s.mean_change_deg) std::fprintf(stderr, " %.3g", d);
    std::fprintf(stderr, " deg\n");
  }
  std::fprintf(stderr, "  wrote        %s (%.2f s)\n", f.out.c_str(), write_s);
}

// The one value both runs take, built once from the flags.
FilterFileOptions file_options(const FilterFlags& flags) {
  FilterFileOptions o;
  o.params = flags.params;
  o.params.units = parse_units(flags.units);
  o.params.mean_radius = flags.radius;
  o.options = flags.device.options();
  o.options.memory.budget_bytes = static_cast<std::size_t>(flags.memory_mib * kMiB);
  o.options.memory.max_neighbour_pairs = flags.max_pairs;
  o.options.max_seconds = flags.max_seconds;
  o.write = write_options(flags.ascii, flags.pcd_data);
  o.automatic = flags.automatic;
  o.stop_change_deg = flags.stop_change;
  o.in_place = flags.in_place;
  return o;
}

int run_filter(const FilterFlags& flags) {
  const FilterFileOptions o = file_options(flags);
#ifdef PNF_WITH_MPI
  if (launched_as_many()) return run_filter_distributed(flags.in, flags.out, o, flags.quiet);
#endif
  Stage stage = Stage::reading;
  return guarded(stage, [&] {
    FilterParams params = o.run_params();
    if (!o.automatic) params.validate();
    o.options.validate();
    check_output_extension(flags.out);
    check_write_options(flags.out, o.write);
    check_not_overwriting_input(flags.in, flags.out, o.in_place);
    auto t = std::chrono::steady_clock::now();
    PointFile file = read_point_file(flags.in);
    const double read_s = seconds_since(t);
    if (!file.has_normals()) {
      throw Error(ErrorCode::invalid_input, flags.in + ": the vertices have no normals (nx ny nz); run `pnf estimate " +
                                                flags.in + " OUT` first");
    }
    stage = Stage::running;
    const PointCloud cloud = cloud_to_filter(file, flags.in, o);
    NormalFilter filter(o.options);
    FilterResult result;
    int passes_kept = -1;
    if (o.automatic) {
      const auto t_auto = std::chrono::steady_clock::now();
      // The rule's choice, then its passes, each judged against the surface fitted to the
      // positions; an explicit --stop-change (0 included: off) wins over the rule's.
      result.normals.resize(cloud.size());
      AutoRun run = improve_normals_auto(cloud, MutableVec3ArrayView(result.normals), filter, progress_bar(flags.quiet),
                                         o.stop_change_deg);
      params = run.choice.params;
      passes_kept = run.passes_kept;
      result.summary = run.summary;
      // The run was handed the estimate's mean radius; say where that came from, not "given".
      result.summary.radius_source = run.choice.estimate.radius_source;
      if (!flags.quiet) print_auto(run.choice, seconds_since(t_auto));
    } else {
      result = filter.run(cloud, params, progress_bar(flags.quiet));
    }
    stage = Stage::writing;
    t = std::chrono::steady_clock::now();
    file.set_normals(result.normals);
    write_point_file(flags.out, file, o.write);
    if (!flags.quiet) {
      print_summary(flags, params, result.summary, read_s, seconds_since(t), passes_kept);
      print_rows_not_filtered(file.without_normals(), file.size() - file.valid_count() - file.without_normals(),
                              flags.out);
    }
    return int(kOk);
  });
}

}  // namespace

Command add_filter_command(CLI::App& parent) {
  auto flags = std::make_shared<FilterFlags>();
  CLI::App* app = parent.add_subcommand("filter", "Improve the normals of a point file (Jones, Durand, Zwicker 2004)");
  app->add_option("IN", flags->in, "input point file with normals (.ply, .pcd, .xyz, .xyzn, .pwn)")->required();
  app->add_option("OUT", flags->out, "output file; the format follows its extension")->required();
  // Defaults shown in the help are the library's (FilterParams{}, MemoryPolicy{}), captured from
  // the flags' initial values, never written here.
  CLI::Option* sigma_f =
      app->add_option("--sigma-f", flags->params.sigma_f, "spatial width; neighbours reach 2 sigma_f")
          ->capture_default_str();
  CLI::Option* sigma_g =
      app->add_option("--sigma-g", flags->params.sigma_g, "feature width: distance to a neighbour's plane")
          ->capture_default_str();
  CLI::Option* iterations = app->add_option("--iterations", flags->params.iterations,
                                            "number of passes, or the most passes with --stop-change")
                                ->capture_default_str();
  CLI::Option* units =
      app->add_option("--units", flags->units, "radius: sigmas in mean surfel radii; absolute: model units")
          ->check(CLI::IsMember({"radius", "absolute"}))
          ->capture_default_str();
  CLI::Option* radius =
      app->add_option("--radius", flags->radius,
                      "mean surfel radius in model units, > 0 (default: mean of the radius property, else "
                      "estimated)")
          ->check(finite_positive());
  app->add_flag("--auto", flags->automatic,
                "estimate spacing, position and normal noise from the data and choose sigma_f, sigma_g and the passes "
                "(docs/auto.md); without it the paper's settings apply")
      ->excludes(sigma_f, sigma_g, iterations, units, radius);
  app->add_option("--stop-change", flags->stop_change,
                  "end the passes once the mean change of the normals falls below DEG degrees (default: off; "
                  "--auto sets 0.01; 0 turns it off)")
      ->check(finite_non_negative());
  app->add_option("--memory-budget", flags->memory_mib,
                  "MiB of neighbour lists kept at once; larger clouds run in chunks")
      ->check(finite_positive())
      ->capture_default_str();
  app->add_option("--max-pairs", flags->max_pairs,
                  "refuse runs whose neighbour lists would pass this many pairs (estimated before they are built)")
      ->check(finite_positive())
      ->capture_default_str();
  app->add_option("--max-seconds", flags->max_seconds,
                  "refuse runs estimated (by timing this device on a sample) to take longer; 0: no limit")
      ->check(finite_non_negative())
      ->capture_default_str();
  flags->device.add_to(*app);
  app->add_flag("--ascii", flags->ascii, "write ascii PLY (default: binary little endian)");
  add_pcd_data_option(*app, flags->pcd_data);
  app->add_flag("--in-place", flags->in_place, "allow OUT to be IN (the file is replaced atomically)");
  app->add_flag("-q,--quiet", flags->quiet, "print nothing but errors");
  return {app, [flags] { return run_filter(*flags); }};
}

}  // namespace pnf::cli
